// The inverse of an affine map applied to a point, in double, by the
// adjugate: what the work estimate (work_estimate.cpp) uses to put the light
// in an occluder's object space, where the mesh's face planes are.  Internal
// to the analysis layer; the tests include it to compare against it.
#pragma once

#include "nearcap/numeric/vec3.hpp"

namespace nearcap::analysis {

// x -> A^-1 (x - t) for the affine A x + t.  A must be invertible (the
// scene file refuses a singular object transform); each
// entry of the result is one cofactor sum over the determinant, so the
// result is the same bits wherever it is called.
inline Vec3d inverse_apply(const Affine3d& a, const Vec3d& p) {
  const auto& r = a.rows;
  const double m00 = r[1][1] * r[2][2] - r[1][2] * r[2][1], m01 = r[0][2] * r[2][1] - r[0][1] * r[2][2],
               m02 = r[0][1] * r[1][2] - r[0][2] * r[1][1];
  const double m10 = r[1][2] * r[2][0] - r[1][0] * r[2][2], m11 = r[0][0] * r[2][2] - r[0][2] * r[2][0],
               m12 = r[0][2] * r[1][0] - r[0][0] * r[1][2];
  const double m20 = r[1][0] * r[2][1] - r[1][1] * r[2][0], m21 = r[0][1] * r[2][0] - r[0][0] * r[2][1],
               m22 = r[0][0] * r[1][1] - r[0][1] * r[1][0];
  const double det = r[0][0] * m00 + r[0][1] * m10 + r[0][2] * m20;
  const Vec3d q{p.x - r[0][3], p.y - r[1][3], p.z - r[2][3]};
  return {(m00 * q.x + m01 * q.y + m02 * q.z) / det, (m10 * q.x + m11 * q.y + m12 * q.z) / det,
          (m20 * q.x + m21 * q.y + m22 * q.z) / det};
}

}  // namespace nearcap::analysis
