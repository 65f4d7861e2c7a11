// The emulated rasterizer (gl/rasterizer.hpp) against Mesa's llvmpipe, pixel
// for pixel, through a headless EGL context: coverage of triangles whose
// vertices lie on the half-pixel grid (so that many pixel centres fall exactly
// on edges, where only the fill convention decides) and on the 1/256-pixel
// grid (snapping), in both orientations.  This is the observable check of the
// fill rule the emulation assumes by default.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "llvmpipe_fixture.hpp"
#include "nearcap/error.hpp"
#include "nearcap/gl/clipping.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "nearcap/gl/rasterizer.hpp"
#include "nearcap/render/coverage_probe.hpp"
#include "nearcap/render/egl_context.hpp"

namespace nearcap {
namespace {

using gl::FillRule;
using gl::RasterSettings;
using gl::WindowVertex;
using Triangle = std::array<WindowVertex, 3>;

constexpr int kSize = 64;

std::vector<std::uint8_t> emulated(const std::vector<Triangle>& triangles, FillRule rule) {
  std::vector<std::uint8_t> counts(kSize * kSize, 0);
  RasterSettings settings;
  settings.fill_rule = rule;
  for (const Triangle& t : triangles)
    gl::rasterize_triangle(t, kSize, kSize, settings, [&](const gl::Fragment& f) { ++counts[f.y * kSize + f.x]; });
  return counts;
}

// Triangles with vertices on a grid of step 1/denominator pixels inside the
// framebuffer (and a little outside, to exercise the edges of the viewport).
std::vector<Triangle> random_triangles(std::mt19937& rng, int denominator, int count, int margin = 0) {
  std::uniform_int_distribution<int> coordinate(-margin * denominator, (kSize + margin) * denominator);
  std::vector<Triangle> triangles;
  for (int i = 0; i < count; ++i) {
    Triangle t;
    for (WindowVertex& v : t) {
      v.x = static_cast<float>(coordinate(rng)) / static_cast<float>(denominator);
      v.y = static_cast<float>(coordinate(rng)) / static_cast<float>(denominator);
    }
    triangles.push_back(t);
  }
  return triangles;
}

// Axis-aligned right triangles whose legs run through pixel centres: the
// horizontal and vertical edge cases of the fill rule, all four orientations.
std::vector<Triangle> centre_aligned_triangles() {
  std::vector<Triangle> triangles;
  for (float sx : {1.0f, -1.0f})
    for (float sy : {1.0f, -1.0f}) {
      const float cx = 32.5f, cy = 32.5f;
      triangles.push_back(
          {WindowVertex{cx, cy, 0}, WindowVertex{cx + sx * 10, cy, 0}, WindowVertex{cx, cy + sy * 10, 0}});
      triangles.push_back(
          {WindowVertex{cx, cy, 0}, WindowVertex{cx, cy + sy * 10, 0}, WindowVertex{cx + sx * 10, cy, 0}});
    }
  return triangles;
}

class LlvmpipeRasterizer : public test::LlvmpipeTest {};

// Describes the first pixel where two coverage images differ.
std::string first_difference(const Triangle& t, const std::vector<std::uint8_t>& real,
                             const std::vector<std::uint8_t>& emu) {
  for (int i = 0; i < kSize * kSize; ++i)
    if (real[i] != emu[i]) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "triangle (%.9g, %.9g) (%.9g, %.9g) (%.9g, %.9g): pixel (%d, %d) llvmpipe %d, emulation %d", t[0].x,
                    t[0].y, t[1].x, t[1].y, t[2].x, t[2].y, i % kSize, i / kSize, real[i], emu[i]);
      return text;
    }
  return {};
}

// Compares one triangle at a time; returns how many triangles differ and, in
// `example`, the first difference.
int mismatching_triangles(render::CoverageProbe& probe, const std::vector<Triangle>& triangles, FillRule rule,
                          std::string* example = nullptr) {
  int differing = 0;
  for (const Triangle& t : triangles) {
    const std::vector<std::uint8_t> real = probe.coverage({t}), emu = emulated({t}, rule);
    if (real == emu) continue;
    if (differing++ == 0 && example != nullptr) *example = first_difference(t, real, emu);
  }
  return differing;
}

TEST_F(LlvmpipeRasterizer, DefaultFillRuleMatchesPixelForPixel) {
  render::CoverageProbe probe(kSize, kSize);
  std::mt19937 rng(20261124);
  const FillRule default_rule = RasterSettings{}.fill_rule;
  const FillRule other_rule = default_rule == FillRule::TopLeft ? FillRule::BottomLeft : FillRule::TopLeft;

  const std::vector<Triangle> on_edges = random_triangles(rng, 2, 300);
  const std::vector<Triangle> snapped = random_triangles(rng, 256, 300);
  const std::vector<Triangle> aligned = centre_aligned_triangles();
  for (const auto* set : {&on_edges, &snapped, &aligned}) {
    std::string example;
    EXPECT_EQ(mismatching_triangles(probe, *set, default_rule, &example), 0) << example;
  }
  // The probe discriminates: the other convention disagrees with llvmpipe on
  // the triangles whose edges run through pixel centres.
  EXPECT_GT(mismatching_triangles(probe, on_edges, other_rule), 0);
  EXPECT_GT(mismatching_triangles(probe, aligned, other_rule), 0);
}

// The emulated clipper with guard band g, then the rasterizer, on triangles
// given in window coordinates (w = 1).
std::vector<std::uint8_t> clipped_then_emulated(const Triangle& t, float guard_band, FillRule rule) {
  std::array<gl::Vec4f, 3> clip;
  for (int k = 0; k < 3; ++k) clip[k] = {2.0f * t[k].x / kSize - 1.0f, 2.0f * t[k].y / kSize - 1.0f, 0.0f, 1.0f};
  gl::ClipSettings settings;
  settings.guard_band = guard_band;
  const std::vector<gl::Vec4f> polygon = gl::clip_triangle(clip[0], clip[1], clip[2], settings);
  std::vector<Triangle> fan;
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
    fan.push_back({gl::to_window(polygon[0], kSize, kSize), gl::to_window(polygon[i], kSize, kSize),
                   gl::to_window(polygon[i + 1], kSize, kSize)});
  return emulated(fan, rule);
}

TEST_F(LlvmpipeRasterizer, TrianglesCrossingTheViewportAreClippedAtTheViewVolume) {
  render::CoverageProbe probe(kSize, kSize);
  std::mt19937 rng(7);
  int differ_guard = 0, differ_clip = 0;
  std::string example;
  for (const Triangle& t : random_triangles(rng, 2, 300, 24)) {
    const std::vector<std::uint8_t> real = probe.coverage({t});
    if (real != clipped_then_emulated(t, 8192, RasterSettings{}.fill_rule)) ++differ_guard;
    const std::vector<std::uint8_t> clipped =
        clipped_then_emulated(t, RasterSettings{}.guard_band, RasterSettings{}.fill_rule);
    if (real != clipped && differ_clip++ == 0) example = first_difference(t, real, clipped);
  }
  // llvmpipe clips x and y at the view volume (the default guard band, 1):
  // every triangle matches; with a wide guard band some do not, because the
  // clipped polygon's new vertices are rounded and move its edges.
  EXPECT_EQ(RasterSettings{}.guard_band, 1.0f);
  EXPECT_EQ(differ_clip, 0) << example;
  EXPECT_GT(differ_guard, 0);
}

TEST_F(LlvmpipeRasterizer, SharedEdgesAreDrawnOnceByBoth) {
  // A fan of triangles around a centre on the half-pixel grid: llvmpipe and
  // the emulation both cover every pixel of the fan's hull exactly once.
  render::CoverageProbe probe(kSize, kSize);
  std::vector<Triangle> fan;
  const WindowVertex c{32.5f, 31.5f, 0};
  const std::array<WindowVertex, 6> ring{WindowVertex{52.5f, 31.5f, 0},
                                         {42.5f, 50.5f, 0},
                                         {20.5f, 52.5f, 0},
                                         {10.5f, 31.5f, 0},
                                         {22.5f, 10.5f, 0},
                                         {44.5f, 12.5f, 0}};
  for (std::size_t i = 0; i < ring.size(); ++i) fan.push_back({c, ring[i], ring[(i + 1) % ring.size()]});
  const std::vector<std::uint8_t> real = probe.coverage(fan);
  EXPECT_EQ(real, emulated(fan, RasterSettings{}.fill_rule));
  int covered = 0;
  for (std::uint8_t n : real) {
    EXPECT_LE(n, 1);
    covered += n;
  }
  EXPECT_GT(covered, 800);
}

}  // namespace
}  // namespace nearcap
