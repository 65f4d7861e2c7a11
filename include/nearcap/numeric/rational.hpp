// nearcap/numeric/rational.hpp — the exact number type of nearcap's exact paths.
//
// GMP's mpq_class: exact rationals, the same arithmetic CGAL's Exact_rational
// wraps (CGAL::Gmpq), but a header that costs a tenth of a second to compile
// instead of two and a half.  Every double is exactly a rational, so a scene's
// numbers enter exact arithmetic without rounding (docs/scene-format.md, "Exactness convention").
#pragma once

#include <gmpxx.h>

#include <cmath>
#include <limits>
#include <string>

#include "nearcap/numeric/bounded_double.hpp"
#include "nearcap/numeric/sign.hpp"
#include "nearcap/numeric/vec3.hpp"

namespace nearcap {

using Rational = mpq_class;

inline Sign sign_of(const Rational& q) { return static_cast<Sign>(sgn(q)); }
inline Vec3<Rational> to_rational(const Vec3d& p) { return {Rational(p.x), Rational(p.y), Rational(p.z)}; }
// "p/q" in lowest terms ("3/4", "-5", "0").
inline std::string to_string(const Rational& q) { return q.get_str(); }
inline double to_double(const Rational& q) { return q.get_d(); }  // truncation toward zero (GMP)
// A certified estimate of q: get_d truncates, so the error is below one ulp.
inline BoundedDouble bounded_estimate(const Rational& q) {
  const double v = q.get_d();
  return BoundedDouble(v, std::fabs(v) * 0x1p-52 + std::numeric_limits<double>::denorm_min());
}

}  // namespace nearcap
