// The near-cap from the clipped volume boundary (see near_plane_cap.hpp).
#include "nearcap/gl/near_plane_cap.hpp"

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

std::vector<Vec4f> near_plane_cap_fan(const std::vector<Vec4f>& boundary_clip_vertices) {
  return near_plane_cap_fan(boundary_clip_vertices, near_plane_cap_anchor());
}

}  // namespace nearcap::gl
