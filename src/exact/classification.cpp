#include "nearcap/exact/classification.hpp"

#include <algorithm>

namespace nearcap {
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
      lc.objects.push_back(classify_object_exact(scene, o, k, &out.stats));
    }
    out.lights.push_back(std::move(lc));
  }
  return out;
}

}  // namespace nearcap
