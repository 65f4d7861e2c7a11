// nearcap/judge/near_cap_svg.hpp — a picture of the near-cap: the near
// rectangle with its faces shaded by count (darker = more front faces between
// the light and the point; hovering a face shows its count), y up as in camera
// space, with a legend of the counts and a caption.
//
// The rectangle is drawn to the frame's aspect (camera width : height), as
// the frame's images show it, so the picture sits beside them unstretched.
// When the camera's pixels are not square (the near rectangle's own aspect
// differs from width / height) the caption says so.  The picture is
// kNearCapSvgWidth wide; the caption is wrapped to that width less its
// margins, by caption_width's estimate.
#pragma once

#include <string>
#include <vector>

#include "nearcap/exact/near_cap.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {

inline constexpr double kNearCapSvgWidth = 800;
inline constexpr double kCaptionMargin = 10;
std::string near_cap_svg(const NearCap& cap, const Camera& camera, const std::string& title);

// An upper bound on the width in pixels of `text` drawn in the caption's
// 12 px sans-serif: each glyph counted at the advance of the widest glyph of
// its class in DejaVu Sans (wider than Liberation Sans, Arial and Helvetica),
// bytes outside printable ASCII at the widest advance.
double caption_width(const std::string& text);

// `text` cut into lines no wider than width_px by caption_width, at spaces
// where it can, inside a word where one word is wider; never empty.
std::vector<std::string> wrap_caption(const std::string& text, double width_px);

}  // namespace nearcap
