// nearcap/judge/reference_images.hpp — the per-pixel reference as image files.
//
// cap.pgm and stencil.pgm: 16-bit binary PGM, the file's first row the image's
// TOP row (PGM's order; PixelReference stores GL's bottom row first).  A count
// is stored as is up to 65534; kPgmSaturated (65534) means "65534 or more" and
// kPgmNothingSeen (65535) marks a pixel where no surface is seen (stencil only).
// shadow.png: the visible surfaces, Lambert-shaded by the light, darkened where
// the exact stencil count says shadow: for a person to look at.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/pixel_reference.hpp"

namespace nearcap {

inline constexpr std::uint16_t kPgmNothingSeen = 65535;
inline constexpr std::uint16_t kPgmSaturated = 65534;

std::string cap_pgm(const PixelReference& ref);
std::string stencil_pgm(const PixelReference& ref);
std::string shadow_png(const CameraSpaceScene& scene, const PixelReference& ref);
// shadow.png's pixels: 8-bit RGB, top row first.
std::vector<std::uint8_t> shadow_rgb(const CameraSpaceScene& scene, const PixelReference& ref);

}  // namespace nearcap
