// One-sided Jacobi SVD of a 4x4 matrix (see singular_values.hpp).
#include "nearcap/numeric/singular_values.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace nearcap {

std::array<double, 4> singular_values(const std::array<std::array<double, 4>, 4>& a) {
  // Work on the columns u_j of A: rotate pairs until every pair is orthogonal;
  // then the singular values are the column norms.
  std::array<std::array<double, 4>, 4> u{};  // u[j] = column j
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) u[c][r] = a[r][c];
  for (int sweep = 0; sweep < 60; ++sweep) {
    bool rotated = false;
    for (int p = 0; p < 3; ++p)
      for (int q = p + 1; q < 4; ++q) {
        double alpha = 0, beta = 0, gamma = 0;
        for (int r = 0; r < 4; ++r) {
          alpha += u[p][r] * u[p][r];
          beta += u[q][r] * u[q][r];
          gamma += u[p][r] * u[q][r];
        }
        if (gamma == 0 || std::fabs(gamma) <= 1e-17 * std::sqrt(alpha * beta)) continue;
        rotated = true;
        const double zeta = (beta - alpha) / (2 * gamma);
        const double t = std::copysign(1.0, zeta) / (std::fabs(zeta) + std::sqrt(1 + zeta * zeta));
        const double c = 1 / std::sqrt(1 + t * t), s = c * t;
        for (int r = 0; r < 4; ++r) {
          const double x = u[p][r], y = u[q][r];
          u[p][r] = c * x - s * y;
          u[q][r] = s * x + c * y;
        }
      }
    if (!rotated) break;
  }
  std::array<double, 4> sigma{};
  for (int j = 0; j < 4; ++j) sigma[j] = std::hypot(std::hypot(u[j][0], u[j][1]), std::hypot(u[j][2], u[j][3]));
  std::sort(sigma.begin(), sigma.end(), std::greater<>());
  return sigma;
}

double condition_number(const std::array<std::array<double, 4>, 4>& a) {
  for (const auto& row : a)
    for (double v : row)
      if (!std::isfinite(v)) return std::numeric_limits<double>::quiet_NaN();
  const std::array<double, 4> s = singular_values(a);
  if (s[3] == 0) return std::numeric_limits<double>::infinity();
  return s[0] / s[3];
}

}  // namespace nearcap
