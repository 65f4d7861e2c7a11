// SVG rendering of a near-cap arrangement.
#include "nearcap/judge/near_cap_svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

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

std::string near_cap_svg(const NearCap& cap, const Camera& camera, const std::string& title) {
  const Frustum& fr = camera.frustum;
  const double width_px = 800.0;
  const double scale = width_px / (fr.right - fr.left);
  const double height_px = (fr.top - fr.bottom) * scale;
  const double legend = 64.0;
  auto px = [&](const NearCapPoint& p) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3f,%.3f", (p.x.get_d() - fr.left) * scale, (fr.top - p.y.get_d()) * scale);
    return std::string(buf);
  };
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width_px << "\" height=\"" << height_px + legend
      << "\" viewBox=\"0 0 " << width_px << " " << height_px + legend << "\">\n";
  svg << "<title>" << escape(title) << "</title>\n";
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
  // Legend: one swatch per count, then the title, and the pixel aspect.
  svg << "<text x=\"10\" y=\"" << height_px + 25
      << "\" font-family=\"sans-serif\" font-size=\"12\">near-cap count:</text>\n";
  for (std::size_t c = 0; c <= max_count && c < 12; ++c) {
    const double x = 110 + 50.0 * static_cast<double>(c);
    svg << "<rect x=\"" << x << "\" y=\"" << height_px + 12 << "\" width=\"18\" height=\"18\" fill=\""
        << fill_for(c, max_count) << "\" stroke=\"#555555\"/>";
    svg << "<text x=\"" << x + 23 << "\" y=\"" << height_px + 25 << "\" font-family=\"sans-serif\" font-size=\"12\">"
        << c << "</text>\n";
  }
  const double rect_aspect = (fr.right - fr.left) / (fr.top - fr.bottom);
  const double pixel_aspect = static_cast<double>(camera.width) / static_cast<double>(camera.height);
  char note[200];
  if (std::fabs(rect_aspect / pixel_aspect - 1.0) > 1e-9)
    std::snprintf(note, sizeof note,
                  "drawn to the near rectangle's aspect %.4g; the %dx%d pixels are not square (pixel aspect %.4g)",
                  rect_aspect, camera.width, camera.height, rect_aspect / pixel_aspect);
  else
    std::snprintf(note, sizeof note, "drawn to the near rectangle's aspect %.4g (%dx%d square pixels)", rect_aspect,
                  camera.width, camera.height);
  svg << "<text x=\"10\" y=\"" << height_px + 52 << "\" font-family=\"sans-serif\" font-size=\"12\">" << escape(title)
      << "; " << note << "</text>\n";
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace nearcap
