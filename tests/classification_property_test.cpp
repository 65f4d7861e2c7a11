// Properties of the exact classification on random scenes: invariance under an
// exactly representable translation of everything (objects, light, eye), and
// the bookkeeping identities of the case counts.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "nearcap/error.hpp"
#include "nearcap/exact/classification.hpp"
#include "random_scene.hpp"

#include <map>

namespace nearcap {
namespace {

// Same silhouette edges, in the same order, with the same exact cases.
void assert_same_edges(const ObjectClassification& a, const ObjectClassification& b) {
  RC_ASSERT(a.edges.size() == b.edges.size());
  for (std::size_t e = 0; e < a.edges.size(); ++e) {
    RC_ASSERT(a.edges[e].edge.a == b.edges[e].edge.a);
    RC_ASSERT(a.edges[e].edge.d == b.edges[e].edge.d);
    RC_ASSERT(a.edges[e].exact == b.edges[e].exact);
  }
}

void assert_same_classification(const SceneClassification& a, const SceneClassification& b) {
  RC_ASSERT(a.lights.size() == b.lights.size());
  for (std::size_t k = 0; k < a.lights.size(); ++k) {
    RC_ASSERT(a.lights[k].light_in_near_plane == b.lights[k].light_in_near_plane);
    RC_ASSERT(a.lights[k].objects.size() == b.lights[k].objects.size());
    for (std::size_t o = 0; o < a.lights[k].objects.size(); ++o)
      assert_same_edges(a.lights[k].objects[o], b.lights[k].objects[o]);
  }
}

RC_GTEST_PROP(Classification, InvariantUnderExactTranslation, ()) {
  const test::RandomSceneParams params = *test::random_scene_params();
  const std::array<int, 3> offset = *test::dyadic_offset16(4096);
  const auto a = test::try_parse_scene(test::random_scene_json(params));
  RC_PRE(a.has_value());
  const auto b = test::try_parse_scene(test::random_scene_json(params, offset));
  RC_ASSERT(b.has_value());
  const CameraSpaceScene csa(*a), csb(*b);
  assert_same_classification(classify_scene(csa), classify_scene(csb));
}

RC_GTEST_PROP(Classification, CaseCountsAddUp, ()) {
  const auto s = test::try_parse_scene(test::random_scene_json(*test::random_scene_params()));
  RC_PRE(s.has_value());
  const CameraSpaceScene cs(*s);
  const SceneClassification c = classify_scene(cs);
  for (const LightClassification& lc : c.lights)
    for (const ObjectClassification& oc : lc.objects) {
      std::array<std::size_t, kQuadCaseCount> recount{};
      for (const ClassifiedEdge& e : oc.edges) {
        RC_ASSERT(static_cast<std::size_t>(e.exact) < kQuadCaseCount);  // one of the six values
        ++recount[static_cast<std::size_t>(e.exact)];
      }
      RC_ASSERT(recount == oc.case_counts);
      std::size_t sum = 0;
      for (std::size_t n : oc.case_counts) sum += n;
      RC_ASSERT(sum == oc.edges.size());
      // A closed mesh's silhouette is a set of closed loops: every vertex has
      // an even number of silhouette edges.
      std::map<VertexIndex, int> degree;
      for (const ClassifiedEdge& e : oc.edges) {
        ++degree[e.edge.a];
        ++degree[e.edge.d];
      }
      for (const auto& [v, d] : degree) RC_ASSERT(d % 2 == 0);
    }
}

// A torus (data/meshes/torus.off, 2304 triangles, genus 1: silhouettes with
// several loops) at a random place, light and camera as in random_scene_json.
// The first box is replaced by the torus, scaled by scale8 / 8.
std::string torus_scene_json(const test::RandomSceneParams& p, int scale8,
                             const std::array<int, 3>& offset16 = {0, 0, 0}) {
  nlohmann::json j = nlohmann::json::parse(test::random_scene_json(p, offset16));
  j["objects"][0] = {{"mesh", std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/torus.off"},
                     {"translate", j["objects"][0]["translate"]},
                     {"scale", scale8 / 8.0},
                     {"rotate_deg", j["objects"][0]["rotate_deg"]}};
  return j.dump();
}

// The quad of [A, D] and the quad of [D, A] are the same quad: the reversed
// edge has the sides of the original with A and D swapped, and the same case.
void check_reversal(const SceneClassification& c, const CameraSpaceScene& cs) {
  for (const LightClassification& lc : c.lights)
    for (const ObjectClassification& oc : lc.objects)
      for (const ClassifiedEdge& e : oc.edges) {
        const QuadSides fwd = quad_sides(cs, oc.object, e.edge.a, e.edge.d, lc.light, nullptr);
        const QuadSides rev = quad_sides(cs, oc.object, e.edge.d, e.edge.a, lc.light, nullptr);
        RC_ASSERT(rev.a == fwd.d);
        RC_ASSERT(rev.d == fwd.a);
        RC_ASSERT(rev.a_inf == fwd.d_inf);
        RC_ASSERT(rev.d_inf == fwd.a_inf);
        RC_ASSERT(quad_case_from_sides(rev) == e.exact);
        const SilhouetteEdge reversed{e.edge.d, e.edge.a, e.edge.other_face, e.edge.front_face};
        RC_ASSERT(quad_case(cs, oc.object, reversed, lc.light, nullptr) == e.exact);
      }
}

RC_GTEST_PROP(Classification, ReversedEdgeHasTheSameCase, ()) {
  const auto s = test::try_parse_scene(test::random_scene_json(*test::random_scene_params()));
  RC_PRE(s.has_value());
  const CameraSpaceScene cs(*s);
  const SceneClassification c = classify_scene(cs);
  check_reversal(c, cs);
  for (std::size_t k = 0; k < kQuadCaseCount; ++k)
    RC_CLASSIFY(c.lights[0].objects[0].case_counts[k] > 0, std::string(to_string(static_cast<QuadCase>(k))));
}

RC_GTEST_PROP(ClassificationTorus, ReversalAndCountsOnRandomTori, ()) {
  const auto s = test::try_parse_scene(torus_scene_json(*test::random_scene_params(), *rc::gen::inRange(2, 9)));
  RC_PRE(s.has_value());
  const CameraSpaceScene cs(*s);
  const SceneClassification c = classify_scene(cs);
  check_reversal(c, cs);
  const ObjectClassification& oc = c.lights.at(0).objects.at(0);
  RC_ASSERT(!oc.edges.empty());  // a closed mesh lit from outside has a silhouette
  std::size_t sum = 0;
  for (std::size_t n : oc.case_counts) sum += n;
  RC_ASSERT(sum == oc.edges.size());
}

RC_GTEST_PROP(ClassificationTorus, InvariantUnderExactTranslation, ()) {
  // The torus's rotation is rounded once (cos, sin), but a translation by
  // sixteenths of everything still cancels exactly in view * object_to_world.
  const test::RandomSceneParams params = *test::random_scene_params();
  const int scale8 = *rc::gen::inRange(2, 9);
  const std::array<int, 3> offset = *test::dyadic_offset16(4096);
  const auto a = test::try_parse_scene(torus_scene_json(params, scale8));
  RC_PRE(a.has_value());
  const auto b = test::try_parse_scene(torus_scene_json(params, scale8, offset));
  RC_ASSERT(b.has_value());
  const CameraSpaceScene csa(*a), csb(*b);
  const ObjectClassification ca = classify_object_exact(csa, 0, 0, nullptr);
  const ObjectClassification cb = classify_object_exact(csb, 0, 0, nullptr);
  assert_same_edges(ca, cb);
  RC_ASSERT(ca.case_counts == cb.case_counts);
}

// Random scenes pressed against the near plane, where every case and every
// degeneracy arises: near = m/16, unrotated boxes (half of them) whose faces
// can lie exactly in z = -near, the light within 3/16 of the plane or in it.
rc::Gen<test::RandomSceneParams> near_plane_scene_params() {
  return rc::gen::exec([] {
    test::RandomSceneParams p = *test::random_scene_params();
    const int m = *rc::gen::inRange(1, 8);
    p.near64 = 4 * m;
    const int plane16 = p.eye16[2] - m;  // world z of the near plane, in sixteenths
    for (std::size_t b = 0; b < p.box_centres16.size(); ++b) {
      p.box_centres16[b][0] = *rc::gen::inRange(-6, 7);
      p.box_centres16[b][1] = p.eye16[1] + *rc::gen::inRange(-6, 7);
      p.box_centres16[b][2] = plane16 + *rc::gen::inRange(-6, 7);
      p.box_scales16[b] = 2 * *rc::gen::inRange(2, 8);  // even: faces on sixteenths
      if (*rc::gen::inRange(0, 2) == 0) p.box_rotations_deg[b] = {0, 0, 0};
    }
    p.light16[2] = plane16 + *rc::gen::inRange(-3, 4);
    return p;
  });
}

RC_GTEST_PROP(Classification, ReversedEdgeHasTheSameCaseNearTheNearPlane, ()) {
  const auto s = test::try_parse_scene(test::random_scene_json(*near_plane_scene_params()));
  RC_PRE(s.has_value());
  const CameraSpaceScene cs(*s);
  const SceneClassification c = classify_scene(cs);
  check_reversal(c, cs);
  for (const ObjectClassification& oc : c.lights[0].objects)
    for (std::size_t k = 0; k < kQuadCaseCount; ++k)
      RC_CLASSIFY(oc.case_counts[k] > 0, std::string(to_string(static_cast<QuadCase>(k))));
}

RC_GTEST_PROP(Classification, InvariantUnderExactTranslationNearTheNearPlane, ()) {
  const test::RandomSceneParams params = *near_plane_scene_params();
  const std::array<int, 3> offset = *test::dyadic_offset16(1024);
  const auto a = test::try_parse_scene(test::random_scene_json(params));
  RC_PRE(a.has_value());
  const auto b = test::try_parse_scene(test::random_scene_json(params, offset));
  RC_ASSERT(b.has_value());
  const CameraSpaceScene csa(*a), csb(*b);
  const SceneClassification ca = classify_scene(csa), cb = classify_scene(csb);
  assert_same_classification(ca, cb);
  RC_CLASSIFY(ca.lights[0].light_in_near_plane, "light in the near plane");
}

}  // namespace
}  // namespace nearcap
