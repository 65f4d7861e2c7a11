#include "nearcap/classification.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

#include "nearcap/engine_classification.hpp"

namespace nearcap {
namespace {
std::uint64_t undirected_key(VertexIndex a, VertexIndex b) {
  return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}
}  // namespace

ObjectClassification classify_object_exact(const CameraSpaceScene& scene, std::size_t object, std::size_t light,
                                           FilterStats* stats) {
  ObjectClassification out;
  out.object = object;
  const std::vector<Facing> facing = light_facing(scene, object, light, stats);
  out.edge_on_triangles = static_cast<std::size_t>(std::count(facing.begin(), facing.end(), Facing::EdgeOn));
  for (const SilhouetteEdge& e : silhouette_edges(scene.mesh(object), facing)) {
    const QuadCase c = quad_case(scene, object, e, light, stats);
    ++out.case_counts[static_cast<int>(c)];
    out.edges.push_back({e, c});
  }
  return out;
}

SceneClassification classify_scene(const CameraSpaceScene& scene) {
  SceneClassification out;
  for (std::size_t k = 0; k < scene.light_count(); ++k) {
    LightClassification lc;
    lc.light = k;
    lc.light_in_near_plane =
        filtered_sign(
            Predicate::NearPlaneSide, &out.stats,
            [&] { return scene.light(k).z + BoundedDouble(scene.frustum().near); },
            [&] { return Rational(scene.exact_light(k).z + Rational(scene.frustum().near)); }) == Sign::Zero;
    for (std::size_t o = 0; o < scene.object_count(); ++o) {
      if (!scene.object(o).occluder) continue;
      ObjectClassification oc = classify_object_exact(scene, o, k, &out.stats);
      const EngineSilhouette engine = engine_silhouette(scene.scene(), o, k);
      // Facing mismatches (the root of silhouette disagreements).
      const std::vector<Facing> exact_facing = light_facing(scene, o, k, nullptr);
      for (std::size_t f = 0; f < exact_facing.size(); ++f)
        if ((exact_facing[f] == Facing::Front) != (engine.facing[f] == Facing::Front)) ++oc.engine.facing_mismatch;
      std::unordered_map<std::uint64_t, std::size_t> engine_index;
      for (std::size_t i = 0; i < engine.edges.size(); ++i)
        engine_index.emplace(undirected_key(engine.edges[i].a, engine.edges[i].d), i);
      std::size_t common = 0;
      for (ClassifiedEdge& ce : oc.edges) {
        const auto it = engine_index.find(undirected_key(ce.edge.a, ce.edge.d));
        if (it == engine_index.end()) {
          ++oc.engine.silhouette_missed;
          continue;
        }
        ++common;
        ce.engine_silhouette = true;
        ce.engine = engine.cases[it->second];
        if (ce.engine != ce.exact) ++oc.engine.case_mismatch;
      }
      oc.engine.silhouette_extra = engine.edges.size() - common;
      lc.objects.push_back(std::move(oc));
    }
    out.lights.push_back(std::move(lc));
  }
  return out;
}

}  // namespace nearcap
