// The viewer's status text (see status_panel.hpp).
#include "nearcap/view/status_panel.hpp"

#include <algorithm>

namespace nearcap::view {
namespace {

constexpr int kLine = 12;  // glyph pixels a line (legend.hpp)

// Splits `text` at its spaces into words (runs of spaces dropped).
std::vector<std::string> words_of(const std::string& text) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t start = text.find_first_not_of(' ', at);
    if (start == std::string::npos) break;
    const std::size_t end = std::min(text.find(' ', start), text.size());
    out.push_back(text.substr(start, end - start));
    at = end;
  }
  return out;
}

// Appends `piece` to the lines, starting a new line when the last one would
// grow wider than `width` with `gap` and the piece after it.
void place(std::vector<std::string>& lines, const std::string& piece, const std::string& gap, int width) {
  if (!lines.empty() && !lines.back().empty() && legend::text_width(lines.back() + gap + piece) <= width) {
    lines.back() += gap + piece;
    return;
  }
  if (!lines.empty() && lines.back().empty()) {
    lines.back() = piece;
    return;
  }
  lines.push_back(piece);
}

}  // namespace

std::vector<std::string> wrap_fields(const std::vector<std::string>& fields, int width) {
  width = std::max(width, 1);
  std::vector<std::string> lines;
  for (const std::string& field : fields) {
    if (field.empty()) continue;
    if (legend::text_width(field) <= width) {
      place(lines, field, "  ", width);
      continue;
    }
    // Too wide for any line: its words, each on the line it starts on.
    lines.emplace_back();
    for (const std::string& word : words_of(field)) {
      if (legend::text_width(word) <= width) {
        place(lines, word, " ", width);
        continue;
      }
      // A word wider than a line: as many characters a line as fit (at least one).
      std::string part;
      for (char c : word) {
        if (!part.empty() && legend::text_width(part + c) > width) {
          place(lines, part, " ", width);
          lines.emplace_back();
          part.clear();
        }
        part += c;
      }
      place(lines, part, " ", width);
    }
    lines.emplace_back();  // the next field starts on a line of its own
  }
  while (!lines.empty() && lines.back().empty()) lines.pop_back();
  return lines;
}

int status_scale(int image_width) { return image_width >= 960 ? 2 : 1; }

int paint_status(legend::Image& image, const std::vector<std::vector<std::string>>& paragraphs) {
  const int scale = status_scale(image.width), line = kLine * scale, margin = 2 * scale;
  const int width = (image.width - 2 * margin) / scale;
  std::vector<std::string> lines;
  for (const std::vector<std::string>& p : paragraphs) {
    const std::vector<std::string> wrapped = wrap_fields(p, width);
    lines.insert(lines.end(), wrapped.begin(), wrapped.end());
  }
  if (lines.empty()) return 0;
  const int band = std::min(image.height, static_cast<int>(lines.size()) * line + 2 * scale);
  for (int y = 0; y < band; ++y)
    for (int x = 0; x < 3 * image.width; ++x) {
      std::uint8_t& v = image.rgb[3 * static_cast<std::size_t>(y) * image.width + static_cast<std::size_t>(x)];
      v = static_cast<std::uint8_t>(v / 4);
    }
  for (std::size_t k = 0; k < lines.size(); ++k)
    legend::draw_text(image, margin, scale + static_cast<int>(k) * line, lines[k], scale, {240, 240, 240});
  return band;
}

}  // namespace nearcap::view
