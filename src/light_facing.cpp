#include "nearcap/light_facing.hpp"

namespace nearcap {

Sign light_side(const CameraSpaceScene& scene, std::size_t o, FaceIndex f, std::size_t light, FilterStats* stats) {
  const auto& t = scene.mesh(o).triangles[f];
  const Sign s = filtered_sign(
      Predicate::LightFacing, stats,
      [&] {
        return orientation_determinant(scene.vertex(o, t[0]), scene.vertex(o, t[1]), scene.vertex(o, t[2]),
                                       scene.light(light));
      },
      [&] {
        return orientation_determinant(scene.exact_vertex(o, t[0]), scene.exact_vertex(o, t[1]),
                                       scene.exact_vertex(o, t[2]), scene.exact_light(light));
      });
  // A mirroring map (negative determinant) reverses the winding: undo it.
  return s * scene.handedness(o);
}

std::vector<Facing> light_facing(const CameraSpaceScene& scene, std::size_t o, std::size_t light, FilterStats* stats) {
  const std::size_t n = scene.mesh(o).triangle_count();
  std::vector<Facing> facing(n);
  for (FaceIndex f = 0; f < n; ++f) {
    const Sign s = light_side(scene, o, f, light, stats);
    facing[f] = s == Sign::Positive ? Facing::Front : (s == Sign::Negative ? Facing::Back : Facing::EdgeOn);
  }
  return facing;
}

}  // namespace nearcap
