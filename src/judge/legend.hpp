// Legends under the judge's pictures (private to judge/): colour swatches with
// their meaning, drawn in a strip below an RGB image with stb_easy_font's
// vector glyphs, so that a picture explains itself without the README.
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

}  // namespace nearcap::legend
