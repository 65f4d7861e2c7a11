// nearcap/view/status_panel.hpp — the viewer's status text drawn over the top
// of its frame, wrapped to the frame's width.
//
// The status is a list of paragraphs (the status line, the policy's method per
// occluder), each a list of fields ("[m] zfail", "[l] all lights", the
// times, the crack count).  A paragraph is laid out in lines no wider than
// the frame less its margins: as many whole fields per line as fit, two
// spaces apart; a field wider than a line is broken at its spaces, and a word
// wider than a line between characters.  Nothing is cut off at the frame's
// right edge, whatever its width.
#pragma once

#include <string>
#include <vector>

#include "nearcap/judge/legend.hpp"

namespace nearcap::view {

// The lines of one paragraph, each at most `width` glyph pixels wide
// (legend::text_width); `width` < 1 is taken as 1 (one character a line).
std::vector<std::string> wrap_fields(const std::vector<std::string>& fields, int width);

// The glyph scale the viewer draws its status with on an image `image_width`
// pixels wide: 2 from 960 pixels on, else 1.
int status_scale(int image_width);

// Draws `paragraphs` (empty ones skipped) wrapped to the image's width, on a
// band across the top darkened to a quarter, light grey text, 12 pixels a
// line at scale 1.  Returns the band's height in pixels (0: nothing drawn).
int paint_status(legend::Image& image, const std::vector<std::vector<std::string>>& paragraphs);

}  // namespace nearcap::view
