#include "nearcap/numeric/vec3.hpp"

namespace nearcap {

Affine3d compose_rounded(const Affine3d& outer, const Affine3d& inner) {
  Affine3d r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double s = j == 3 ? outer.rows[i][3] : 0.0;
      for (int k = 0; k < 3; ++k) s += outer.rows[i][k] * inner.rows[k][j];
      r.rows[i][j] = s;
    }
  }
  return r;
}

}  // namespace nearcap
