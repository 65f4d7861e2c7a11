// Properties of the exact classification on random scenes: invariance under an
// exactly representable translation of everything (objects, light, eye), and
// the bookkeeping identities of the case counts.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "nearcap/classification.hpp"
#include "nearcap/error.hpp"
#include "random_scene.hpp"

#include <map>

namespace nearcap {
namespace {

std::optional<Scene> try_parse(const std::string& json) {
  try {
    return parse_scene(json, "random", ".");
  } catch (const Error&) {
    return std::nullopt;
  }
}

RC_GTEST_PROP(Classification, InvariantUnderExactTranslation, ()) {
  const test::RandomSceneParams params = *test::random_scene_params();
  const std::array<int, 3> offset{*rc::gen::inRange(-4096 * 16, 4096 * 16), *rc::gen::inRange(-4096 * 16, 4096 * 16),
                                  *rc::gen::inRange(-4096 * 16, 4096 * 16)};
  const auto a = try_parse(test::random_scene_json(params));
  RC_PRE(a.has_value());
  const auto b = try_parse(test::random_scene_json(params, offset));
  RC_ASSERT(b.has_value());
  const CameraSpaceScene csa(*a), csb(*b);
  const SceneClassification ca = classify_scene(csa), cb = classify_scene(csb);
  RC_ASSERT(ca.lights.size() == cb.lights.size());
  for (std::size_t k = 0; k < ca.lights.size(); ++k) {
    RC_ASSERT(ca.lights[k].objects.size() == cb.lights[k].objects.size());
    for (std::size_t o = 0; o < ca.lights[k].objects.size(); ++o) {
      const auto& ea = ca.lights[k].objects[o].edges;
      const auto& eb = cb.lights[k].objects[o].edges;
      RC_ASSERT(ea.size() == eb.size());
      for (std::size_t e = 0; e < ea.size(); ++e) {
        RC_ASSERT(ea[e].edge.a == eb[e].edge.a);
        RC_ASSERT(ea[e].edge.d == eb[e].edge.d);
        RC_ASSERT(ea[e].exact == eb[e].exact);
      }
    }
  }
}

RC_GTEST_PROP(Classification, CaseCountsAddUp, ()) {
  const auto s = try_parse(test::random_scene_json(*test::random_scene_params()));
  RC_PRE(s.has_value());
  const CameraSpaceScene cs(*s);
  const SceneClassification c = classify_scene(cs);
  for (const LightClassification& lc : c.lights)
    for (const ObjectClassification& oc : lc.objects) {
      std::array<std::size_t, kQuadCaseCount> recount{};
      for (const ClassifiedEdge& e : oc.edges) ++recount[static_cast<std::size_t>(e.exact)];
      RC_ASSERT(recount == oc.case_counts);
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

}  // namespace
}  // namespace nearcap
