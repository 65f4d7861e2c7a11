// Fixed-point triangle rasterization (see rasterizer.hpp).
#include "nearcap/gl/rasterizer.hpp"

namespace nearcap::gl {

bool rasterize_triangle(const std::array<WindowVertex, 3>& v, int width, int height, const RasterSettings& settings,
                        const std::function<void(const Fragment&)>& emit) {
  return rasterize_triangle_with(v, width, height, settings, emit);
}

}  // namespace nearcap::gl
