// nearcap/gl/float_transforms.hpp — the camera's matrices as a GL application
// uploads them: float32, column-major, and the float32 vertex transform with
// the operation order a GPU uses (optionally fused multiply-add).
//
// Part of the float pipeline (issue 3): everything here rounds, on purpose.
#pragma once

#include <array>

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
// glFrustum(left, right, bottom, top, near, far), computed in double and
// rounded to float32 (what an application computing in double uploads).
Mat4f frustum_matrix(const Frustum& f);
// The same with the far plane at infinity (Everitt and Kilgard 2002).
Mat4f infinite_frustum_matrix(const Frustum& f);
// a * b in float32 (each entry a dot product in the reference order).
Mat4f multiply(const Mat4f& a, const Mat4f& b, Arithmetic arithmetic = Arithmetic::Separate);

Vec4f transform(const Mat4f& m, const Vec4f& v, Arithmetic arithmetic = Arithmetic::Separate);
// One row of transform(m, v), bit for bit (row 0 to 3: x, y, z, w).
float transform_row(const Mat4f& m, int row, const Vec4f& v, Arithmetic arithmetic = Arithmetic::Separate);

}  // namespace nearcap::gl
