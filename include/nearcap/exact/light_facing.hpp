// nearcap/exact/light_facing.hpp — which triangles face a point light (exact).
//
// A triangle is light-front-facing when the light lies strictly on its outer
// side (the side its counter-clockwise normal points to, in object space).
// When the light lies in the triangle's plane the triangle is EdgeOn: it is not
// front-facing, so for silhouettes it counts with the back-facing ones.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "nearcap/exact/camera_space.hpp"

namespace nearcap {

enum class Facing : std::uint8_t { Front, Back, EdgeOn };

// Sign of the light's side of triangle f of object o: Positive = outer side.
Sign light_side(const CameraSpaceScene& scene, std::size_t o, FaceIndex f, std::size_t light, FilterStats* stats);

// Facing of every triangle of object o for the given light.
std::vector<Facing> light_facing(const CameraSpaceScene& scene, std::size_t o, std::size_t light, FilterStats* stats);

}  // namespace nearcap
