// BoundedDouble's contract over the whole binary64 range: for a BoundedDouble
// {v, e} standing for the exact rational X, every +, -, * keeps
// |X - v| <= e (up to the documented slack of the bound's own rounding), and
// sign() answers only with X's exact sign.  Inputs include subnormals, zeros,
// huge values, inputs that are themselves uncertain, and chains of operations
// that cancel; division by a certainly non-zero divisor; determinants of
// nearly parallel vectors (the case the filters exist for).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "nearcap/numeric/bounded_double.hpp"
#include "nearcap/numeric/rational.hpp"
#include "nearcap/numeric/vec3.hpp"

namespace nearcap {
namespace {

// A double anywhere in the finite range: full random mantissa, any exponent
// (subnormals included), either sign, and a few special values.
rc::Gen<double> any_finite_double() {
  return rc::gen::oneOf(
      rc::gen::map(
          rc::gen::tuple(rc::gen::inRange<std::int64_t>(-(1LL << 53), 1LL << 53), rc::gen::inRange(-1126, 972)),
          [](const std::tuple<std::int64_t, int>& t) {
            return std::ldexp(static_cast<double>(std::get<0>(t)), std::get<1>(t));
          }),
      rc::gen::element(0.0, -0.0, std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::denorm_min(),
                       std::numeric_limits<double>::min(), std::numeric_limits<double>::max(),
                       -std::numeric_limits<double>::max(), 1.0, -1.0));
}

// A double of moderate magnitude, so that chains of products stay finite.
rc::Gen<double> moderate_double() {
  return rc::gen::map(
      rc::gen::tuple(rc::gen::inRange<std::int64_t>(-(1LL << 53), 1LL << 53), rc::gen::inRange(-30, 31)),
      [](const std::tuple<std::int64_t, int>& t) {
        return std::ldexp(static_cast<double>(std::get<0>(t)), std::get<1>(t) - 53);
      });
}

// |X - v| <= e * kBoundSlack, decided exactly.  The slack is the documented
// allowance for e being computed in round-to-nearest (header comment).
bool encloses(const BoundedDouble& b, const Rational& exact) {
  const Rational slack = Rational(BoundedDouble::kBoundSlack);
  return abs(Rational(b.v) - exact) <= Rational(b.e) * slack;
}

// sign() may abstain; when it answers, the answer is the exact sign.
bool sign_is_sound(const BoundedDouble& b, const Rational& exact) {
  const auto s = b.sign();
  return !s.has_value() || *s == sign_of(exact);
}

// A value with its exact meaning: the certified estimate and the rational it stands for.
struct Tracked {
  BoundedDouble approx;
  Rational exact;
};

Tracked apply(char op, const Tracked& a, const Tracked& b) {
  switch (op) {
    case '+':
      return {a.approx + b.approx, a.exact + b.exact};
    case '-':
      return {a.approx - b.approx, a.exact - b.exact};
    default:
      return {a.approx * b.approx, a.exact * b.exact};
  }
}

RC_GTEST_PROP(BoundedDoubleRange, ExactInputsAnyMagnitude, ()) {
  const double a = *any_finite_double(), b = *any_finite_double();
  for (char op : {'+', '-', '*'}) {
    const Tracked r = apply(op, {BoundedDouble(a), Rational(a)}, {BoundedDouble(b), Rational(b)});
    // An overflowed result (v or e infinite) claims nothing; mpq cannot hold it.
    if (!r.approx.is_finite()) continue;
    RC_ASSERT(r.approx.e >= 0.0);
    RC_ASSERT(encloses(r.approx, r.exact));
    RC_ASSERT(sign_is_sound(r.approx, r.exact));
  }
}

RC_GTEST_PROP(BoundedDoubleRange, UncertainInputsPropagateTheirError, ()) {
  // X is an exact double; the estimate v sits k ulps away and e >= |X - v|.
  auto uncertain = [] {
    const double x = *moderate_double();
    double v = x;
    const int k = *rc::gen::inRange(-4, 5);
    for (int i = 0; i < std::abs(k); ++i)
      v = std::nextafter(v, k > 0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity());
    const double gap = std::fabs(v - x);  // exact: Sterbenz
    const double extra = *rc::gen::element(0.0, 1.0, 0x1p-40);
    return Tracked{BoundedDouble(v, gap + extra * std::fabs(x)), Rational(x)};
  };
  const Tracked a = uncertain(), b = uncertain();
  RC_PRE(encloses(a.approx, a.exact) && encloses(b.approx, b.exact));
  for (char op : {'+', '-', '*'}) {
    const Tracked r = apply(op, a, b);
    RC_ASSERT(encloses(r.approx, r.exact));
    RC_ASSERT(sign_is_sound(r.approx, r.exact));
  }
}

RC_GTEST_PROP(BoundedDoubleRange, ChainsWithCancellationStaySound, ()) {
  // Leaves: random doubles, near-copies of earlier leaves (a few ulps apart)
  // and small integers, so that differences cancel, often to exactly zero.
  std::vector<Tracked> values;
  const int leaves = *rc::gen::inRange(2, 7);
  for (int i = 0; i < leaves; ++i) {
    double x = 0;
    const int kind = *rc::gen::inRange(0, 3);
    if (kind == 0 || values.empty()) {
      x = *moderate_double();
    } else if (kind == 1) {
      x = values[*rc::gen::inRange<std::size_t>(0, values.size())].approx.v;
      for (int s = *rc::gen::inRange(0, 3); s > 0; --s) x = std::nextafter(x, 2 * x + 1);
    } else {
      x = *rc::gen::inRange(-3, 4);
    }
    values.push_back({BoundedDouble(x), Rational(x)});
  }
  const int ops = *rc::gen::inRange(1, 11);
  for (int i = 0; i < ops; ++i) {
    const Tracked& a = values[*rc::gen::inRange<std::size_t>(0, values.size())];
    const Tracked& b = values[*rc::gen::inRange<std::size_t>(0, values.size())];
    const Tracked r = apply(*rc::gen::element('+', '-', '*'), a, b);
    if (!r.approx.is_finite()) break;  // repeated squaring can overflow: no claim then
    RC_ASSERT(encloses(r.approx, r.exact));
    RC_ASSERT(sign_is_sound(r.approx, r.exact));
    RC_CLASSIFY(!r.approx.sign().has_value(), "undecided");
    RC_CLASSIFY(sgn(r.exact) == 0, "exactly zero");
    values.push_back(r);
  }
}

TEST(BoundedDoubleSign, ExactValuesHaveTheirOwnSign) {
  EXPECT_EQ(BoundedDouble(0.0).sign(), Sign::Zero);
  EXPECT_EQ(BoundedDouble(-0.0).sign(), Sign::Zero);
  EXPECT_EQ(BoundedDouble(std::numeric_limits<double>::denorm_min()).sign(), Sign::Positive);
  EXPECT_EQ(BoundedDouble(-3.5).sign(), Sign::Negative);
}

TEST(BoundedDoubleSign, ZeroEstimateWithAnErrorIsUndecided) {
  EXPECT_FALSE(BoundedDouble(0.0, std::numeric_limits<double>::denorm_min()).sign().has_value());
  EXPECT_FALSE(BoundedDouble(1.0, 1.0).sign().has_value()) << "|v| = e: zero is still possible";
  EXPECT_EQ(BoundedDouble(1.0, 0.5).sign(), Sign::Positive);
  EXPECT_EQ(BoundedDouble(-1.0, 0.5).sign(), Sign::Negative);
}

TEST(BoundedDoubleSign, UnderflowToZeroIsNotReportedAsZero) {
  // denorm_min^2 rounds to 0 although the exact product is positive.
  const double tiny = std::numeric_limits<double>::denorm_min();
  const BoundedDouble p = BoundedDouble(tiny) * BoundedDouble(tiny);
  EXPECT_EQ(p.v, 0.0);
  EXPECT_GT(p.e, 0.0);
  EXPECT_FALSE(p.sign().has_value());
  EXPECT_TRUE(encloses(p, Rational(tiny) * Rational(tiny)));
}

TEST(BoundedDoubleSign, ExactCancellationOfExactInputsIsZero) {
  // x - x and (x + y) - (x + y) with exact inputs: the first is exactly zero with
  // no error; the second carries the rounding error of the sums and abstains
  // or says zero, never a non-zero sign.
  const double x = 0.1, y = 0x1p-60;
  const BoundedDouble d = BoundedDouble(x) - BoundedDouble(x);
  EXPECT_EQ(d.sign(), Sign::Zero);
  const BoundedDouble s = BoundedDouble(x) + BoundedDouble(y);
  const BoundedDouble z = s - s;
  const auto zs = z.sign();
  EXPECT_TRUE(!zs.has_value() || *zs == Sign::Zero);
}

TEST(BoundedDoubleSign, NegationKeepsTheErrorAndFlipsTheSign) {
  const BoundedDouble a(2.0, 0.25);
  const BoundedDouble n = -a;
  EXPECT_EQ(n.v, -2.0);
  EXPECT_EQ(n.e, 0.25);
  EXPECT_EQ(n.sign(), Sign::Negative);
}

TEST(BoundedDoubleSign, CompoundAssignmentMatchesTheOperators) {
  const BoundedDouble a(1.0 / 3.0, 0x1p-54), b(0.7, 0x1p-53);
  BoundedDouble s = a, d = a, m = a;
  s += b;
  d -= b;
  m *= b;
  const BoundedDouble s2 = a + b, d2 = a - b, m2 = a * b;
  EXPECT_EQ(s.v, s2.v);
  EXPECT_EQ(s.e, s2.e);
  EXPECT_EQ(d.v, d2.v);
  EXPECT_EQ(d.e, d2.e);
  EXPECT_EQ(m.v, m2.v);
  EXPECT_EQ(m.e, m2.e);
}

RC_GTEST_PROP(BoundedDoubleRange, DivisionEnclosesTheExactQuotient, ()) {
  const double a = *moderate_double(), b = *moderate_double();
  RC_PRE(b != 0.0);
  const Rational exact = Rational(a) / Rational(b);
  const BoundedDouble q = BoundedDouble(a) / BoundedDouble(b);
  RC_ASSERT(encloses(q, exact));
  RC_ASSERT(sign_is_sound(q, exact));
}

RC_GTEST_PROP(BoundedDoubleRange, DeterminantSignIsNeverWrong, ()) {
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
  RC_ASSERT(encloses(det, exact));
  RC_ASSERT(sign_is_sound(det, exact));
  RC_CLASSIFY(!det.sign().has_value(), "undecided (would go exact)");
}

// dot() of bounded vectors is one expression (bounded_double.hpp): the same
// estimate as the operators' ((x + y) + z), a bound that encloses the exact
// dot product of the exact inputs, and, where bounds are normal numbers,
// within the bound's own rounding of the operators' bound.
RC_GTEST_PROP(BoundedDoubleRange, DotProductEnclosesTheExactDot, ()) {
  const bool wide = *rc::gen::arbitrary<bool>();  // any magnitude, or moderate with cancellation
  auto coordinate = [wide] {
    const double x = wide ? *any_finite_double() : *moderate_double();
    const double e = *rc::gen::element(0.0, 0x1p-52, 0x1p-30, 1.0) * std::fabs(x);
    const double v = *rc::gen::arbitrary<bool>() ? x : std::nextafter(x, 0.0);
    return Tracked{BoundedDouble(v, e + std::fabs(v - x)), Rational(x)};
  };
  std::array<Tracked, 6> c{coordinate(), coordinate(), coordinate(), coordinate(), coordinate(), coordinate()};
  if (*rc::gen::arbitrary<bool>()) {  // x and y terms that cancel: a.y = a.x, b.y = -b.x
    c[1] = c[0];
    c[4] = {-c[3].approx, -c[3].exact};
  }
  const Vec3<BoundedDouble> a{c[0].approx, c[1].approx, c[2].approx}, b{c[3].approx, c[4].approx, c[5].approx};
  const BoundedDouble fused = dot(a, b);
  const BoundedDouble composed = a.x * b.x + a.y * b.y + a.z * b.z;
  if (!composed.is_finite()) return;  // an overflow claims nothing
  // Summed at once, the rounded results' magnitudes overflow a little sooner
  // (an infinite bound: sound, and the exact predicate decides).
  if (!fused.is_finite()) {
    RC_ASSERT(composed.e > 0x1p960);
    return;
  }
  const Rational exact = c[0].exact * c[3].exact + c[1].exact * c[4].exact + c[2].exact * c[5].exact;
  RC_ASSERT(fused.v == composed.v);
  RC_ASSERT(encloses(fused, exact));
  RC_ASSERT(sign_is_sound(fused, exact));
  // (Subnormal bounds round by absolute steps: compared where they are normal.)
  if (composed.e > 0x1p-1000) {
    RC_ASSERT(fused.e <= composed.e * BoundedDouble::kBoundSlack);
    RC_ASSERT(composed.e <= fused.e * BoundedDouble::kBoundSlack);
  }
}

TEST(BoundedDoubleSign, UncertainValuesCarryTheirErrorThroughProducts) {
  const BoundedDouble x(1.0, 0.5);  // somewhere in [0.5, 1.5]
  EXPECT_FALSE((x * x - BoundedDouble(1.0)).sign().has_value()) << "x^2 - 1 has both signs on [0.5, 1.5]";
  const auto s = (x * x + BoundedDouble(1.0)).sign();
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(*s, Sign::Positive);
}

}  // namespace
}  // namespace nearcap
