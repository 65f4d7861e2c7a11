// The engine's cases against the exact ones (see case_comparison.hpp).
#include "nearcap/judge/case_comparison.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

#include "nearcap/exact/light_facing.hpp"
#include "nearcap/gl/engine_classification.hpp"

namespace nearcap {
namespace {

std::uint64_t undirected_key(VertexIndex a, VertexIndex b) {
  return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}

ObjectCaseComparison compare_object(const CameraSpaceScene& scene, const ObjectClassification& oc, std::size_t light) {
  ObjectCaseComparison out;
  const EngineSilhouette engine = engine_silhouette(scene.scene(), oc.object, light);
  // Facing mismatches (the root of silhouette disagreements).
  const std::vector<Facing> exact_facing = light_facing(scene, oc.object, light, nullptr);
  for (std::size_t f = 0; f < exact_facing.size(); ++f)
    if ((exact_facing[f] == Facing::Front) != (engine.facing[f] == Facing::Front)) ++out.disagreement.facing_mismatch;
  std::unordered_map<std::uint64_t, std::size_t> engine_index;
  for (std::size_t i = 0; i < engine.edges.size(); ++i)
    engine_index.emplace(undirected_key(engine.edges[i].a, engine.edges[i].d), i);
  std::size_t common = 0;
  out.edges.resize(oc.edges.size());
  for (std::size_t e = 0; e < oc.edges.size(); ++e) {
    const ClassifiedEdge& ce = oc.edges[e];
    const auto it = engine_index.find(undirected_key(ce.edge.a, ce.edge.d));
    if (it == engine_index.end()) {
      ++out.disagreement.silhouette_missed;
      continue;
    }
    ++common;
    out.edges[e] = {true, engine.cases[it->second]};
    if (out.edges[e].engine != ce.exact) ++out.disagreement.case_mismatch;
  }
  out.disagreement.silhouette_extra = engine.edges.size() - common;
  return out;
}

}  // namespace

std::size_t CaseComparison::total(std::size_t light) const {
  std::size_t sum = 0;
  for (const ObjectCaseComparison& o : lights.at(light)) sum += o.disagreement.total();
  return sum;
}

CaseComparison compare_engine_cases(const CameraSpaceScene& scene, const SceneClassification& exact) {
  CaseComparison out;
  for (const LightClassification& lc : exact.lights) {
    std::vector<ObjectCaseComparison> objects;
    for (const ObjectClassification& oc : lc.objects) objects.push_back(compare_object(scene, oc, lc.light));
    out.lights.push_back(std::move(objects));
  }
  return out;
}

}  // namespace nearcap
