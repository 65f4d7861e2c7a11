// Legend strips (see legend.hpp).
#include "nearcap/judge/legend.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <stb/stb_easy_font.h>

#include "nearcap/judge/word_wrap.hpp"

namespace nearcap::legend {
namespace {

constexpr Rgb kBackground{235, 235, 235}, kInk{20, 20, 20};

struct Canvas {
  int width, height;
  std::vector<std::uint8_t>& rgb;
  void fill(int x0, int y0, int x1, int y1, const Rgb& c) {
    for (int y = std::max(0, y0); y < std::min(height, y1); ++y)
      for (int x = std::max(0, x0); x < std::min(width, x1); ++x)
        std::copy(c.begin(), c.end(), &rgb[3 * (static_cast<std::size_t>(y) * width + x)]);
  }
  // stb_easy_font's quads, scaled, at (x, y) (top left), pixel centres inside a quad filled.
  void text(int x, int y, const std::string& s, int scale, const Rgb& ink = kInk) {
    std::vector<char> chars(s.begin(), s.end());
    chars.push_back('\0');
    alignas(float) thread_local char buffer[64 * 1024];
    const int quads = stb_easy_font_print(0, 0, chars.data(), nullptr, buffer, sizeof buffer);
    const float* v = reinterpret_cast<const float*>(buffer);
    for (int q = 0; q < quads; ++q) {
      const float* quad = v + 16 * q;  // 4 vertices of x, y, z, colour
      float xmin = quad[0], xmax = quad[0], ymin = quad[1], ymax = quad[1];
      for (int k = 1; k < 4; ++k) {
        xmin = std::min(xmin, quad[4 * k]);
        xmax = std::max(xmax, quad[4 * k]);
        ymin = std::min(ymin, quad[4 * k + 1]);
        ymax = std::max(ymax, quad[4 * k + 1]);
      }
      fill(x + static_cast<int>(std::lround(xmin * scale)), y + static_cast<int>(std::lround(ymin * scale)),
           x + static_cast<int>(std::lround(xmax * scale)), y + static_cast<int>(std::lround(ymax * scale)), ink);
    }
  }
};

}  // namespace

int text_width(const std::string& s) {
  std::vector<char> chars(s.begin(), s.end());
  chars.push_back('\0');
  return stb_easy_font_width(chars.data());
}

void draw_text(Image& image, int x, int y, const std::string& text, int scale, const Rgb& ink) {
  Canvas{image.width, image.height, image.rgb}.text(x, y, text, scale, ink);
}

std::vector<std::string> wrap_text(const std::string& text, int width) {
  return wrap_words(text, [width](const std::string& s) { return text_width(s) <= width; });
}

Image with_legend(const Image& image, const std::string& title, const std::vector<Entry>& entries) {
  const int scale = image.width >= 480 ? 2 : 1;
  const int line = 12 * scale, swatch = 8 * scale, margin = 4 * scale;
  Image out;
  out.width = std::max(image.width, kMinLegendWidth);
  // Text widths in glyph pixels: the title spans the strip, an entry's text
  // starts after its swatch.
  const int title_w = (out.width - 2 * margin) / scale, entry_w = (out.width - 3 * margin - swatch) / scale;
  const std::vector<std::string> title_lines = title.empty() ? std::vector<std::string>{} : wrap_text(title, title_w);
  std::vector<std::vector<std::string>> entry_lines;
  std::size_t lines = title_lines.size();
  for (const Entry& e : entries) {
    entry_lines.push_back(wrap_text(e.text, entry_w));
    lines += entry_lines.back().size();
  }
  out.height = image.height + static_cast<int>(lines) * line + 2 * margin;
  out.rgb.assign(3 * static_cast<std::size_t>(out.width) * out.height, 0);
  Canvas canvas{out.width, out.height, out.rgb};
  canvas.fill(0, 0, out.width, out.height, kBackground);
  for (int y = 0; y < image.height; ++y)
    std::copy(&image.rgb[3 * static_cast<std::size_t>(y) * image.width],
              &image.rgb[3 * static_cast<std::size_t>(y + 1) * image.width],
              &out.rgb[3 * static_cast<std::size_t>(y) * out.width]);
  int y = image.height + margin;
  for (const std::string& t : title_lines) {
    canvas.text(margin, y + scale, t, scale);
    y += line;
  }
  for (std::size_t k = 0; k < entries.size(); ++k) {
    canvas.fill(margin, y, margin + swatch, y + swatch, kInk);
    canvas.fill(margin + 1, y + 1, margin + swatch - 1, y + swatch - 1, entries[k].colour);
    for (const std::string& t : entry_lines[k]) {
      canvas.text(margin + swatch + margin, y + scale, t, scale);
      y += line;
    }
  }
  return out;
}

}  // namespace nearcap::legend
