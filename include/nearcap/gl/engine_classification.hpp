// nearcap/gl/engine_classification.hpp — the same silhouettes and cases in plain float.
//
// What a shadow-volume engine computes during silhouette extraction (ZP+ section
// 5: "the cases are explicitly examined during the search for silhouette
// edges"): the modelview matrix built in float32 as a GLM application builds it
// (view * object_to_world, both rounded to float), vertices and light moved to
// camera space in float32, facing from the float sign of dot(n, l - a), and the
// near-plane sides from float comparisons.  There is no "degenerate": a float
// zero counts as the positive side, as `if (z + near > 0) ... else ...` would
// (mapping zero to one side; an engine has to pick one).  Comparing these with
// the exact results counts how often an engine classifies wrongly.
#pragma once

#include <cstddef>
#include <vector>

#include "nearcap/exact/quad_case.hpp"
#include "nearcap/exact/silhouette.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {

struct EngineSilhouette {
  std::vector<Facing> facing;         // Front or Back only
  std::vector<SilhouetteEdge> edges;  // in the front face's winding
  std::vector<QuadCase> cases;        // never Degenerate
};

EngineSilhouette engine_silhouette(const Scene& scene, std::size_t object, std::size_t light);

}  // namespace nearcap
