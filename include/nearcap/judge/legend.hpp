// nearcap/judge/legend.hpp — legends under the judge's pictures: colour
// swatches with their meaning, drawn in a strip below an RGB image with
// stb_easy_font's vector glyphs, so that a picture explains itself without
// the README; and the same text drawn anywhere on an image (the viewer's
// status line).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace nearcap::legend {

using Rgb = std::array<std::uint8_t, 3>;

struct Entry {
  Rgb colour;
  std::string text;
};

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // top row first
};

// The image with a strip below it: an optional title line, then one line per
// entry (swatch, text).  The strip is as wide as the image, or wider (padded
// grey) when the text needs it.
Image with_legend(const Image& image, const std::string& title, const std::vector<Entry>& entries);

// `text` (printable ASCII) drawn in `ink` with its top left corner at (x, y),
// each glyph pixel scaled to scale x scale pixels; clipped to the image.
void draw_text(Image& image, int x, int y, const std::string& text, int scale, const Rgb& ink);
// The width of `text` in glyph pixels (times the scale on the image); 12 is a line.
int text_width(const std::string& text);

}  // namespace nearcap::legend
