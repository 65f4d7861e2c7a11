// The viewport estimates of the cap triangulator (see chain_triangulator.hpp):
// where an edge comes near the viewport, and how much of it a triangle or a
// fan covers, in double.  The steps choose by these; a wrong estimate costs
// fragments, never a count.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "chain_triangulator.hpp"

namespace nearcap::gl::chain {

namespace {

// Does p + t d, t in [0, t_end] (t_end infinite for a ray), meet the NDC box
// |x| <= bx, |y| <= by?  (Liang-Barsky.)
bool meets_box(double px, double py, double dx, double dy, double t_end, double bx, double by) {
  double t0 = 0, t1 = t_end;
  // Each side: f(t) = f0 + t df >= 0 inside.
  const double f0[4] = {bx - px, bx + px, by - py, by + py}, df[4] = {-dx, dx, -dy, dy};
  for (int k = 0; k < 4; ++k) {
    if (df[k] == 0) {
      if (f0[k] < 0) return false;
    } else {
      const double t = -f0[k] / df[k];
      if (df[k] > 0)
        t0 = std::max(t0, t);
      else
        t1 = std::min(t1, t);
      if (t0 > t1) return false;
    }
  }
  return true;
}

// Does the clip-space edge p -> q come into the NDC box?  The edge is the
// arc of positive combinations (1 - t) p + t q, as the clipper interpolates
// it; only its part with w > 0 is ever drawn.  A part running out to w = 0
// leaves along the direction (x, y) of its crossing there, so it is a ray.
bool hemisphere_edge_meets_box(const Vec4f& p, const Vec4f& q, double bx, double by) {
  if (p.w > 0 && q.w > 0) {
    const double px = double{p.x} / p.w, py = double{p.y} / p.w;
    return meets_box(px, py, double{q.x} / q.w - px, double{q.y} / q.w - py, 1.0, bx, by);
  }
  if (!(p.w > 0) && !(q.w > 0)) return false;  // at infinity or behind: never drawn
  const Vec4f& in = p.w > 0 ? p : q;
  const Vec4f& out = p.w > 0 ? q : p;
  const double t = double{in.w} / (double{in.w} - double{out.w});  // where w reaches 0
  const double dx = in.x + t * (double{out.x} - in.x), dy = in.y + t * (double{out.y} - in.y);
  return meets_box(double{in.x} / in.w, double{in.y} / in.w, dx, dy, std::numeric_limits<double>::infinity(), bx, by);
}

}  // namespace

std::vector<Vec4f> fan_over(const std::vector<Vec4f>& edges, const Vec4f& anchor) {
  std::vector<Vec4f> fan;
  fan.reserve(edges.size() / 2 * 3);
  for (std::size_t e = 0; e + 1 < edges.size(); e += 2) fan.insert(fan.end(), {anchor, edges[e], edges[e + 1]});
  return fan;
}

// The same, or its part behind (w < 0) the antipodal box: the fans'
// counts are relative to the anchors' antipodes, so a curve passing there
// is as near as one passing through the viewport.
bool edge_meets_box(const Vec4f& p, const Vec4f& q, double bx, double by) {
  const Vec4f np{-p.x, -p.y, -p.z, -p.w}, nq{-q.x, -q.y, -q.z, -q.w};
  return hemisphere_edge_meets_box(p, q, bx, by) || hemisphere_edge_meets_box(np, nq, bx, by);
}

bool finite(const Vec4f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.w); }

// The viewport's area (NDC: 4 in all) that triangle (a, b, c) covers: the
// triangle clipped in homogeneous space (x, y, w) to -w <= x, y <= w, in
// double, so that a triangle with a vertex at or behind infinity (w <= 0)
// counts the part of it the rasterizer draws (the region with w > 0);
// `signed_area`: that part's signed area (counter-clockwise positive, as
// the rasterizer sees it).
double triangle_area_in_viewport(const Vec4f& a, const Vec4f& b, const Vec4f& c, double& signed_area) {
  // Sutherland-Hodgman against x + w, w - x, y + w, w - y >= 0: at most 7 vertices.
  using Polygon = std::array<std::array<double, 3>, 8>;
  Polygon poly{}, next{};
  std::size_t size = 0;
  for (const Vec4f* v : {&a, &b, &c}) poly[size++] = {double{v->x}, double{v->y}, double{v->w}};
  for (int plane = 0; plane < 4 && size > 0; ++plane) {
    const int axis = plane / 2;
    const double sign = plane % 2 == 0 ? 1.0 : -1.0;  // sign * p[axis] + p.w >= 0
    std::size_t kept = 0;
    for (std::size_t k = 0; k < size; ++k) {
      const auto& p = poly[k];
      const auto& q = poly[(k + 1) % size];
      const double dp = sign * p[axis] + p[2], dq = sign * q[axis] + q[2];
      if (dp >= 0) next[kept++] = p;
      if ((dp >= 0) != (dq >= 0)) {
        const double t = dp / (dp - dq);
        next[kept++] = {p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2])};
      }
    }
    std::swap(poly, next);
    size = kept;
  }
  double area = 0;
  for (std::size_t k = 0; k < size; ++k) {
    const auto& p = poly[k];
    const auto& q = poly[(k + 1) % size];
    if (!(p[2] > 0) || !(q[2] > 0)) continue;  // a corner on w = 0 (x = y = w = 0): no area
    area += (p[0] / p[2]) * (q[1] / q[2]) - (p[1] / p[2]) * (q[0] / q[2]);
  }
  signed_area = 0.5 * area;
  return std::fabs(signed_area);
}

// The viewport's area that the fan from `anchor` over `edges` covers,
// counted once per triangle (triangle_area_in_viewport): an estimate of the
// fragments a choice costs; `net`: the signed sum's magnitude (the region
// filled); past `limit` it stops counting.
double fan_area(const std::vector<Vec4f>& edges, const Vec4f& anchor, double* net, double limit) {
  double total = 0, signed_total = 0;
  for (std::size_t e = 0; e + 1 < edges.size() && !(total > limit); e += 2) {
    double signed_area = 0;
    total += triangle_area_in_viewport(anchor, edges[e], edges[e + 1], signed_area);
    signed_total += signed_area;
  }
  if (net) *net = std::fabs(signed_total);
  return total;
}

// A point with w > 0 in the viewport's chart (NDC), in double, and twice
// the signed area of a triangle of such points: the estimates the cuts
// below choose by.  A choice they get wrong costs fragments, never a count.
Ndc ndc(const Vec4f& v) { return {double{v.x} / v.w, double{v.y} / v.w}; }

double orient(const Ndc& a, const Ndc& b, const Ndc& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool opposite_signs(double a, double b) { return (a > 0 && b < 0) || (a < 0 && b > 0); }

}  // namespace nearcap::gl::chain
