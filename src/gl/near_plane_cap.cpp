// The near-cap from the clipped volume boundary (see near_plane_cap.hpp).
#include "nearcap/gl/near_plane_cap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "nearcap/gl/clipping.hpp"

namespace nearcap::gl {
namespace {

std::vector<Vec4f> fan_over(const std::vector<Vec4f>& edges, const Vec4f& anchor) {
  std::vector<Vec4f> fan;
  fan.reserve(edges.size() / 2 * 3);
  for (std::size_t e = 0; e + 1 < edges.size(); e += 2) fan.insert(fan.end(), {anchor, edges[e], edges[e + 1]});
  return fan;
}

}  // namespace

std::vector<Vec4f> near_plane_cap_edges(const std::vector<Vec4f>& boundary_clip_vertices) {
  std::vector<Vec4f> edges;
  for (std::size_t t = 0; t + 2 < boundary_clip_vertices.size(); t += 3) {
    const Vec4f &a = boundary_clip_vertices[t], &b = boundary_clip_vertices[t + 1], &c = boundary_clip_vertices[t + 2];
    // Only a triangle that reaches the near plane leaves an edge in it.
    if ((a.z + a.w > 0) && (b.z + b.w > 0) && (c.z + c.w > 0)) continue;
    const NearClippedPolygon poly = clip_to_near_plane(a, b, c);
    const std::size_t n = poly.vertices.size();
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t next = (k + 1) % n;
      if (!poly.on_near_plane[k] || !poly.on_near_plane[next]) continue;
      // The polygon runs k -> next; the cap closing it runs next -> k.
      edges.insert(edges.end(), {poly.vertices[next], poly.vertices[k]});
    }
  }
  return edges;
}

std::vector<Vec4f> near_plane_cap_fan(const std::vector<Vec4f>& boundary_clip_vertices, const Vec4f& anchor) {
  return fan_over(near_plane_cap_edges(boundary_clip_vertices), anchor);
}

Vec4f near_plane_cap_anchor() { return {0.0f, 0.0f, -1.0f, 1.0f}; }

Vec4f near_plane_cap_anchor(const std::vector<Vec4f>& edges) {
  double sx = 0, sy = 0;
  std::size_t n = 0;
  for (const Vec4f& v : edges)
    if (v.w > 0 && std::fabs(v.x) <= v.w && std::fabs(v.y) <= v.w) {
      sx += double{v.x} / v.w;
      sy += double{v.y} / v.w;
      ++n;
    }
  if (n == 0) return near_plane_cap_anchor();
  return {static_cast<float>(std::clamp(sx / n, -1.0, 1.0)), static_cast<float>(std::clamp(sy / n, -1.0, 1.0)), -1.0f,
          1.0f};
}

std::vector<Vec4f> near_plane_cap_fan(const std::vector<Vec4f>& boundary_clip_vertices) {
  const std::vector<Vec4f> edges = near_plane_cap_edges(boundary_clip_vertices);
  return fan_over(edges, near_plane_cap_anchor(edges));
}

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

// Does the clip-space edge p -> q (w >= 0 at both ends, so along it) come
// into the NDC box?  A vertex at infinity (w = 0) is the direction (x, y):
// the edge from a finite vertex is a ray, between two such an arc at
// infinity, which no finite box meets.
bool edge_meets_box(const Vec4f& p, const Vec4f& q, double bx, double by) {
  if (p.w > 0 && q.w > 0) {
    const double px = double{p.x} / p.w, py = double{p.y} / p.w;
    return meets_box(px, py, double{q.x} / q.w - px, double{q.y} / q.w - py, 1.0, bx, by);
  }
  const double inf = std::numeric_limits<double>::infinity();
  if (p.w > 0) return meets_box(double{p.x} / p.w, double{p.y} / p.w, q.x, q.y, inf, bx, by);
  if (q.w > 0) return meets_box(double{q.x} / q.w, double{q.y} / q.w, p.x, p.y, inf, bx, by);
  return false;
}

bool finite(const Vec4f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.w); }

}  // namespace

std::optional<int> near_plane_cap_constant_winding(const std::vector<Vec4f>& edges, double margin_x, double margin_y) {
  int winding = 0;
  for (std::size_t e = 0; e + 1 < edges.size(); e += 2) {
    const Vec4f &p = edges[e], &q = edges[e + 1];
    if (!finite(p) || !finite(q) || p.w < 0 || q.w < 0) return std::nullopt;
    if ((p.w == 0 && p.x == 0 && p.y == 0) || (q.w == 0 && q.x == 0 && q.y == 0)) return std::nullopt;
    if (edge_meets_box(p, q, 1 + margin_x, 1 + margin_y)) return std::nullopt;
    // Crossings of the half-line y = 0, x > 0 from the centre, on the
    // hemisphere w >= 0 (so at infinity too): where y changes sign (half
    // open), the crossing's x has the sign of p x q = x_p y_q - y_p x_q
    // upward and the opposite downward.  Float products are exact in
    // double, and their difference has the right sign.
    const double side = double{p.x} * double{q.y} - double{p.y} * double{q.x};
    if (p.y <= 0 && q.y > 0 && side > 0) ++winding;  // upward, the centre on its left
    if (p.y > 0 && q.y <= 0 && side < 0) --winding;  // downward, the centre on its right
  }
  return winding;
}

std::vector<Vec4f> near_plane_cap_triangles(const std::vector<Vec4f>& boundary_clip_vertices, int width, int height) {
  const std::vector<Vec4f> edges = near_plane_cap_edges(boundary_clip_vertices);
  const double mx = 0.1 + 16.0 / std::max(width, 1), my = 0.1 + 16.0 / std::max(height, 1);
  if (const std::optional<int> c = near_plane_cap_constant_winding(edges, mx, my)) {
    // |c| triangles over the viewport (the clipper trims them to it).
    const Vec4f a{-1.0f, -1.0f, -1.0f, 1.0f}, b{3.0f, -1.0f, -1.0f, 1.0f}, d{-1.0f, 3.0f, -1.0f, 1.0f};
    std::vector<Vec4f> out;
    for (int k = 0; k < std::abs(*c); ++k) {
      if (*c > 0)
        out.insert(out.end(), {a, b, d});
      else
        out.insert(out.end(), {a, d, b});
    }
    return out;
  }
  return fan_over(edges, near_plane_cap_anchor(edges));
}

}  // namespace nearcap::gl
