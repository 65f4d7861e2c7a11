// nearcap/numeric/singular_values.hpp — singular values and the 2-norm
// condition number of a small dense matrix (the 4x4 matrices of the float
// pipeline), by one-sided Jacobi rotations (Hestenes' method): accurate to a
// few ulps relative to each singular value, also for ill-conditioned
// matrices, which is what a conditioning feature needs (forming A^T A would
// square the condition number and lose the small singular values).
#pragma once

#include <array>
#include <cstddef>

namespace nearcap {

// The singular values of the 4x4 matrix a (row-major a[row][column]), largest first.
std::array<double, 4> singular_values(const std::array<std::array<double, 4>, 4>& a);

// sigma_max / sigma_min; infinity for a singular matrix, NaN when an entry is not finite.
double condition_number(const std::array<std::array<double, 4>, 4>& a);

}  // namespace nearcap
