// nearcap/near_cap_svg.hpp — a picture of the near-cap: the near rectangle
// with its faces shaded by count (darker = more front faces between the light
// and the point), y up as in camera space, with a legend.
#pragma once

#include <string>

#include "nearcap/exact/near_cap.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {

std::string near_cap_svg(const NearCap& cap, const Frustum& frustum, const std::string& title);

}  // namespace nearcap
