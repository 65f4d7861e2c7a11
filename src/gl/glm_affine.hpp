// An Affine3d (numeric/vec3.hpp: three rows of [linear | translation]) as a
// glm 4x4 matrix: column-major (m[column][row]), bottom row 0 0 0 1.  In
// double, exactly; or each entry rounded to float32 once, as an engine
// uploads it.  Private to the library's sources (glm is no public
// dependency).
#pragma once

#include <glm/glm.hpp>

#include "nearcap/numeric/vec3.hpp"

namespace nearcap::gl {

inline glm::dmat4 to_glm(const Affine3d& a) {
  glm::dmat4 m(1.0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = a.rows[r][c];
  return m;
}

inline glm::mat4 to_glm_float(const Affine3d& a) { return glm::mat4(to_glm(a)); }

}  // namespace nearcap::gl
