// Fixed-point triangle rasterization (see rasterizer.hpp).
#include "nearcap/gl/rasterizer.hpp"

#include <algorithm>
#include <cmath>

namespace nearcap::gl {
namespace {

struct FixedPoint {
  std::int64_t x, y;
};

FixedPoint snap(const WindowVertex& v, int bits) {
  const float scale = static_cast<float>(1 << bits);
  // lrintf: round to nearest (even) under the default rounding mode, as
  // llvmpipe's setup does with its float-to-fixed conversion.
  return {std::lrintf(v.x * scale), std::lrintf(v.y * scale)};
}

// Is the directed edge a -> b (of a counter-clockwise triangle, y up: the
// interior on its left) included when a pixel centre lies exactly on it?
bool edge_included(const FixedPoint& a, const FixedPoint& b, FillRule rule) {
  const std::int64_t dx = b.x - a.x, dy = b.y - a.y;
  const bool left = dy < 0;                                           // going down: the interior is to its right (+x)
  if (rule == FillRule::TopLeft) return left || (dy == 0 && dx < 0);  // horizontal, interior below
  return left || (dy == 0 && dx > 0);                                 // horizontal, interior above
}

}  // namespace

bool rasterize_triangle(const std::array<WindowVertex, 3>& v, int width, int height, const RasterSettings& settings,
                        const std::function<void(const Fragment&)>& emit) {
  const int bits = settings.subpixel_bits;
  std::array<FixedPoint, 3> p{snap(v[0], bits), snap(v[1], bits), snap(v[2], bits)};
  std::array<float, 3> z{v[0].z, v[1].z, v[2].z};
  std::int64_t area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
  if (area == 0) return false;
  const bool front = area > 0;
  if (!front) {  // make it counter-clockwise for coverage
    std::swap(p[1], p[2]);
    std::swap(z[1], z[2]);
    area = -area;
  }
  const std::int64_t one = std::int64_t{1} << bits, half = one >> 1;
  const std::int64_t min_x = std::min({p[0].x, p[1].x, p[2].x}), max_x = std::max({p[0].x, p[1].x, p[2].x});
  const std::int64_t min_y = std::min({p[0].y, p[1].y, p[2].y}), max_y = std::max({p[0].y, p[1].y, p[2].y});
  // Pixel i's centre is i * one + half: the candidate columns and rows.
  auto first_pixel = [&](std::int64_t lo) { return (lo - half + one - 1) >> bits; };  // ceil((lo - half) / one)
  auto last_pixel = [&](std::int64_t hi) { return (hi - half) >> bits; };             // floor((hi - half) / one)
  const std::int64_t i0 = std::max<std::int64_t>(0, first_pixel(min_x));
  const std::int64_t i1 = std::min<std::int64_t>(width - 1, last_pixel(max_x));
  const std::int64_t j0 = std::max<std::int64_t>(0, first_pixel(min_y));
  const std::int64_t j1 = std::min<std::int64_t>(height - 1, last_pixel(max_y));
  std::array<bool, 3> included;
  for (int k = 0; k < 3; ++k) included[k] = edge_included(p[k], p[(k + 1) % 3], settings.fill_rule);
  for (std::int64_t j = j0; j <= j1; ++j) {
    const std::int64_t py = j * one + half;
    for (std::int64_t i = i0; i <= i1; ++i) {
      const std::int64_t px = i * one + half;
      std::array<std::int64_t, 3> e;
      bool inside = true;
      for (int k = 0; k < 3 && inside; ++k) {
        const FixedPoint& a = p[k];
        const FixedPoint& b = p[(k + 1) % 3];
        e[k] = (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
        inside = e[k] > 0 || (e[k] == 0 && included[k]);
      }
      if (!inside) continue;
      // Barycentric weight of vertex k is the edge function opposite to it.
      const double w0 = static_cast<double>(e[1]), w1 = static_cast<double>(e[2]), w2 = static_cast<double>(e[0]);
      const double depth = (w0 * z[0] + w1 * z[1] + w2 * z[2]) / static_cast<double>(area);
      emit(Fragment{static_cast<int>(i), static_cast<int>(j), static_cast<float>(depth), front});
    }
  }
  return true;
}

}  // namespace nearcap::gl
