// nearcap/exact/classification.hpp — silhouettes and A-D cases of a whole scene.
//
// For every light and every occluder: the exact silhouette edges and the exact
// case of each edge's side quad.  The float engine's answer for the same edges
// and the disagreements are judged in judge/case_comparison.hpp.  This is what
// `nearcap classify` prints; sweeps aggregate the counts.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/quad_case.hpp"
#include "nearcap/exact/silhouette.hpp"

namespace nearcap {

struct ClassifiedEdge {
  SilhouetteEdge edge;  // exact silhouette edge
  QuadCase exact;       // exact case
};

struct ObjectClassification {
  std::size_t object = 0;
  std::vector<ClassifiedEdge> edges;
  std::array<std::size_t, kQuadCaseCount> case_counts{};
  std::size_t edge_on_triangles = 0;  // triangles whose plane contains the light
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

// Exact classification of one occluder for one light.
ObjectClassification classify_object_exact(const CameraSpaceScene& scene, std::size_t object, std::size_t light,
                                           FilterStats* stats);

// Every light and every occluder.
SceneClassification classify_scene(const CameraSpaceScene& scene);

}  // namespace nearcap
