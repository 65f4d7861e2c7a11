// nearcap/judge/near_cap_svg.hpp — a picture of the near-cap: the near
// rectangle with its faces shaded by count (darker = more front faces between
// the light and the point; hovering a face shows its count), y up as in camera
// space, drawn to the rectangle's true aspect, with a legend of the counts.
// When the camera's pixels are not square (the rectangle's aspect differs
// from width / height), the legend says so: an image of the same frame is
// stretched relative to this picture.
#pragma once

#include <string>

#include "nearcap/exact/near_cap.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {

std::string near_cap_svg(const NearCap& cap, const Camera& camera, const std::string& title);

}  // namespace nearcap
