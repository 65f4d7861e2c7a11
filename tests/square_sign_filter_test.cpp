// The crack distance's centre filter (src/exact/square_sign_filter.hpp)
// against the form evaluated exactly at the square's four corners: every
// sign it claims is every corner's, every Zero it claims has corners of both
// signs, and it decides most squares.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <random>

#include "../src/exact/square_sign_filter.hpp"
#include "nearcap/numeric/rational.hpp"

namespace nearcap {
namespace {

// x given to the filter as an estimate within `relative` of it, its bound
// covering the difference.
BoundedDouble enclosing(double x, double relative, std::mt19937& random) {
  std::uniform_real_distribution<double> unit(-1, 1);
  const double off = x * relative * unit(random);
  return {x + off, std::fabs(off) * 2 + std::fabs(x) * 0x1p-60};
}

TEST(SquareSignFilter, ItsSignsAreTheCornersExactSigns) {
  std::mt19937 random(20261203);
  std::uniform_real_distribution<double> coefficient(-4, 4), side(1e-4, 1e-1), ratio(-2, 2);
  std::map<int, int> claims;  // -1, 0, +1 decided; 2 undecided
  constexpr int kTrials = 20000;
  for (int trial = 0; trial < kTrials; ++trial) {
    // The exact form, centre and half-sides: doubles, so exact rationals too.
    const Vec3d h{coefficient(random), coefficient(random), coefficient(random)};
    const Vec3d c{coefficient(random), coefficient(random), -std::fabs(coefficient(random)) - 0.01};
    const double hx = side(random), hy = side(random);
    // h0 puts f(C) at t times the half-range |h_x| hx + |h_y| hy: |t| > 1 is a
    // square of one sign, |t| < 1 one of both, |t| near 1 a corner near zero
    // (a third of the trials, within the estimates' errors of 1).
    const double range = std::fabs(h.x) * hx + std::fabs(h.y) * hy;
    const double t = trial % 3 == 2 ? (ratio(random) > 0 ? 1 : -1) * (1 + 1e-11 * ratio(random)) : ratio(random);
    const double h0 = t * range - (h.x * c.x + h.y * c.y + h.z * c.z);
    std::array<Rational, 4> corner;
    for (int k = 0; k < 4; ++k) {
      const Rational x = Rational(c.x) + (k & 1 ? 1 : -1) * Rational(hx);
      const Rational y = Rational(c.y) + (k & 2 ? 1 : -1) * Rational(hy);
      corner[k] = Rational(h.x) * x + Rational(h.y) * y + Rational(h.z) * Rational(c.z) + Rational(h0);
    }
    // Exact inputs in half the trials, estimates with bounds in the others.
    const double relative = trial % 2 ? 1e-12 : 0;
    const AffineForm<BoundedDouble> form{
        {enclosing(h.x, relative, random), enclosing(h.y, relative, random), enclosing(h.z, relative, random)},
        enclosing(h0, relative, random)};
    const BoundedVec3 centre{enclosing(c.x, relative, random), enclosing(c.y, relative, random),
                             enclosing(c.z, relative, random)};
    const std::optional<Sign> claim =
        square_sign_filter(form, centre, enclosing(hx, relative, random), enclosing(hy, relative, random));
    if (!claim) {
      ++claims[2];
      continue;
    }
    ++claims[static_cast<int>(*claim)];
    if (*claim == Sign::Zero) {
      bool positive = false, negative = false;
      for (const Rational& v : corner) {
        positive = positive || sign_of(v) == Sign::Positive;
        negative = negative || sign_of(v) == Sign::Negative;
      }
      EXPECT_TRUE(positive && negative) << "trial " << trial << ": Zero claimed, the corners are of one sign";
    } else {
      for (const Rational& v : corner) EXPECT_EQ(sign_of(v), *claim) << "trial " << trial;
    }
  }
  // Decided in most trials, each outcome often: the filter is not vacuous.
  EXPECT_GT(claims[1], kTrials / 5);
  EXPECT_GT(claims[-1], kTrials / 5);
  EXPECT_GT(claims[0], kTrials / 10);
  EXPECT_LT(claims[2], kTrials / 5);
}

}  // namespace
}  // namespace nearcap
