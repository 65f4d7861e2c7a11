// nearcap/judge/case_comparison.hpp — the float engine's silhouettes and
// cases against the exact ones.
//
// For every light and occluder of an exact classification
// (exact/classification.hpp), what the float32 engine (gl/engine_classification.hpp)
// finds for the same edges: whether it found each exact silhouette edge and
// its case there, the edges it found that are not exact silhouette edges, and
// the triangles whose float facing differs.  `nearcap classify` prints both;
// `nearcap cracks` reports the total as "case_disagreements".
#pragma once

#include <cstddef>
#include <vector>

#include "nearcap/exact/classification.hpp"

namespace nearcap {

struct EngineEdge {
  bool found = false;                      // the engine also has this exact silhouette edge
  QuadCase engine = QuadCase::Degenerate;  // its case there (if found)
};

struct EngineDisagreement {
  std::size_t silhouette_missed = 0;  // exact silhouette edges the engine missed
  std::size_t silhouette_extra = 0;   // engine silhouette edges that are not exact ones
  std::size_t case_mismatch = 0;      // common edges classified differently
  std::size_t facing_mismatch = 0;    // triangles whose float facing differs from the exact one
  std::size_t total() const { return silhouette_missed + silhouette_extra + case_mismatch; }
};

struct ObjectCaseComparison {
  std::vector<EngineEdge> edges;  // parallel to ObjectClassification::edges
  EngineDisagreement disagreement;
};

// comparisons[light][k] is for classification.lights[light].objects[k].
struct CaseComparison {
  std::vector<std::vector<ObjectCaseComparison>> lights;
  std::size_t total(std::size_t light) const;  // summed over the light's occluders
};

CaseComparison compare_engine_cases(const CameraSpaceScene& scene, const SceneClassification& exact);

}  // namespace nearcap
