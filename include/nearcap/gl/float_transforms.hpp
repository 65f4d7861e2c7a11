// nearcap/gl/float_transforms.hpp — the camera's matrices as a GL application
// uploads them: float32, column-major, and the float32 vertex transform with
// the operation order a GPU uses (optionally fused multiply-add).
//
// Part of the float pipeline (issue 3): everything here rounds, on purpose.
#pragma once

#include <array>
#include <optional>
#include <string_view>

#include "nearcap/named_values.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::gl {

// Column-major 4x4, as glUniformMatrix4fv takes it: m[4 * column + row].
struct Mat4f {
  std::array<float, 16> m{};
  float at(int row, int column) const { return m[4 * column + row]; }
  float& at(int row, int column) { return m[4 * column + row]; }
};

struct Vec4f {
  float x = 0, y = 0, z = 0, w = 1;
};

// How products are summed: separately rounded (the reference order
// x*m0 + y*m1 + z*m2 + w*m3, left to right) or fused (fma chains).
enum class Arithmetic { Separate, Fused };

// An affine double map rounded entry by entry to float32.
Mat4f to_mat4f(const Affine3d& a);

// How the camera's depth leaves clip space:
//   standard  GL's default, glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE):
//             the near plane is z = -w, the far plane z = w, window depth
//             z_w = (z/w) / 2 + 1/2: near 0, far 1, tested GL_LESS;
//   reversed  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) with a projection
//             whose depth row sends the near plane to 1 and the far plane
//             (or infinity) to 0: the near plane is z = w, the far plane
//             z = 0, z_w = z/w, cleared to 0, tested GL_GREATER.  With a
//             float depth buffer the dense floats near 0 meet the distant
//             depths, which a near plane far below the scene's size pushes
//             towards 1 in the standard mapping (Reed 2015; Lapidous and
//             Jiao 1999).
enum class DepthMapping { Standard, Reversed };
inline constexpr NamedValue<DepthMapping> kDepthMappingTable[] = {
    {DepthMapping::Standard, "standard", "GL's -1..1 clip depth, near at 0, GL_LESS"},
    {DepthMapping::Reversed, "reversed",
     "glClipControl GL_ZERO_TO_ONE, near at 1, far or infinity at 0, GL_GREATER: with --depth float32, reversed-Z"},
};
constexpr const auto& named_values(DepthMapping) { return kDepthMappingTable; }
static_assert(names_are_unique<DepthMapping>());
inline std::string_view to_string(DepthMapping m) { return name_of(m); }
inline std::optional<DepthMapping> depth_mapping_from_string(std::string_view name) {
  return value_named<DepthMapping>(name);
}

// glFrustum(left, right, bottom, top, near, far), computed in double and
// rounded to float32 (what an application computing in double uploads).
// Reversed: the depth row (0, 0, n/(f-n), f n/(f-n)), so that z/w is 1 at
// the near plane and 0 at the far one.
Mat4f frustum_matrix(const Frustum& f, DepthMapping mapping = DepthMapping::Standard);
// The far plane at infinity (Everitt and Kilgard 2002), with the nudges
// shipped code puts in its depth row so that w = 0 vertices land just
// inside the far plane instead of on it (where rounding could clip them):
//   exact    z_clip = -z - 2n: a point at infinity has z = w, depth 1;
//   epsilon  (eps - 1) z + (eps - 2) n, eps = 2^-22 (Everitt and Kilgard's
//            and Lengyel's epsilon for 24-bit depth): depth 1 - eps/2 there;
//   doom3    -0.999 z - 2n (Doom 3 and BFG, "crunches the Z range slightly
//            so w=0 vertexes do not rasterize right at the wraparound point");
//   one-ulp  -(1 - 2^-23) z - 2n: the smallest float32 nudge below -1.
// Every finite point's depth moves too (the nudged rows are not the exact
// projection's): the choice trades depth at infinity for depth precision.
// Reversed: the depth row (0, 0, 0, n): z = n w_eye, z/w = n / -z_eye, 1 at
// the near plane and exactly 0 at infinity (the far plane z = 0, which
// clipping keeps); the nudges are the standard row's and are refused there
// (Error(Usage)).
enum class InfiniteFar { Exact, Epsilon, Doom3, OneUlp };
inline constexpr NamedValue<InfiniteFar> kInfiniteFarTable[] = {
    {InfiniteFar::Exact, "exact", "-1, -2 near"},
    {InfiniteFar::Epsilon, "epsilon", "Everitt and Kilgard's 2^-22 margin"},
    {InfiniteFar::Doom3, "doom3", "-0.999"},
    {InfiniteFar::OneUlp, "one-ulp", "-(1 - 2^-23)"},
};
constexpr const auto& named_values(InfiniteFar) { return kInfiniteFarTable; }
static_assert(names_are_unique<InfiniteFar>());
inline std::string_view to_string(InfiniteFar f) { return name_of(f); }
inline std::optional<InfiniteFar> infinite_far_from_string(std::string_view name) {
  return value_named<InfiniteFar>(name);
}
Mat4f infinite_frustum_matrix(const Frustum& f, InfiniteFar nudge = InfiniteFar::Exact,
                              DepthMapping mapping = DepthMapping::Standard);
// a * b in float32 (each entry a dot product in the reference order).
Mat4f multiply(const Mat4f& a, const Mat4f& b, Arithmetic arithmetic = Arithmetic::Separate);

Vec4f transform(const Mat4f& m, const Vec4f& v, Arithmetic arithmetic = Arithmetic::Separate);
// One row of transform(m, v), bit for bit (row 0 to 3: x, y, z, w).
float transform_row(const Mat4f& m, int row, const Vec4f& v, Arithmetic arithmetic = Arithmetic::Separate);

}  // namespace nearcap::gl
