// An occluder's facing under a light, and the cache of the last few (see
// occluder_facing.hpp).
#include "nearcap/analysis/occluder_facing.hpp"

#include <algorithm>

#include "nearcap/check.hpp"

namespace nearcap::analysis {

OccluderFacing occluder_facing(const TriangleMesh& mesh, const Vec3d& light) {
  NEARCAP_CHECK(mesh.has_adjacency());
  OccluderFacing out;
  const std::size_t faces = mesh.triangle_count();
  out.front.resize(faces);
  for (std::size_t f = 0; f < faces; ++f) {
    const auto& pl = mesh.face_planes.plane[f];
    out.front[f] = pl[0] * light.x + pl[1] * light.y + pl[2] * light.z - pl[3] > 0;
    out.light_facing += out.front[f];
  }
  for (std::size_t f = 0; f < faces; ++f) {
    if (!out.front[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const FaceIndex g = mesh.neighbours[f][k];
      NEARCAP_CHECK(g != kNoFace);
      if (!out.front[g]) out.edges.push_back({mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3]});
    }
  }
  return out;
}

const OccluderFacing& FacingCache::facing(const std::shared_ptr<const TriangleMesh>& mesh, const Vec3d& light) {
  ++clock_;
  for (Entry& e : entries_)
    if (e.mesh == mesh && e.light.x == light.x && e.light.y == light.y && e.light.z == light.z) {
      e.used = clock_;
      return e.facing;
    }
  ++computed_;
  Entry* slot = nullptr;
  if (entries_.size() < kKept) {
    slot = &entries_.emplace_back();
  } else {
    slot = &*std::min_element(entries_.begin(), entries_.end(),
                              [](const Entry& a, const Entry& b) { return a.used < b.used; });
  }
  slot->mesh = mesh;
  slot->light = light;
  slot->facing = occluder_facing(*mesh, light);
  slot->used = clock_;
  return slot->facing;
}

}  // namespace nearcap::analysis
