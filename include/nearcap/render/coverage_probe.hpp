// nearcap/render/coverage_probe.hpp — which pixels a real GL rasterizer covers.
//
// Draws one triangle, given in GL window coordinates (pixels, y up), into an
// offscreen stencil buffer with increment-and-wrap and reads the counts back:
// the ground truth against which the emulated rasterizer (gl/rasterizer.hpp)
// is checked pixel for pixel, fill convention and sub-pixel snapping included.
// Needs a current context (EglContext).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "nearcap/gl/rasterizer.hpp"
#include "nearcap/render/gl_handle.hpp"

namespace nearcap::render {

class CoverageProbe {
 public:
  // A width x height framebuffer object (RGBA8 + DEPTH24_STENCIL8).  The
  // sizes must be powers of two, so that window coordinates on a 1/2^k grid
  // survive the round trip through normalized device coordinates exactly.
  CoverageProbe(int width, int height);
  ~CoverageProbe();
  CoverageProbe(const CoverageProbe&) = delete;
  CoverageProbe& operator=(const CoverageProbe&) = delete;

  // Per pixel (row-major, row 0 at the bottom), how many of `triangles` cover
  // it: stencil cleared to 0, every triangle drawn (no culling, no depth test)
  // with GL_INCR_WRAP on both faces.
  std::vector<std::uint8_t> coverage(const std::vector<std::array<gl::WindowVertex, 3>>& triangles);

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_, height_;
  OffscreenTarget target_;
  GlProgram program_;
};

}  // namespace nearcap::render
