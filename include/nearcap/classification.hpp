// nearcap/classification.hpp — silhouettes and A-D cases of a whole scene.
//
// For every light and every occluder: the exact silhouette edges and the exact
// case of each edge's side quad, the float engine's answer for the same edges,
// and the disagreements between the two.  This is what `nearcap classify`
// prints; sweeps aggregate the counts.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "nearcap/camera_space.hpp"
#include "nearcap/quad_case.hpp"
#include "nearcap/silhouette.hpp"

namespace nearcap {

struct ClassifiedEdge {
  SilhouetteEdge edge;                     // exact silhouette edge
  QuadCase exact;                          // exact case
  bool engine_silhouette = false;          // the float engine also found this edge
  QuadCase engine = QuadCase::Degenerate;  // the engine's case (if engine_silhouette)
};

struct EngineDisagreement {
  std::size_t silhouette_missed = 0;  // exact silhouette edges the engine missed
  std::size_t silhouette_extra = 0;   // engine silhouette edges that are not exact ones
  std::size_t case_mismatch = 0;      // common edges classified differently
  std::size_t facing_mismatch = 0;    // triangles whose float facing differs from the exact one
  std::size_t total() const { return silhouette_missed + silhouette_extra + case_mismatch; }
};

struct ObjectClassification {
  std::size_t object = 0;
  std::vector<ClassifiedEdge> edges;
  std::array<std::size_t, kQuadCaseCount> case_counts{};
  std::size_t edge_on_triangles = 0;  // triangles whose plane contains the light
  EngineDisagreement engine;
};

struct LightClassification {
  std::size_t light = 0;
  // The light lies exactly in the near plane (exact test).  Every infinite
  // edge then leaves the plane on its vertex's side, so quads are A or D, and
  // ZP+'s light frustum is undefined (l_far = 0): ZP+ must fall back to Z-fail
  // for this light.
  bool light_in_near_plane = false;
  std::vector<ObjectClassification> objects;  // occluders only, in scene order
};

struct SceneClassification {
  std::vector<LightClassification> lights;
  FilterStats stats;
};

// Exact classification of one occluder for one light (no engine comparison).
ObjectClassification classify_object_exact(const CameraSpaceScene& scene, std::size_t object, std::size_t light,
                                           FilterStats* stats);

// Everything, with the engine comparison.
SceneClassification classify_scene(const CameraSpaceScene& scene);

}  // namespace nearcap
