// The near-cap from the clipped volume boundary (see near_plane_cap.hpp).
#include "nearcap/gl/near_plane_cap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>

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

namespace {

// The edges one plane's clipping stage leaves, as the cap closing the
// clipped volume runs them: the near plane's (clip_to_near_plane), or the
// far plane's (clip_to_far_plane), each the first stage.
std::vector<Vec4f> plane_cap_edges(const std::vector<Vec4f>& boundary_clip_vertices, DepthMapping mapping, bool far) {
  std::vector<Vec4f> edges;
  auto distance = [&](const Vec4f& v) {
    return far ? far_plane_distance(v, mapping) : near_plane_distance(v, mapping);
  };
  for (std::size_t t = 0; t + 2 < boundary_clip_vertices.size(); t += 3) {
    const Vec4f &a = boundary_clip_vertices[t], &b = boundary_clip_vertices[t + 1], &c = boundary_clip_vertices[t + 2];
    // Only a triangle that reaches the plane leaves an edge in it.
    if (distance(a) > 0 && distance(b) > 0 && distance(c) > 0) continue;
    const NearClippedPolygon poly = far ? clip_to_far_plane(a, b, c, mapping) : clip_to_near_plane(a, b, c, mapping);
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

// The far plane's z at w = 1.
float far_plane_z(DepthMapping m) { return m == DepthMapping::Standard ? 1.0f : 0.0f; }

}  // namespace

std::vector<Vec4f> near_plane_cap_edges(const std::vector<Vec4f>& boundary_clip_vertices, DepthMapping mapping) {
  return plane_cap_edges(boundary_clip_vertices, mapping, false);
}

std::vector<Vec4f> far_plane_cap_edges(const std::vector<Vec4f>& boundary_clip_vertices, DepthMapping mapping) {
  return plane_cap_edges(boundary_clip_vertices, mapping, true);
}

std::vector<Vec4f> near_plane_cap_fan(const std::vector<Vec4f>& boundary_clip_vertices, const Vec4f& anchor,
                                      DepthMapping mapping) {
  return fan_over(near_plane_cap_edges(boundary_clip_vertices, mapping), anchor);
}

Vec4f near_plane_cap_anchor(DepthMapping mapping) { return {0.0f, 0.0f, near_plane_z(1.0f, mapping), 1.0f}; }

Vec4f near_plane_cap_anchor(const std::vector<Vec4f>& edges, DepthMapping mapping) {
  double sx = 0, sy = 0;
  std::size_t n = 0;
  for (const Vec4f& v : edges)
    if (v.w > 0 && std::fabs(v.x) <= v.w && std::fabs(v.y) <= v.w) {
      sx += double{v.x} / v.w;
      sy += double{v.y} / v.w;
      ++n;
    }
  if (n == 0) return near_plane_cap_anchor(mapping);
  return {static_cast<float>(std::clamp(sx / n, -1.0, 1.0)), static_cast<float>(std::clamp(sy / n, -1.0, 1.0)),
          near_plane_z(1.0f, mapping), 1.0f};
}

std::vector<Vec4f> near_plane_cap_fan(const std::vector<Vec4f>& boundary_clip_vertices, DepthMapping mapping) {
  const std::vector<Vec4f> edges = near_plane_cap_edges(boundary_clip_vertices, mapping);
  return fan_over(edges, near_plane_cap_anchor(edges, mapping));
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

// The same, or its part behind (w < 0) the antipodal box: the fans'
// counts are relative to the anchors' antipodes, so a curve passing there
// is as near as one passing through the viewport.
bool edge_meets_box(const Vec4f& p, const Vec4f& q, double bx, double by) {
  const Vec4f np{-p.x, -p.y, -p.z, -p.w}, nq{-q.x, -q.y, -q.z, -q.w};
  return hemisphere_edge_meets_box(p, q, bx, by) || hemisphere_edge_meets_box(np, nq, bx, by);
}

bool finite(const Vec4f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.w); }

}  // namespace

std::optional<int> near_plane_cap_constant_winding(const std::vector<Vec4f>& edges, double margin_x, double margin_y) {
  int winding = 0;
  for (std::size_t e = 0; e + 1 < edges.size(); e += 2) {
    const Vec4f &p = edges[e], &q = edges[e + 1];
    if (!finite(p) || !finite(q)) return std::nullopt;
    // A vertex on the axis x = y = 0 but not in the viewport (at infinity,
    // or the antipode behind): the fan's count would depend on its anchor.
    if ((p.x == 0 && p.y == 0 && !(p.w > 0)) || (q.x == 0 && q.y == 0 && !(q.w > 0))) return std::nullopt;
    if (edge_meets_box(p, q, 1 + margin_x, 1 + margin_y)) return std::nullopt;
    // Crossings of the half great circle y = 0, x > 0 from the centre (0, 0,
    // 1) through infinity to the antipode of the fan's anchor (0, 0, -1) (in
    // (x, y, w)), where the fan from the centre counts from: where y
    // changes sign along the edge (half open), the crossing's x has the sign
    // of p x q = x_p y_q - y_p x_q upward and the opposite downward, whatever
    // w is there.  Float products are exact in double, and their difference
    // has the right sign.
    const double side = double{p.x} * double{q.y} - double{p.y} * double{q.x};
    if (p.y <= 0 && q.y > 0 && side > 0) ++winding;  // upward, the centre on its left
    if (p.y > 0 && q.y <= 0 && side < 0) --winding;  // downward, the centre on its right
  }
  return winding;
}

std::vector<std::vector<Vec4f>> near_plane_cap_loops(const std::vector<Vec4f>& edges) {
  // Vertices are matched bit for bit: the clipper made both ends of a curve
  // vertex's two edges from the same boundary edge, so they are equal.
  using Key = std::array<std::uint32_t, 4>;
  auto key = [](const Vec4f& v) {
    Key k;
    std::memcpy(k.data(), &v, sizeof k);
    return k;
  };
  const std::size_t n = edges.size() / 2;
  std::map<Key, std::vector<std::size_t>> leaving;  // edges by their first vertex
  for (std::size_t e = 0; e < n; ++e) leaving[key(edges[2 * e])].push_back(e);
  std::vector<bool> used(n, false);
  std::vector<std::vector<Vec4f>> loops;
  std::vector<Vec4f> rest;
  for (std::size_t start = 0; start < n; ++start) {
    if (used[start]) continue;
    std::vector<std::size_t> walk{start};
    used[start] = true;
    const Key first = key(edges[2 * start]);
    bool closed = false;
    while (true) {
      const Key at = key(edges[2 * walk.back() + 1]);
      if (at == first) {
        closed = true;
        break;
      }
      std::vector<std::size_t>& out = leaving[at];
      while (!out.empty() && used[out.back()]) out.pop_back();
      if (out.empty()) break;  // not closed (cannot happen for a closed volume): kept with the rest
      walk.push_back(out.back());
      used[out.back()] = true;
      out.pop_back();
    }
    std::vector<Vec4f>& into = closed ? loops.emplace_back() : rest;
    for (std::size_t e : walk) into.insert(into.end(), {edges[2 * e], edges[2 * e + 1]});
  }
  if (!rest.empty()) loops.push_back(std::move(rest));
  return loops;
}

namespace {

// The viewport's area (NDC: 4 in all) that triangle (a, b, c) covers,
// clipped to the square in double; a triangle with a vertex at or behind
// infinity (w <= 0) counts the whole viewport, its signed area unknown (NaN).
double triangle_area_in_viewport(const Vec4f& a, const Vec4f& b, const Vec4f& c, double& signed_area) {
  // Sutherland-Hodgman against x >= -1, x <= 1, y >= -1, y <= 1: at most 7 vertices.
  using Polygon = std::array<std::array<double, 2>, 8>;
  Polygon poly{}, next{};
  std::size_t size = 0;
  for (const Vec4f* v : {&a, &b, &c}) {
    if (!(v->w > 0)) {
      signed_area = std::numeric_limits<double>::quiet_NaN();
      return 4.0;
    }
    poly[size++] = {double{v->x} / v->w, double{v->y} / v->w};
  }
  for (int plane = 0; plane < 4 && size > 0; ++plane) {
    const int axis = plane / 2;
    const double sign = plane % 2 == 0 ? 1.0 : -1.0;  // sign * p[axis] + 1 >= 0
    std::size_t kept = 0;
    for (std::size_t k = 0; k < size; ++k) {
      const auto& p = poly[k];
      const auto& q = poly[(k + 1) % size];
      const double dp = sign * p[axis] + 1, dq = sign * q[axis] + 1;
      if (dp >= 0) next[kept++] = p;
      if ((dp >= 0) != (dq >= 0)) {
        const double t = dp / (dp - dq);
        next[kept++] = {p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])};
      }
    }
    std::swap(poly, next);
    size = kept;
  }
  double area = 0;
  for (std::size_t k = 0; k < size; ++k) {
    const auto& p = poly[k];
    const auto& q = poly[(k + 1) % size];
    area += p[0] * q[1] - p[1] * q[0];
  }
  signed_area = 0.5 * area;
  return std::fabs(signed_area);
}

// The viewport's area that the fan from `anchor` over `edges` covers,
// counted once per triangle (triangle_area_in_viewport): an estimate of the
// fragments a choice costs; `net`: the signed sum's magnitude (the region
// filled); past `limit` it stops counting.
double fan_area(const std::vector<Vec4f>& edges, const Vec4f& anchor, double* net = nullptr,
                double limit = std::numeric_limits<double>::infinity()) {
  double total = 0, signed_total = 0;
  for (std::size_t e = 0; e + 1 < edges.size() && !(total > limit); e += 2) {
    double signed_area = 0;
    total += triangle_area_in_viewport(anchor, edges[e], edges[e + 1], signed_area);
    signed_total += signed_area;
  }
  if (net) *net = std::fabs(signed_total);
  return total;
}

// A fan with an anchor per edge: a loop that no single anchor fans without
// drawing much of the viewport twice (a curve that winds across it) split
// into runs of edges, each run fanned from its own anchor (all at w = 1).
// Where edge e's anchor a_e gives way to a_{e+1} at vertex v (the end of e,
// the start of e + 1), a glue triangle (a_e, v, a_{e+1}) closes the gap, and
// for each such switch a triangle (s, a_e, a_{e+1}) from the reference anchor
// s = a_0 closes the polygon of the anchors: the triangles' boundaries then
// sum to the loop's edges alone.  So every pixel gets the single fan from s's
// count: fanning edge (v, w) from a instead of s adds triangles (a, v, s) and
// (a, s, w), exactly so in the oriented projective plane when a, s, v and w
// lie in one open hemisphere (else it may add the whole plane once), which
// holds when v and w have w > 0 like the anchors; an edge with an endpoint at
// or behind infinity keeps s, and switches happen only at vertices in the
// viewport.  The loop must be a chain of finite vertices (each edge's end bit
// for bit the next one's start); else nothing.
//
// The anchors are chosen by dynamic programming over the loop, for each of
// the first `references` anchors as s: the cost of an edge is its
// triangle's area in the viewport, of a switch its glue and closing
// triangles' areas.  Switches between any two anchors are tried at the
// vertices in the viewport where the preferred anchor (the one that fans
// the edge alone with the least area) changes, and at every other vertex
// with w > 0 between the edge's preferred anchor, its predecessor's and the
// first two.  Returns the triangles, `area` their total in the viewport.
std::optional<std::vector<Vec4f>> anchor_per_run_fan(const std::vector<Vec4f>& loop, const std::vector<Vec4f>& anchors,
                                                     std::size_t references, double& area) {
  const std::size_t n = loop.size() / 2, count = anchors.size();
  if (n < 3 || count < 2 || count > 255 || references > count) return std::nullopt;
  for (std::size_t e = 0; e < n; ++e) {
    const Vec4f& v = loop[2 * e];
    if (!finite(v) || std::memcmp(&loop[2 * ((e + n - 1) % n) + 1], &v, sizeof(Vec4f)) != 0) return std::nullopt;
  }
  struct Point {
    double x, y;
  };
  std::vector<Point> start(n);
  std::vector<bool> inside(n), behind(n);
  for (std::size_t e = 0; e < n; ++e) {
    const Vec4f& v = loop[2 * e];
    behind[e] = !(v.w > 0) || !(loop[2 * e + 1].w > 0);
    start[e] = v.w > 0 ? Point{double{v.x} / v.w, double{v.y} / v.w} : Point{0, 0};
    inside[e] = v.w > 0 && std::fabs(start[e].x) <= 1 && std::fabs(start[e].y) <= 1;
  }
  std::vector<Point> a(count);
  for (std::size_t k = 0; k < count; ++k)
    a[k] = {double{anchors[k].x} / anchors[k].w, double{anchors[k].y} / anchors[k].w};
  // edge_area[e * count + k]: edge e's triangle from anchor k; preferred[e]: the anchor giving the least.
  std::vector<double> edge_area(n * count);
  std::vector<std::size_t> preferred(n, 0);
  for (std::size_t e = 0; e < n; ++e)
    for (std::size_t k = 0; k < count; ++k) {
      double unused = 0;
      double& area_k = edge_area[e * count + k];
      area_k = triangle_area_in_viewport(anchors[k], loop[2 * e], loop[2 * e + 1], unused);
      if (area_k < edge_area[e * count + preferred[e]]) preferred[e] = k;
    }
  // A switch from anchor j to k at vertex v: the glue triangle's area
  // |cross(a_k - a_j, v - a_j)| / 2 = |dx v.y - dy v.x + c| / 2, linear in v;
  // tried only at vertices in the viewport where the preferred anchor changes.
  struct Glue {
    double dx, dy, c;
  };
  std::vector<Glue> glue(count * count);
  for (std::size_t j = 0; j < count; ++j)
    for (std::size_t k = 0; k < count; ++k) {
      const double dx = a[k].x - a[j].x, dy = a[k].y - a[j].y;
      glue[j * count + k] = {dx, dy, dy * a[j].x - dx * a[j].y};
    }
  auto closing = [&](std::size_t r, std::size_t j, std::size_t k) {
    return 0.5 * std::fabs((a[j].x - a[r].x) * (a[k].y - a[r].y) - (a[j].y - a[r].y) * (a[k].x - a[r].x));
  };
  constexpr double kNone = std::numeric_limits<double>::infinity();
  double best = kNone;
  std::vector<std::uint8_t> best_choice, choice(n * count);  // choice[e * count + k]: edge e - 1's anchor
  std::vector<double> cost(count), next(count);
  std::size_t best_last = 0;
  for (std::size_t s = 0; s < references; ++s) {
    std::fill(cost.begin(), cost.end(), kNone);
    cost[s] = edge_area[s];  // edge 0's anchor: s (and so for an edge behind, below)
    for (std::size_t e = 1; e < n; ++e) {
      const Point& v = start[e];
      // In the viewport where the preferred anchor changes: any two anchors;
      // at any other vertex with w > 0: between the candidates.
      const bool switch_any = inside[e] && preferred[e] != preferred[e - 1];
      const bool switch_candidates = !switch_any && loop[2 * e].w > 0;
      auto candidate = [&](std::size_t i) { return i == preferred[e] || i == preferred[e - 1] || i < 2; };
      for (std::size_t k = 0; k < count; ++k) {
        double c = cost[k];
        std::size_t from = k;
        if (switch_any || (switch_candidates && candidate(k)))
          for (std::size_t j = 0; j < count; ++j) {
            if (j == k || !(cost[j] < c) || (switch_candidates && !candidate(j))) continue;
            const Glue& g = glue[j * count + k];
            double unused = 0;
            const double glue_area = inside[e] ? 0.5 * std::fabs(g.dx * v.y - g.dy * v.x + g.c)
                                               : triangle_area_in_viewport(anchors[j], loop[2 * e], anchors[k], unused);
            const double switched = cost[j] + glue_area + closing(s, j, k);
            if (switched < c) {
              c = switched;
              from = j;
            }
          }
        next[k] = behind[e] && k != s ? kNone : c + edge_area[e * count + k];
        choice[e * count + k] = static_cast<std::uint8_t>(from);
      }
      std::swap(cost, next);
    }
    for (std::size_t k = 0; k < count; ++k) {
      const Glue& g = glue[k * count + s];
      // Back to s at vertex 0 (its closing triangle is degenerate).
      double total = cost[k], unused = 0;
      if (k != s) {
        if (inside[0])
          total += 0.5 * std::fabs(g.dx * start[0].y - g.dy * start[0].x + g.c);
        else if (loop[0].w > 0)
          total += triangle_area_in_viewport(anchors[k], loop[0], anchors[s], unused);
        else
          total = kNone;
      }
      if (total < best) {
        best = total;
        best_last = k;
        best_choice = choice;
      }
    }
  }
  if (!(best < kNone)) return std::nullopt;
  std::vector<std::size_t> k(n);
  k[n - 1] = best_last;
  for (std::size_t e = n - 1; e > 0; --e) k[e - 1] = best_choice[e * count + k[e]];
  const std::size_t s = k[0];
  std::vector<Vec4f> out;
  out.reserve(3 * n);
  for (std::size_t e = 0; e < n; ++e) out.insert(out.end(), {anchors[k[e]], loop[2 * e], loop[2 * e + 1]});
  for (std::size_t e = 0; e < n; ++e) {
    const std::size_t f = (e + 1) % n;
    if (k[e] == k[f]) continue;
    out.insert(out.end(), {anchors[k[e]], loop[2 * e + 1], anchors[k[f]]});
    if (k[e] != s && k[f] != s) out.insert(out.end(), {anchors[s], anchors[k[e]], anchors[k[f]]});
  }
  area = best;
  return out;
}

// A path around the viewport in place of a whole run of edges away from it:
// from the run's first vertex u to its last v through 1 to 4 corners of the
// box |x|, |y| <= 1 + 2 margin (w = 1, z = plane_z), such that the run and
// the path back count 0 over the viewport.  The fan over it draws the
// wedges of the cap's own side of the viewport, where chords that follow a
// run circling the viewport far away cost wedges all around it, and a chord
// past its other side |count| triangles over all of it (`fly_around` frame
// 38: 34,468 fragments where the cap covers 5,420 pixels).  The count of
// the run with a candidate path back is computed once in full
// (near_plane_cap_constant_winding); the others' from it and the small
// closed polygon of the two paths.  Nothing when no path avoids the margin.
std::optional<std::vector<Vec4f>> detour(const std::vector<Vec4f>& run, double mx, double my, float plane_z) {
  const Vec4f u = run.front(), v = run.back();
  const float bx = static_cast<float>(1 + 2 * mx), by = static_cast<float>(1 + 2 * my);
  const std::array<Vec4f, 4> corner{Vec4f{-bx, -by, plane_z, 1.0f}, Vec4f{bx, -by, plane_z, 1.0f},
                                    Vec4f{bx, by, plane_z, 1.0f}, Vec4f{-bx, by, plane_z, 1.0f}};
  auto backwards = [](const std::vector<Vec4f>& path, std::vector<Vec4f>& edges) {
    for (std::size_t k = path.size() - 1; k > 0; --k) edges.insert(edges.end(), {path[k], path[k - 1]});
  };
  std::optional<std::vector<Vec4f>> base;  // a path whose count with the run is known
  int base_count = 0;
  for (int count = 1; count <= 4; ++count)
    for (int first = 0; first < 4; ++first)
      for (int step : {1, 3}) {  // counter-clockwise, clockwise
        std::vector<Vec4f> path{u};
        for (int k = 0; k < count; ++k) path.push_back(corner[(first + k * step) % 4]);
        path.push_back(v);
        std::optional<int> c;
        if (!base) {
          std::vector<Vec4f> closed = run;
          backwards(path, closed);
          c = near_plane_cap_constant_winding(closed, mx, my);
          if (c) {
            base = path;
            base_count = *c;
          }
        } else {
          std::vector<Vec4f> closed;
          for (std::size_t k = 0; k + 1 < base->size(); ++k) closed.insert(closed.end(), {(*base)[k], (*base)[k + 1]});
          backwards(path, closed);
          if (const std::optional<int> between = near_plane_cap_constant_winding(closed, mx, my))
            c = base_count + *between;
        }
        if (!c || *c != 0) continue;
        std::vector<Vec4f> edges;
        for (std::size_t k = 0; k + 1 < path.size(); ++k) edges.insert(edges.end(), {path[k], path[k + 1]});
        return edges;
      }
  return std::nullopt;
}

// Edges [begin, end) of `run` (2 vertices each, consecutive), simplified:
// the chord from the first vertex to the last where the closed
// run-and-chord-back has one count over the viewport
// (near_plane_cap_constant_winding: every edge and the chord away from it),
// that count added to `constant`; else each half the same way.
void simplify_run(const std::vector<Vec4f>& run, std::size_t begin, std::size_t end, double mx, double my,
                  int& constant, std::vector<Vec4f>& out) {
  if (end - begin >= 2) {
    std::vector<Vec4f> closed(run.begin() + 2 * begin, run.begin() + 2 * end);
    const Vec4f u = run[2 * begin], v = run[2 * end - 1];
    closed.insert(closed.end(), {v, u});
    if (const std::optional<int> c = near_plane_cap_constant_winding(closed, mx, my)) {
      constant += *c;
      out.insert(out.end(), {u, v});
      return;
    }
    const std::size_t mid = begin + (end - begin) / 2;
    simplify_run(run, begin, mid, mx, my, constant, out);
    simplify_run(run, mid, end, mx, my, constant, out);
    return;
  }
  out.insert(out.end(), run.begin() + 2 * begin, run.begin() + 2 * end);
}

// A loop that comes into the viewport, with each run of consecutive edges
// that stays away from it simplified (simplify_run): the fan over a run is
// the fan over its chord plus the fan over the closed run-and-chord-back,
// whose count is one number over the viewport.  The loop's edges near the
// viewport, which the sides share bit for bit, are kept as they are.
std::vector<Vec4f> shortened_loop(const std::vector<Vec4f>& loop, const Vec4f& anchor, double mx, double my,
                                  float plane_z, int& constant) {
  const std::size_t n = loop.size() / 2;
  std::vector<bool> far(n);
  std::size_t first_near = n;
  for (std::size_t e = 0; e < n; ++e) {
    far[e] =
        finite(loop[2 * e]) && finite(loop[2 * e + 1]) && !edge_meets_box(loop[2 * e], loop[2 * e + 1], 1 + mx, 1 + my);
    if (!far[e] && first_near == n) first_near = e;
  }
  if (first_near == n) return loop;
  std::vector<Vec4f> out;
  // Walk once around from a near edge, so that no run wraps past the start.
  for (std::size_t k = 0; k < n;) {
    const std::size_t e = (first_near + k) % n;
    if (!far[e]) {
      out.insert(out.end(), {loop[2 * e], loop[2 * e + 1]});
      ++k;
      continue;
    }
    std::vector<Vec4f> run;
    for (; k < n && far[(first_near + k) % n]; ++k) {
      const std::size_t f = (first_near + k) % n;
      run.insert(run.end(), {loop[2 * f], loop[2 * f + 1]});
    }
    // The chords (and their count over the viewport), or a detour around
    // it: whichever the fan covers less of the viewport with.
    std::vector<Vec4f> chords;
    int count = 0;
    simplify_run(run, 0, run.size() / 2, mx, my, count, chords);
    if (count != 0) {
      if (const std::optional<std::vector<Vec4f>> around = detour(run, mx, my, plane_z)) {
        if (fan_area(*around, anchor) < fan_area(chords, anchor) + 4.0 * std::abs(count)) {
          out.insert(out.end(), around->begin(), around->end());
          continue;
        }
      }
    }
    constant += count;
    out.insert(out.end(), chords.begin(), chords.end());
  }
  return out;
}

}  // namespace

namespace {

// The cap's triangles over `edges` (near_plane_cap_triangles), every vertex
// the pass adds (anchors, the viewport's triangles) at z = plane_z w.
std::vector<Vec4f> cap_triangles_over(const std::vector<Vec4f>& edges, int width, int height, float plane_z) {
  const double mx = near_plane_cap_margin(width), my = near_plane_cap_margin(height);
  std::vector<Vec4f> out;
  int constant = 0;  // the loops that stay outside the viewport, together
  for (const std::vector<Vec4f>& loop : near_plane_cap_loops(edges)) {
    if (const std::optional<int> c = near_plane_cap_constant_winding(loop, mx, my)) {
      constant += *c;
      continue;
    }
    Vec4f anchor = near_plane_cap_anchor(loop);
    anchor.z = plane_z;
    const std::vector<Vec4f> shortened = shortened_loop(loop, anchor, mx, my, plane_z, constant);
    // Any anchor gives the same counts; of the mean and a 5 x 5 grid of
    // points of the viewport, all with w = 1 (as well conditioned:
    // near_plane_cap_anchor), the one whose fan covers the least of it.
    // The search only where the fan draws more than 2 % of the viewport
    // twice (its area beyond the signed sum, the region it fills).
    double net = 0;
    double least = fan_area(shortened, anchor, &net);
    constexpr float kGrid[5] = {-1.0f + 0x1p-10f, -0.5f, 0.0f, 0.5f, 1.0f - 0x1p-10f};
    for (int k = 0; k < 25 && !(least - net < 0.08); ++k) {
      const Vec4f candidate{kGrid[k % 5], kGrid[k / 5], plane_z, 1.0f};
      const double area = fan_area(shortened, candidate, nullptr, least);  // stops once above the least
      if (area < least) {
        least = area;
        anchor = candidate;
      }
    }
    // Where the best single fan still draws 256 fragments or more twice
    // (its area beyond the region it fills): an anchor per run of edges,
    // from that one, the centre and the grid, referred to one of the first
    // two.  Below that the search costs more time than it saves.
    constexpr double kRunsWorthTrying = 256;  // fragments
    if (!((least - net) * 0.25 * width * height < kRunsWorthTrying)) {
      std::vector<Vec4f> anchors{anchor, {0.0f, 0.0f, plane_z, 1.0f}};
      for (int k = 0; k < 25; ++k)
        if (k != 12) anchors.push_back({kGrid[k % 5], kGrid[k / 5], plane_z, 1.0f});
      double area = 0;
      if (std::optional<std::vector<Vec4f>> runs = anchor_per_run_fan(shortened, anchors, 2, area);
          runs && area < least) {
        out.insert(out.end(), runs->begin(), runs->end());
        continue;
      }
    }
    const std::vector<Vec4f> fan = fan_over(shortened, anchor);
    out.insert(out.end(), fan.begin(), fan.end());
  }
  // |constant| triangles over the viewport (the clipper trims them to it).
  const Vec4f a{-1.0f, -1.0f, plane_z, 1.0f}, b{3.0f, -1.0f, plane_z, 1.0f}, d{-1.0f, 3.0f, plane_z, 1.0f};
  for (int k = 0; k < std::abs(constant); ++k) {
    if (constant > 0)
      out.insert(out.end(), {a, b, d});
    else
      out.insert(out.end(), {a, d, b});
  }
  return out;
}

}  // namespace

double near_plane_cap_margin(int pixels) { return 0.1 + 16.0 / std::max(pixels, 1); }

std::vector<Vec4f> near_plane_cap_triangles(const std::vector<Vec4f>& boundary_clip_vertices, int width, int height,
                                            DepthMapping mapping) {
  return cap_triangles_over(near_plane_cap_edges(boundary_clip_vertices, mapping), width, height,
                            near_plane_z(1.0f, mapping));
}

std::vector<Vec4f> far_plane_cap_triangles(const std::vector<Vec4f>& boundary_clip_vertices, int width, int height,
                                           DepthMapping mapping) {
  return cap_triangles_over(far_plane_cap_edges(boundary_clip_vertices, mapping), width, height, far_plane_z(mapping));
}

int near_plane_side_of_box(const Mat4f& m, const Vec3d& lo, const Vec3d& hi, double w, DepthMapping mapping) {
  double row[4], magnitude[4];
  const double z_sign = mapping == DepthMapping::Standard ? 1.0 : -1.0;  // z + w, or w - z
  for (int k = 0; k < 4; ++k) {
    row[k] = z_sign * double{m.at(2, k)} + double{m.at(3, k)};
    magnitude[k] = std::fabs(double{m.at(2, k)}) + std::fabs(double{m.at(3, k)});
  }
  double lowest = std::numeric_limits<double>::infinity(), highest = -lowest, bound = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const double c[4] = {(corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z, w};
    double value = 0, size = 0;
    for (int k = 0; k < 4; ++k) {
      value += row[k] * c[k];
      size += magnitude[k] * std::fabs(c[k]);
    }
    lowest = std::min(lowest, value);
    highest = std::max(highest, value);
    bound = std::max(bound, size);
  }
  const double margin = 1e-5 * bound;
  if (!std::isfinite(lowest) || !std::isfinite(highest) || !std::isfinite(margin)) return 0;
  if (lowest > margin) return 1;
  if (highest < -margin) return -1;
  return 0;
}

}  // namespace nearcap::gl
