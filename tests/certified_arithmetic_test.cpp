// BoundedDouble soundness: for exact double inputs, every result's certified
// interval holds the exact rational result, and a sign it reports is the exact
// sign, also for expressions built to cancel (determinants of nearly parallel
// vectors), the case the filters exist for.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

#include "nearcap/bounded_double.hpp"
#include "nearcap/rational.hpp"
#include "nearcap/vec3.hpp"

namespace nearcap {
namespace {

// A double of moderate magnitude with a full random mantissa.
rc::Gen<double> moderate_double() {
  return rc::gen::map(
      rc::gen::tuple(rc::gen::inRange<std::int64_t>(-(1LL << 53), 1LL << 53), rc::gen::inRange(-40, 41)),
      [](const std::tuple<std::int64_t, int>& t) {
        return std::ldexp(static_cast<double>(std::get<0>(t)), std::get<1>(t) - 53);
      });
}

bool contains(const BoundedDouble& b, const Rational& exact) {
  const Rational diff = Rational(b.v) - exact;
  return abs(diff) <= Rational(b.e);
}

Sign exact_sign(const Rational& r) { return sign_of(r); }

RC_GTEST_PROP(BoundedDouble, ArithmeticEnclosesTheExactResult, ()) {
  const double a = *moderate_double(), b = *moderate_double();
  const Rational qa(a), qb(b);
  RC_ASSERT(contains(BoundedDouble(a) + BoundedDouble(b), qa + qb));
  RC_ASSERT(contains(BoundedDouble(a) - BoundedDouble(b), qa - qb));
  RC_ASSERT(contains(BoundedDouble(a) * BoundedDouble(b), qa * qb));
  if (b != 0) RC_ASSERT(contains(BoundedDouble(a) / BoundedDouble(b), qa / qb));
}

RC_GTEST_PROP(BoundedDouble, DeterminantSignIsNeverWrong, ()) {
  // Nearly parallel rows: the second is the first scaled, plus a tiny nudge.
  const double x = *moderate_double(), y = *moderate_double(), z = *moderate_double();
  const int scale_exp = *rc::gen::inRange(-3, 4);
  const double nudge = std::ldexp(static_cast<double>(*rc::gen::inRange(-2, 3)), *rc::gen::inRange(-60, -20));
  const Vec3<double> u{x, y, z};
  const Vec3<double> v{std::ldexp(x, scale_exp) + nudge, std::ldexp(y, scale_exp), std::ldexp(z, scale_exp)};
  const Vec3<double> w{*moderate_double(), *moderate_double(), *moderate_double()};
  const Vec3<BoundedDouble> bu(u), bv(v), bw(w);
  const BoundedDouble det = dot(cross(bu, bv), bw);
  const Rational exact = dot(cross(to_rational(u), to_rational(v)), to_rational(w));
  RC_ASSERT(contains(det, exact));
  if (const auto s = det.sign()) RC_ASSERT(*s == exact_sign(exact));
  RC_CLASSIFY(!det.sign().has_value(), "undecided (would go exact)");
}

TEST(BoundedDouble, ExactZeroIsZeroOrUndecidedNeverASign) {
  // 0.1 * 3 - 0.3 in doubles is not zero, but (3 * 2^-3) * 8 - 3 is exactly 0.
  const BoundedDouble a(3 * 0x1p-3), b(8.0), c(3.0);
  const BoundedDouble r = a * b - c;
  const auto s = r.sign();
  ASSERT_TRUE(!s.has_value() || *s == Sign::Zero);
  // A cancelling product difference with an exact zero result.
  const double p = 1.0 + 0x1p-30, q = 1.0 - 0x1p-30;
  const BoundedDouble cancel = BoundedDouble(p) * BoundedDouble(q) - BoundedDouble(p * q);
  const Rational exact = Rational(p) * Rational(q) - Rational(p * q);
  EXPECT_TRUE(contains(cancel, exact));
  if (const auto t = cancel.sign()) {
    EXPECT_EQ(*t, sign_of(exact));
  }
}

TEST(BoundedDouble, UncertainValuesCarryTheirErrorThroughProducts) {
  const BoundedDouble x(1.0, 0.5);  // somewhere in [0.5, 1.5]
  const BoundedDouble y = x * x - BoundedDouble(1.0);
  EXPECT_FALSE(y.sign().has_value()) << "x^2 - 1 may be negative or positive for x in [0.5, 1.5]";
  const BoundedDouble z = x * x + BoundedDouble(1.0);
  ASSERT_TRUE(z.sign().has_value());
  EXPECT_EQ(*z.sign(), Sign::Positive);
}

}  // namespace
}  // namespace nearcap
