// SVG rendering of a near-cap arrangement.
#include "nearcap/judge/near_cap_svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <vector>

#include "nearcap/judge/word_wrap.hpp"

namespace nearcap {
namespace {

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

// Count 0 white, then darker blues.
std::string fill_for(std::size_t count, std::size_t max_count) {
  if (count == 0) return "#ffffff";
  const double t = max_count > 0 ? static_cast<double>(count) / static_cast<double>(max_count) : 1.0;
  const int r = static_cast<int>(200 - 170 * t), g = static_cast<int>(215 - 150 * t),
            b = static_cast<int>(240 - 90 * t);
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", r, g, b);
  return buf;
}

}  // namespace

double caption_width(const std::string& text) {
  // Advances of DejaVu Sans (the widest of the usual sans-serif fonts) at
  // 12 px, rounded up per class of glyph: the widest of each class.
  double w = 0;
  for (const char c : text) {
    if (std::strchr("mMWw@%", c) != nullptr)
      w += 12;  // W: 2025/2048 em
    else if ((c >= 'A' && c <= 'Z') || std::strchr("#&+<=>^~", c) != nullptr)
      w += 10.5;  // ~: 1716/2048 em
    else if ((c >= 'a' && c <= 'z' && std::strchr("ijlfrt", c) == nullptr) || (c >= '0' && c <= '9') ||
             std::strchr("$?*_`{}", c) != nullptr)
      w += 8;  // digits: 1303/2048 em
    else if (std::strchr(" ijlfrt'\",.:;!|/()[]-\\", c) != nullptr)
      w += 5.5;  // ": 942/2048 em
    else
      w += 12;  // anything else: as wide as the widest
  }
  return w;
}

std::vector<std::string> wrap_caption(const std::string& text, double width_px) {
  return wrap_words(text, [width_px](const std::string& s) { return caption_width(s) <= width_px; });
}

std::string near_cap_svg(const NearCap& cap, const Camera& camera, const std::string& title) {
  const Frustum& fr = camera.frustum;
  // The near rectangle mapped onto the frame's pixel grid: x and y scaled
  // apart, so that the picture has the aspect of the frame's images.
  const double width_px = kNearCapSvgWidth;
  const double height_px = width_px * static_cast<double>(camera.height) / static_cast<double>(camera.width);
  const double x_scale = width_px / (fr.right - fr.left), y_scale = height_px / (fr.top - fr.bottom);
  const double rect_aspect = (fr.right - fr.left) / (fr.top - fr.bottom);
  const double pixel_aspect = static_cast<double>(camera.width) / static_cast<double>(camera.height);
  char note[200];
  if (std::fabs(rect_aspect / pixel_aspect - 1.0) > 1e-9)
    std::snprintf(note, sizeof note,
                  "drawn to the frame's aspect (%dx%d pixels); the near rectangle's own aspect is %.4g, so its "
                  "pixels are not square (pixel aspect %.4g)",
                  camera.width, camera.height, rect_aspect, rect_aspect / pixel_aspect);
  else
    std::snprintf(note, sizeof note, "drawn to the frame's aspect (%dx%d square pixels)", camera.width, camera.height);
  const std::vector<std::string> caption = wrap_caption(title + "; " + note, width_px - 2 * kCaptionMargin);
  const double line = 16.0, swatches = 40.0;
  const double legend = swatches + line * static_cast<double>(caption.size()) + 8.0;
  auto px = [&](const NearCapPoint& p) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3f,%.3f", (p.x.get_d() - fr.left) * x_scale, (fr.top - p.y.get_d()) * y_scale);
    return std::string(buf);
  };
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width_px << "\" height=\"" << height_px + legend
      << "\" viewBox=\"0 0 " << width_px << " " << height_px + legend << "\">\n";
  svg << "<title>" << escape(title) << "</title>\n";
  svg << "<rect id=\"near-rectangle\" x=\"0\" y=\"0\" width=\"" << width_px << "\" height=\"" << height_px
      << "\" fill=\"#ffffff\"/>\n";
  const std::size_t max_count = cap.max_count();
  for (const NearCapFace& f : cap.faces()) {
    svg << "<path fill-rule=\"evenodd\" fill=\"" << fill_for(f.count, max_count)
        << "\" stroke=\"#555555\" stroke-width=\"0.5\" d=\"";
    auto ring = [&](const std::vector<NearCapPoint>& r) {
      for (std::size_t k = 0; k < r.size(); ++k) svg << (k == 0 ? "M" : "L") << px(r[k]) << " ";
      svg << "Z ";
    };
    ring(f.outer);
    for (const auto& h : f.holes) ring(h);
    svg << "\"><title>count " << f.count << "</title></path>\n";
  }
  // Legend: one swatch per count, then the caption (the title and the
  // aspect), wrapped to the picture's width.
  svg << "<text x=\"" << kCaptionMargin << "\" y=\"" << height_px + 25
      << "\" font-family=\"sans-serif\" font-size=\"12\">near-cap count:</text>\n";
  for (std::size_t c = 0; c <= max_count && c < 12; ++c) {
    const double x = 110 + 50.0 * static_cast<double>(c);
    svg << "<rect x=\"" << x << "\" y=\"" << height_px + 12 << "\" width=\"18\" height=\"18\" fill=\""
        << fill_for(c, max_count) << "\" stroke=\"#555555\"/>";
    svg << "<text x=\"" << x + 23 << "\" y=\"" << height_px + 25 << "\" font-family=\"sans-serif\" font-size=\"12\">"
        << c << "</text>\n";
  }
  for (std::size_t k = 0; k < caption.size(); ++k)
    svg << "<text class=\"caption\" x=\"" << kCaptionMargin << "\" y=\""
        << height_px + swatches + 12 + line * static_cast<double>(k)
        << "\" font-family=\"sans-serif\" font-size=\"12\">" << escape(caption[k]) << "</text>\n";
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace nearcap
