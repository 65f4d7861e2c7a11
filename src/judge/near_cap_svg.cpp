// SVG rendering of a near-cap arrangement.
#include "nearcap/judge/near_cap_svg.hpp"

#include <algorithm>
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

std::string near_cap_svg(const NearCap& cap, const Frustum& fr, const std::string& title) {
  const double width_px = 800.0;
  const double scale = width_px / (fr.right - fr.left);
  const double height_px = (fr.top - fr.bottom) * scale;
  const double legend = 40.0;
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
  // Legend: one swatch per count.
  for (std::size_t c = 0; c <= max_count && c < 16; ++c) {
    const double x = 10 + 60.0 * static_cast<double>(c);
    svg << "<rect x=\"" << x << "\" y=\"" << height_px + 10 << "\" width=\"20\" height=\"20\" fill=\""
        << fill_for(c, max_count) << "\" stroke=\"#555555\"/>";
    svg << "<text x=\"" << x + 25 << "\" y=\"" << height_px + 25 << "\" font-family=\"sans-serif\" font-size=\"12\">"
        << c << "</text>\n";
  }
  svg << "<text x=\"" << width_px - 10 << "\" y=\"" << height_px + 25
      << "\" text-anchor=\"end\" font-family=\"sans-serif\" font-size=\"12\">" << escape(title) << "</text>\n";
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace nearcap
