// Float32 matrices and the vertex transform (see float_transforms.hpp).
#include "nearcap/gl/float_transforms.hpp"

#include <cmath>
#include <string>

#include "float_transform_inline.hpp"
#include "nearcap/error.hpp"

namespace nearcap::gl {
namespace {

using inline_transform::dot4;

}  // namespace

Mat4f to_mat4f(const Affine3d& a) {
  Mat4f m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m.at(r, c) = static_cast<float>(a.rows[r][c]);
  m.at(3, 3) = 1.0f;
  return m;
}

Mat4f frustum_matrix(const Frustum& f, DepthMapping mapping) {
  Mat4f m;
  m.at(0, 0) = static_cast<float>(2 * f.near / (f.right - f.left));
  m.at(0, 2) = static_cast<float>((f.right + f.left) / (f.right - f.left));
  m.at(1, 1) = static_cast<float>(2 * f.near / (f.top - f.bottom));
  m.at(1, 2) = static_cast<float>((f.top + f.bottom) / (f.top - f.bottom));
  m.at(2, 2) = static_cast<float>(-(f.far + f.near) / (f.far - f.near));
  m.at(2, 3) = static_cast<float>(-2 * f.far * f.near / (f.far - f.near));
  if (mapping == DepthMapping::Reversed) {
    m.at(2, 2) = static_cast<float>(f.near / (f.far - f.near));
    m.at(2, 3) = static_cast<float>(f.far * f.near / (f.far - f.near));
  }
  m.at(3, 2) = -1.0f;
  return m;
}

Mat4f infinite_frustum_matrix(const Frustum& f, InfiniteFar nudge, DepthMapping mapping) {
  Mat4f m = frustum_matrix(f);
  if (mapping == DepthMapping::Reversed) {
    if (nudge != InfiniteFar::Exact)
      throw Error(ErrorKind::Usage, "--infinite-far " + std::string(to_string(nudge)) +
                                        " nudges the standard depth row; the reversed mapping puts infinity at depth "
                                        "0 exactly (use --infinite-far exact)");
    m.at(2, 2) = 0.0f;
    m.at(2, 3) = static_cast<float>(f.near);
    return m;
  }
  double zz = -1, zw = -2 * f.near;
  switch (nudge) {
    case InfiniteFar::Exact:
      break;
    case InfiniteFar::Epsilon: {
      const double eps = std::ldexp(1.0, -22);
      zz = eps - 1;
      zw = (eps - 2) * f.near;
      break;
    }
    case InfiniteFar::Doom3:
      zz = -0.999;
      break;
    case InfiniteFar::OneUlp:
      zz = -(1 - std::ldexp(1.0, -23));
      break;
  }
  m.at(2, 2) = static_cast<float>(zz);
  m.at(2, 3) = static_cast<float>(zw);
  return m;
}

Mat4f multiply(const Mat4f& a, const Mat4f& b, Arithmetic arithmetic) {
  Mat4f out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      const float row[4] = {a.at(r, 0), a.at(r, 1), a.at(r, 2), a.at(r, 3)};
      const float col[4] = {b.at(0, c), b.at(1, c), b.at(2, c), b.at(3, c)};
      out.at(r, c) = dot4(row, col, arithmetic);
    }
  return out;
}

float transform_row(const Mat4f& m, int r, const Vec4f& v, Arithmetic arithmetic) {
  return inline_transform::transform_row(m, r, v, arithmetic);
}

Vec4f transform(const Mat4f& m, const Vec4f& v, Arithmetic arithmetic) {
  return inline_transform::transform(m, v, arithmetic);
}

}  // namespace nearcap::gl
