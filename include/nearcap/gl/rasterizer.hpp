// nearcap/gl/rasterizer.hpp — triangle setup and coverage as llvmpipe does it.
//
// Input: window-space vertices in float32 (GL window coordinates, y up, after
// clipping, perspective divide and viewport).  Setup snaps x and y to fixed
// point with `subpixel_bits` fractional bits (round to nearest), computes the
// signed area from the snapped positions (zero: the triangle is dropped; its
// sign gives the facing, counter-clockwise = front as glFrontFace(GL_CCW)),
// and evaluates three 64-bit integer edge functions at pixel centres
// (i + 1/2, j + 1/2).  A centre exactly on an edge is covered when the edge is
// included by the fill rule; which rule llvmpipe applies to GL window
// coordinates depends on the framebuffer's orientation, so it is a setting
// (checked against the real renderer later).  Depth is interpolated linearly
// in window space from the three z values.
#pragma once

#include <array>
#include <cstdint>
#include <functional>

namespace nearcap::gl {

struct WindowVertex {
  float x = 0, y = 0, z = 0;  // z in [0, 1] after the depth-range transform
};

enum class FillRule {
  TopLeft,     // edges with the interior below (horizontal) or to the right are included
  BottomLeft,  // horizontal edges with the interior above, and left edges
};

struct RasterSettings {
  int subpixel_bits = 8;
  FillRule fill_rule = FillRule::TopLeft;
};

struct Fragment {
  int x = 0, y = 0;  // pixel column, row from the bottom
  float depth = 0;
  bool front = true;
};

// Calls `emit` for every covered pixel of the triangle inside [0, width) x
// [0, height).  Returns false when the triangle was dropped (zero snapped area).
bool rasterize_triangle(const std::array<WindowVertex, 3>& v, int width, int height, const RasterSettings& settings,
                        const std::function<void(const Fragment&)>& emit);

}  // namespace nearcap::gl
