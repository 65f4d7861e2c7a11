// nearcap/gl/rasterizer.hpp — triangle setup and coverage as llvmpipe does it.
//
// Input: window-space vertices in float32 (GL window coordinates, y up, after
// clipping, perspective divide and viewport).  Setup snaps x and y to fixed
// point with `subpixel_bits` fractional bits (round to nearest), computes the
// signed area from the snapped positions (zero: the triangle is dropped; its
// sign gives the facing, counter-clockwise = front as glFrontFace(GL_CCW)),
// and evaluates three 64-bit integer edge functions at pixel centres
// (i + 1/2, j + 1/2).  A centre exactly on an edge is covered when the edge is
// included by the fill rule, a setting whose default, bottom-left in GL window
// coordinates, is llvmpipe's for framebuffer objects (checked pixel for pixel
// through EGL by tests/llvmpipe_rasterizer_test.cpp).  Depth is interpolated linearly
// in window space from the three z values.
//
// Coverage is found row by row: on pixel row j each edge function is affine in
// the column i, so the covered columns form one span computed exactly in
// integers (no per-pixel test outside the triangle).  The cost is O(rows +
// covered pixels) per triangle, which matters for long shadow-volume sides.
// Snapped coordinates must stay below 2^30 in magnitude (products of
// differences then fit in 64 bits); the clipper's guard band keeps them there
// (pipeline.hpp), and a violation is an internal check failure.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>

#include "nearcap/check.hpp"
#include "nearcap/named_values.hpp"

namespace nearcap::gl {

struct WindowVertex {
  float x = 0, y = 0, z = 0;  // z in [0, 1] after the depth-range transform
};

enum class FillRule {
  TopLeft,     // horizontal edges with the interior below, and left edges (interior to the right)
  BottomLeft,  // horizontal edges with the interior above, and left edges: llvmpipe's, in GL window coordinates
};
inline constexpr NamedValue<FillRule> kFillRuleTable[] = {
    {FillRule::BottomLeft, "bottom-left", "llvmpipe's, GL window coordinates"},
    {FillRule::TopLeft, "top-left", ""},
};
constexpr const auto& named_values(FillRule) { return kFillRuleTable; }
static_assert(names_are_unique<FillRule>());

// The perspective divide and viewport transform's float32 arithmetic.
enum class ViewportArithmetic {
  Divide,    // x_w = (x / w + 1) (W / 2), z_w = (z / w) / 2 + 1/2: the spec's formula, each operation rounded
  Llvmpipe,  // Mesa's: r = 1 / w once; a vertex from the vertex stage gets
             // fma(x r, W/2, W/2) (llvmpipe's JIT fuses where the CPU has
             // FMA), a vertex the clipper made gets (x r) (W/2) + W/2
             // unfused (Mesa's C clipper); z alike with 1/2, 1/2
};
inline constexpr NamedValue<ViewportArithmetic> kViewportArithmeticTable[] = {
    {ViewportArithmetic::Divide, "divide", "(x/w + 1) W/2"},
    {ViewportArithmetic::Llvmpipe, "llvmpipe", "1/w, then fused multiply-add where Mesa fuses: what llvmpipe computes"},
};
constexpr const auto& named_values(ViewportArithmetic) { return kViewportArithmeticTable; }
static_assert(names_are_unique<ViewportArithmetic>());

// How a fragment's depth is computed from the triangle's three window z.
enum class DepthInterpolation {
  Exact,     // from the exact barycentrics of the snapped vertices, rounded
             // once to float32; 24-bit depth as lrint(z * (2^24 - 1)) in double
  Llvmpipe,  // Mesa's (22.3, lp_state_setup.c init_args/calc_coef4,
             // lp_bld_interp.c, lp_bld_depth.c): a float32 plane from the
             // unsnapped window vertices, v0 and v1 swapped for a
             // counter-clockwise triangle (their negative area), each
             // operation rounded: c = 1/2, dx01 = x0 - x1, dy01 = y0 - y1,
             // dx20 = x2 - x0, dy20 = y2 - y0, ooa = 1 / (dx01 dy20 - dy01 dx20),
             // dzdx = (z0 - z1)(dy20 ooa) - (z2 - z0)(dy01 ooa),
             // dzdy = (z2 - z0)(dx01 ooa) - (z0 - z1)(dx20 ooa),
             // a0 = z0 - (dzdx (x0 - c) + dzdy (y0 - c)); at pixel (i, j)
             // z = fma(dzdy, j, fma(dzdx, i, a0)) (llvm.fmuladd, fused where
             // the CPU has FMA), clamped to [0, 1]; 24-bit depth as
             // round-to-nearest-even of the float32 product z * (2^24 - 1)
};
inline constexpr NamedValue<DepthInterpolation> kDepthInterpolationTable[] = {
    {DepthInterpolation::Exact, "exact", "from exact barycentrics, rounded once"},
    {DepthInterpolation::Llvmpipe, "llvmpipe", "Mesa's float32 plane and 24-bit conversion"},
};
constexpr const auto& named_values(DepthInterpolation) { return kDepthInterpolationTable; }
static_assert(names_are_unique<DepthInterpolation>());

// The clipper's arithmetic, as RasterSettings::mesa_clipper holds it.
enum class ClipperArithmetic {
  Inside,  // clipping.hpp's clipper and fan: mesa_clipper = false
  Mesa,    // Mesa's plane order and fan: mesa_clipper = true
};
inline constexpr NamedValue<ClipperArithmetic> kClipperArithmeticTable[] = {
    {ClipperArithmetic::Inside, "inside", "intersections from the inside vertex"},
    {ClipperArithmetic::Mesa, "mesa", "Mesa's plane order, from the endpoint nearer the plane, its fan order"},
};
constexpr const auto& named_values(ClipperArithmetic) { return kClipperArithmeticTable; }
static_assert(names_are_unique<ClipperArithmetic>());

// The defaults are llvmpipe's (Mesa 22.3), as observed through a headless EGL
// context (tests/llvmpipe_rasterizer_test.cpp): 8 sub-pixel bits, pixel
// centres on a horizontal edge owned by the triangle above it (bottom-left in
// GL window coordinates, y up), and x, y clipped at the view volume.
struct RasterSettings {
  int subpixel_bits = 8;
  FillRule fill_rule = FillRule::BottomLeft;
  // x and y are clipped at |x|, |y| <= guard_band * w.  1: at the view volume,
  // as llvmpipe does; larger: a hardware-style guard band (the pipeline caps
  // it at safe_guard_band() so snapped coordinates stay in range).
  float guard_band = 1.0f;
  // Divide by default (the figures in the docs use it unless they name
  // llvmpipe's model); Llvmpipe is what Mesa computes
  // (render/gl_frame_replay.hpp measures the difference).
  ViewportArithmetic viewport = ViewportArithmetic::Divide;
  // Exact by default (as for the viewport above); Llvmpipe follows Mesa's
  // depth plane (render/gl_frame_replay.hpp measures the difference).
  DepthInterpolation depth = DepthInterpolation::Exact;
  // Mesa's clipper (ClipSettings::mesa) and its fan order for a clipped
  // polygon (emit_poly: triangle i is (v[i-1], v[i], v[0])); false: the
  // clipper of clipping.hpp and the fan (v[0], v[i-1], v[i]).
  bool mesa_clipper = false;
};

// The llvmpipe model: Mesa's viewport arithmetic, depth plane and clipper
// (`--viewport llvmpipe --depth-interpolation llvmpipe --clipper mesa`), under
// which the emulation draws what llvmpipe draws (render/gl_frame_replay.hpp
// measures it); the other settings of `s` are kept.
inline RasterSettings llvmpipe_model(RasterSettings s = {}) {
  s.viewport = ViewportArithmetic::Llvmpipe;
  s.depth = DepthInterpolation::Llvmpipe;
  s.mesa_clipper = true;
  return s;
}

// The float32 plane of a triangle's window z as llvmpipe sets it up
// (DepthInterpolation::Llvmpipe), for `v` in submission order.
struct LlvmpipeDepthPlane {
  float a0 = 0, dzdx = 0, dzdy = 0;
  float at(int i, int j) const {
    const float z = std::fma(dzdy, static_cast<float>(j), std::fma(dzdx, static_cast<float>(i), a0));
    return std::clamp(z + 0.0f, 0.0f, 1.0f);
  }
};
inline LlvmpipeDepthPlane llvmpipe_depth_plane(std::array<WindowVertex, 3> v, bool counter_clockwise) {
  if (counter_clockwise) std::swap(v[0], v[1]);
  const float c = 0.5f;
  const float x0c = v[0].x - c, y0c = v[0].y - c;
  const float dx01 = v[0].x - v[1].x, dy01 = v[0].y - v[1].y, dx20 = v[2].x - v[0].x, dy20 = v[2].y - v[0].y;
  const float e = dx01 * dy20, f = dy01 * dx20;
  const float ooa = 1.0f / (e - f);
  const float dx20o = dx20 * ooa, dy20o = dy20 * ooa, dx01o = dx01 * ooa, dy01o = dy01 * ooa;
  const float da01 = v[0].z - v[1].z, da20 = v[2].z - v[0].z;
  LlvmpipeDepthPlane p;
  p.dzdx = (da01 * dy20o) - (da20 * dy01o);
  p.dzdy = (da20 * dx01o) - (da01 * dx20o);
  p.a0 = v[0].z - ((p.dzdx * x0c) + (p.dzdy * y0c));
  return p;
}

struct Fragment {
  int x = 0, y = 0;  // pixel column, row from the bottom
  float depth = 0;
  bool front = true;
};

// The largest snapped coordinate magnitude the rasterizer accepts.
inline constexpr std::int64_t kMaxFixedCoordinate = std::int64_t{1} << 30;

namespace detail {

struct FixedPoint {
  std::int64_t x, y;
};

inline std::int64_t floor_div(std::int64_t n, std::int64_t d) {  // d > 0
  const std::int64_t q = n / d;
  return (n % d != 0 && n < 0) ? q - 1 : q;
}
inline std::int64_t ceil_div(std::int64_t n, std::int64_t d) { return -floor_div(-n, d); }  // d > 0
// floor(n / 2^bits) and ceil(n / 2^bits): an arithmetic shift rounds down.
static_assert((std::int64_t{-3} >> 1) == -2, "signed right shift must be arithmetic");
inline std::int64_t floor_shift(std::int64_t n, int bits) { return n >> bits; }
inline std::int64_t ceil_shift(std::int64_t n, int bits) { return -((-n) >> bits); }

inline FixedPoint snap(const WindowVertex& v, int bits) {
  const float scale = static_cast<float>(1 << bits);
  // lrintf: round to nearest (even) under the default rounding mode, as
  // llvmpipe's setup does with its float-to-fixed conversion.
  const FixedPoint p{std::lrintf(v.x * scale), std::lrintf(v.y * scale)};
  NEARCAP_CHECK(p.x > -kMaxFixedCoordinate && p.x < kMaxFixedCoordinate);
  NEARCAP_CHECK(p.y > -kMaxFixedCoordinate && p.y < kMaxFixedCoordinate);
  return p;
}

// Is the directed edge a -> b (of a counter-clockwise triangle, y up: the
// interior on its left) included when a pixel centre lies exactly on it?
inline bool edge_included(const FixedPoint& a, const FixedPoint& b, FillRule rule) {
  const std::int64_t dx = b.x - a.x, dy = b.y - a.y;
  const bool left = dy < 0;                                           // going down: the interior is to its right (+x)
  if (rule == FillRule::TopLeft) return left || (dy == 0 && dx < 0);  // horizontal, interior below
  return left || (dy == 0 && dx > 0);                                 // horizontal, interior above
}

}  // namespace detail

// The sign of the snapped area: +1 front (counter-clockwise), -1 back, 0 dropped.
inline int snapped_orientation(const std::array<WindowVertex, 3>& v, int subpixel_bits) {
  const detail::FixedPoint a = detail::snap(v[0], subpixel_bits), b = detail::snap(v[1], subpixel_bits),
                           c = detail::snap(v[2], subpixel_bits);
  const std::int64_t area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
  return (area > 0) - (area < 0);
}

// Calls `emit(const Fragment&)` for every covered pixel of the triangle inside
// [0, width) x [0, height), row by row from the bottom, left to right.
// Returns false when the triangle was dropped (zero snapped area).
// Only rows [row_begin, row_end) are visited when given (a band of the
// framebuffer: bands rasterized in parallel see each pixel's fragments in the
// same order as one pass over all rows).
template <class Emit>
bool rasterize_triangle_with(const std::array<WindowVertex, 3>& v, int width, int height,
                             const RasterSettings& settings, Emit&& emit, int row_begin = 0, int row_end = -1) {
  using detail::FixedPoint;
  const int bits = settings.subpixel_bits;
  std::array<FixedPoint, 3> p{detail::snap(v[0], bits), detail::snap(v[1], bits), detail::snap(v[2], bits)};
  std::array<float, 3> z{v[0].z, v[1].z, v[2].z};
  std::int64_t area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
  if (area == 0) return false;
  const bool front = area > 0;
  const bool llvmpipe_depth = settings.depth == DepthInterpolation::Llvmpipe;
  const LlvmpipeDepthPlane plane = llvmpipe_depth ? llvmpipe_depth_plane(v, front) : LlvmpipeDepthPlane{};
  if (!front) {  // make it counter-clockwise for coverage
    std::swap(p[1], p[2]);
    std::swap(z[1], z[2]);
    area = -area;
  }
  const std::int64_t one = std::int64_t{1} << bits, half = one >> 1;
  const std::int64_t min_y = std::min({p[0].y, p[1].y, p[2].y}), max_y = std::max({p[0].y, p[1].y, p[2].y});
  // Pixel j's centre is j * one + half: the candidate rows, and the columns
  // of the bounding box (a covered centre lies in the snapped triangle).
  const std::int64_t last_row = (row_end < 0 ? height : std::min(row_end, height)) - 1;
  const std::int64_t j0 = std::max<std::int64_t>(row_begin, detail::ceil_shift(min_y - half, bits));
  const std::int64_t j1 = std::min<std::int64_t>(last_row, detail::floor_shift(max_y - half, bits));
  if (j0 > j1) return true;
  const std::int64_t min_x = std::min({p[0].x, p[1].x, p[2].x}), max_x = std::max({p[0].x, p[1].x, p[2].x});
  const std::int64_t i0 = std::max<std::int64_t>(0, detail::ceil_shift(min_x - half, bits));
  const std::int64_t i1 = std::min<std::int64_t>(width - 1, detail::floor_shift(max_x - half, bits));
  if (i0 > i1) return true;
  // Edge k from p[k] to p[k+1]: e_k(i, j) = C_k(j) + B_k i with
  // B_k = -(b.y - a.y) one and C_k(j) = (b.x - a.x)(py - a.y) - (b.y - a.y)(half - a.x).
  // A pixel is covered when e_k >= threshold_k for all k (0 if the edge is
  // included by the fill rule, else 1: the edge functions are integers).
  std::array<std::int64_t, 3> B, threshold;
  for (int k = 0; k < 3; ++k) {
    const FixedPoint& a = p[k];
    const FixedPoint& b = p[(k + 1) % 3];
    B[k] = -(b.y - a.y) * one;
    threshold[k] = detail::edge_included(a, b, settings.fill_rule) ? 0 : 1;
  }
  const double inverse_area = 1.0 / static_cast<double>(area);
  // C_k at row j0, then one row up at a time: C_k(j + 1) = C_k(j) + (b.x - a.x) one.
  std::array<std::int64_t, 3> C, C_step;
  for (int k = 0; k < 3; ++k) {
    const FixedPoint& a = p[k];
    const FixedPoint& b = p[(k + 1) % 3];
    C[k] = (b.x - a.x) * (j0 * one + half - a.y) - (b.y - a.y) * (half - a.x);
    C_step[k] = (b.x - a.x) * one;
  }
  for (std::int64_t j = j0; j <= j1; ++j, C[0] += C_step[0], C[1] += C_step[1], C[2] += C_step[2]) {
    std::int64_t lo = i0, hi = i1;
    for (int k = 0; k < 3 && lo <= hi; ++k) {
      const std::int64_t need = threshold[k] - C[k];  // B i >= need
      if (B[k] > 0)
        lo = std::max(lo, detail::ceil_div(need, B[k]));
      else if (B[k] < 0)
        hi = std::min(hi, detail::floor_div(-need, -B[k]));
      else if (need > 0)
        hi = lo - 1;  // a horizontal edge with the row outside
    }
    if (llvmpipe_depth) {
      for (std::int64_t i = lo; i <= hi; ++i)
        emit(Fragment{static_cast<int>(i), static_cast<int>(j), plane.at(static_cast<int>(i), static_cast<int>(j)),
                      front});
      continue;
    }
    for (std::int64_t i = lo; i <= hi; ++i) {
      // Barycentric weight of vertex k is the edge function opposite to it.
      const double w0 = static_cast<double>(C[1] + B[1] * i), w1 = static_cast<double>(C[2] + B[2] * i),
                   w2 = static_cast<double>(C[0] + B[0] * i);
      const double depth = (w0 * z[0] + w1 * z[1] + w2 * z[2]) * inverse_area;
      emit(Fragment{static_cast<int>(i), static_cast<int>(j), static_cast<float>(depth), front});
    }
  }
  return true;
}

// The same through a std::function (tests, one-off callers).
bool rasterize_triangle(const std::array<WindowVertex, 3>& v, int width, int height, const RasterSettings& settings,
                        const std::function<void(const Fragment&)>& emit);

}  // namespace nearcap::gl
