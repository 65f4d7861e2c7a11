// The Z-pass identity, checked exactly on random scenes:
//
//   stencil(i, j) = cap(i, j) + sum over silhouette sides crossed by the open
//                   segment (p, q) of +1 (entering a shadow volume) or -1.
//
// The left side is the reference's direct count (front faces crossed by
// (l, q)); cap(i, j) counts the front faces crossed by [l, p]; the sum is
// computed here, independently, from the silhouette edges of the exact
// classification: the side of edge [a, d] (front face (a, d, c)) is the part of
// plane (l, a, d) inside the wedge at l between a and d, beyond the edge.  The
// open segment (p, q) lies on the view ray x = t P, 1 < t < t_q, so each test
// is again a linear form in P under the same perturbation as the reference.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "random_scene.hpp"
#include "zpass_identity.hpp"

namespace nearcap {
namespace {

RC_GTEST_PROP(ZPassIdentity, HoldsExactlyOnRandomScenes, ()) {
  const test::RandomSceneParams params = *test::random_scene_params();
  Scene scene;
  try {
    scene = parse_scene(test::random_scene_json(params), "random", ".");
  } catch (const Error& e) {
    RC_DISCARD("scene rejected: " + std::string(e.what()));  // e.g. the light inside a box
  }
  const test::IdentityReport r = test::check_zpass_identity(scene);
  RC_ASSERT(r.holds);
  RC_ASSERT(r.degenerate * 20 <= r.checked + r.degenerate);
  RC_CLASSIFY(r.nonzero_cap > 0, "eye in a shadow volume somewhere");
  RC_CLASSIFY(r.shadowed > 0, "some pixel shadowed");
}

}  // namespace
}  // namespace nearcap
