// The sign of an affine form over a square of the near plane, decided from
// one bounded evaluation at the square's centre (the crack distance's proofs,
// crack_distance.cpp: most of their forms are decided here, the rest corner
// by corner).
//
// The square's corners are its centre C plus (+-hx, +-hy, 0), so the form
// f(P) = h . P + h0 takes at its corners exactly the values
// f(C) +- h_x hx +- h_y hy: an affine form's extremes over the square, at its
// corners.  With s an upper bound of |h_x| hx + |h_y| hy, every corner lies in
// f(C) +- s; with a lower bound, the largest corner is at least f(C) + s and
// the smallest at most f(C) - s.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/perturbation.hpp"
#include "nearcap/numeric/bounded_double.hpp"
#include "nearcap/numeric/sign.hpp"

namespace nearcap {

// Positive or Negative: the form has that strict sign at every corner (so
// over the whole square); Zero: two corners certainly have opposite strict
// signs; nothing: not decided, test the corners.  `centre`, `half_x` and
// `half_y` enclose the exact centre and half-sides; `form` encloses the exact
// form (each coefficient within its bound).
inline std::optional<Sign> square_sign_filter(const AffineForm<BoundedDouble>& form, const BoundedVec3& centre,
                                              const BoundedDouble& half_x, const BoundedDouble& half_y) {
  const BoundedDouble at_centre = form.at(centre);
  auto most = [](const BoundedDouble& x) { return std::fabs(x.v) + x.e; };
  auto least = [](const BoundedDouble& x) { return std::max(0.0, std::fabs(x.v) - x.e); };
  // Two products and a sum, each rounded by at most 2^-53 relative: 2^-50
  // covers them, up for the upper bound and down for the lower.
  const double upper =
      (most(form.h.x) * most(half_x) + most(form.h.y) * most(half_y)) * (1.0 + 0x1p-50) + BoundedDouble::kUnderflow;
  const double lower = (least(form.h.x) * least(half_x) + least(form.h.y) * least(half_y)) * (1.0 - 0x1p-50);
  if (const auto s = BoundedDouble(at_centre.v, at_centre.e + upper).sign(); s && *s != Sign::Zero) return s;
  // f(C) + lower > 0 and f(C) - lower < 0 for every f(C) within its bound:
  // at_centre.v - e + lower > 0 and at_centre.v + e - lower < 0, each sum
  // computed with a margin for its own rounding.
  const double e = at_centre.e * BoundedDouble::kBoundSlack;
  const double margin = 0x1p-50 * (std::fabs(at_centre.v) + e + lower) + BoundedDouble::kUnderflow;
  if (at_centre.v - e + lower - margin > 0 && at_centre.v + e - lower + margin < 0) return Sign::Zero;
  return std::nullopt;
}

}  // namespace nearcap
