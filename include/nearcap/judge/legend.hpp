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

// The narrowest legend strip, in image pixels: a narrower image is padded
// grey on the right to this width, so that the legend stays legible.
constexpr int kMinLegendWidth = 240;

// The image with a strip below it: an optional title, then each entry
// (swatch, text), every text wrapped at spaces to the strip's width (a word
// longer than a line is cut).  The result is max(image.width,
// kMinLegendWidth) wide whatever the text: the images of one frame size all
// have one width; the strip grows downwards instead.
Image with_legend(const Image& image, const std::string& title, const std::vector<Entry>& entries);

// `text` cut into lines of at most `width` glyph pixels (text_width), at
// spaces where it can, inside a word where one word is wider; never empty.
std::vector<std::string> wrap_text(const std::string& text, int width);

// `text` (printable ASCII) drawn in `ink` with its top left corner at (x, y),
// each glyph pixel scaled to scale x scale pixels; clipped to the image.
void draw_text(Image& image, int x, int y, const std::string& text, int scale, const Rgb& ink);
// The width of `text` in glyph pixels (times the scale on the image); 12 is a line.
int text_width(const std::string& text);

}  // namespace nearcap::legend
