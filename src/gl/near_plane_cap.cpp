// The near-cap from the clipped volume boundary (see near_plane_cap.hpp).
#include "nearcap/gl/near_plane_cap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>

#include "chain_triangulator.hpp"
#include "nearcap/gl/clipping.hpp"

namespace nearcap::gl {

using chain::edge_meets_box;
using chain::fan_over;
using chain::finite;

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

double near_plane_cap_margin(int pixels) { return 0.1 + 16.0 / std::max(pixels, 1); }

std::vector<Vec4f> near_plane_cap_triangles(const std::vector<Vec4f>& boundary_clip_vertices, int width, int height,
                                            DepthMapping mapping) {
  return chain::cap_triangles(near_plane_cap_edges(boundary_clip_vertices, mapping), width, height,
                              near_plane_z(1.0f, mapping));
}

std::vector<Vec4f> far_plane_cap_triangles(const std::vector<Vec4f>& boundary_clip_vertices, int width, int height,
                                           DepthMapping mapping) {
  return chain::cap_triangles(far_plane_cap_edges(boundary_clip_vertices, mapping), width, height,
                              far_plane_z(mapping));
}

namespace {

// The certified margin.  What the pipeline computes for a vertex of the
// box, and the sign near_plane_side_of_box must predict:
//   input  i: points, i_k = fl(c_k) (k < 3; i_3 = 1), c the double vertex,
//             so |i_k - c_k| <= u |c_k|;  directions from the float light l,
//             i_k = fl(fl(p_k) - l_k), c_k = p_k - l_k exactly, so
//             |i_k - c_k| <= u |p_k| + u |fl(p_k) - l_k|
//                        <= u (2 + u) |c_k| + u (1 + u) |l_k|;
//   rows   z = dot4(m_2, i), w = dot4(m_3, i) in float32, separate or fused:
//          either way each term sees at most 4 roundings, so
//          |z - m_2 . i| <= gamma_4 sum_k |m_2k| |i_k| (same for w), with
//          u = 2^-24 and gamma_n = n u / (1 - n u) (Higham, Accuracy and
//          Stability of Numerical Algorithms, 3.1);
//   sign   d = fl(s z + w) (s = 1; s = -1 reversed: near_plane_distance),
//          one rounding to nearest, which keeps the sign of s z + w and
//          gives 0 only when it is 0.
// With row_k = s m_2k + m_3k and mag_k = |m_2k| + |m_3k| >= |row_k|, and the
// exact distance D(c) = row . c, the float one differs by
//   |s z + w - D(c)| <= gamma_4 sum_k mag_k |i_k| + sum_k mag_k |i_k - c_k|
//                    <= sum_k mag_k ((1 + gamma_4) e_k + gamma_4 |c_k|),
// e_k the input bound above:
//   points:     (gamma_4 + (1 + gamma_4) u) S
//   directions: (gamma_4 + (1 + gamma_4) u (2 + u)) S + (1 + gamma_4) u (1 + u) L
// where S = sum_k mag_k |c_k| (largest at a corner of the box: `size`) and
// L = sum_k mag_k |l_k|.  D is linear, so its least and greatest values
// over the box are at corners; those are evaluated in double (row_k one
// rounding, the corner's shift by the light one, 4 products and 3 sums),
// within 9 roundings of 2^-53 of each term: less than 2^-48 S.  So a least
// corner value above float_bound + 2^-48 S means every vertex's float
// distance is > 0, and a greatest below its negative, every one < 0.
double certified_margin(double size, double light_size, double w) {
  constexpr double u = 0x1p-24;
  constexpr double gamma4 = 4 * u / (1 - 4 * u);
  const double from_box = w != 0 ? gamma4 + (1 + gamma4) * u : gamma4 + (1 + gamma4) * u * (2 + u);
  const double from_light = w != 0 ? 0.0 : (1 + gamma4) * u * (1 + u);
  return (from_box + 0x1p-48) * size + from_light * light_size;
}

}  // namespace

int near_plane_side_of_box(const Mat4f& m, const Vec3d& lo, const Vec3d& hi, double w, DepthMapping mapping,
                           const Vec3d& light) {
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
  const double light_size =
      magnitude[0] * std::fabs(light.x) + magnitude[1] * std::fabs(light.y) + magnitude[2] * std::fabs(light.z);
  const double margin = certified_margin(bound, light_size, w);
  if (!std::isfinite(lowest) || !std::isfinite(highest) || !std::isfinite(margin)) return 0;
  if (lowest > margin) return 1;
  if (highest < -margin) return -1;
  return 0;
}

}  // namespace nearcap::gl
