// gl/float_transform_inline.hpp — the float32 vertex transform
// (float_transforms.hpp's transform), defined where its callers can inline
// it: the vertex programs run it for every vertex of every draw, where a call
// per row costs as much as the row (private to gl/; not installed).
//
// Only for nearcap's own translation units, which are compiled with
// -ffp-contract=off: a compiler allowed to contract x*y + z into one fused
// operation would compute other bits than the reference order below.
#pragma once

#include <cmath>

#include "nearcap/gl/float_transforms.hpp"

namespace nearcap::gl::inline_transform {

// One row's dot product: separately rounded left to right, or an fma chain.
inline float dot4(const float a[4], const float b[4], Arithmetic arithmetic) {
  if (arithmetic == Arithmetic::Fused) {
    float r = a[0] * b[0];
    r = std::fmaf(a[1], b[1], r);
    r = std::fmaf(a[2], b[2], r);
    return std::fmaf(a[3], b[3], r);
  }
  float r = a[0] * b[0];
  r = r + a[1] * b[1];
  r = r + a[2] * b[2];
  return r + a[3] * b[3];
}

inline float transform_row(const Mat4f& m, int r, const Vec4f& v, Arithmetic arithmetic) {
  const float in[4] = {v.x, v.y, v.z, v.w};
  const float row[4] = {m.at(r, 0), m.at(r, 1), m.at(r, 2), m.at(r, 3)};
  return inline_transform::dot4(row, in, arithmetic);
}

inline Vec4f transform(const Mat4f& m, const Vec4f& v, Arithmetic arithmetic) {
  if (arithmetic == Arithmetic::Fused)
    return {inline_transform::transform_row(m, 0, v, arithmetic), inline_transform::transform_row(m, 1, v, arithmetic),
            inline_transform::transform_row(m, 2, v, arithmetic), inline_transform::transform_row(m, 3, v, arithmetic)};
  // Separately rounded, column by column (Mat4f stores columns): row r's
  // lane sees dot4's operations in dot4's order, and the four rows can run
  // as one vector operation per column.
  const float in[4] = {v.x, v.y, v.z, v.w};
  float r[4];
  for (int row = 0; row < 4; ++row) r[row] = m.m[row] * in[0];
  for (int column = 1; column < 4; ++column)
    for (int row = 0; row < 4; ++row) r[row] = r[row] + m.m[4 * column + row] * in[column];
  return {r[0], r[1], r[2], r[3]};
}

}  // namespace nearcap::gl::inline_transform
