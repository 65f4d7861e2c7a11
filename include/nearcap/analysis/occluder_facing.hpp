// nearcap/analysis/occluder_facing.hpp — which faces of an occluder face a
// light, and its silhouette's edges: what the work estimate
// (work_estimate.hpp) reads first, and the one part of it that depends on
// neither the camera nor the other objects, only on the mesh and the
// light's position in object space.  A renderer whose lights and occluders
// stay put while the camera moves (the bundled paths) keeps it across
// frames, as engines keep a static light's shadow volumes: FacingCache.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "nearcap/scene/mesh.hpp"

namespace nearcap::analysis {

struct OccluderFacing {
  // front[f]: face f faces the light, the sign of its plane at the light
  // (FacePlanes, in double; gl::engine_silhouette decides the same sign in
  // float32: the two agree except on faces within rounding of edge-on).
  std::vector<std::uint8_t> front;
  std::size_t light_facing = 0;  // faces with front[f]
  // The silhouette's edges (A, D) = (t[k], t[k + 1]) of a front face t whose
  // neighbour across them is not front (exact/silhouette.hpp's order).
  std::vector<std::array<VertexIndex, 2>> edges;
};

// The facing of `mesh` (with adjacency and face planes) under a light at
// `light` (object space).
OccluderFacing occluder_facing(const TriangleMesh& mesh, const Vec3d& light);

// The facings of the last few (mesh, light) pairs asked for, each computed
// once while it stays among them: a pair is the same mesh object and the
// same object-space light position, bit for bit, so a cached facing is the
// one occluder_facing would compute.  Not thread-safe: one per renderer loop.
class FacingCache {
 public:
  // The reference stays valid until the next call.
  const OccluderFacing& facing(const std::shared_ptr<const TriangleMesh>& mesh, const Vec3d& light);
  std::size_t computed() const { return computed_; }  // facings computed (not found kept)

  static constexpr std::size_t kKept = 32;  // (mesh, light) pairs

 private:
  struct Entry {
    std::shared_ptr<const TriangleMesh> mesh;  // held: its address is not reused while kept
    Vec3d light;
    OccluderFacing facing;
    std::uint64_t used = 0;
  };
  std::vector<Entry> entries_;
  std::uint64_t clock_ = 0;
  std::size_t computed_ = 0;
};

}  // namespace nearcap::analysis
