// nearcap/numeric/bounded_double.hpp — a double with a certified bound on its error.
//
// BoundedDouble{v, e} stands for an unknown exact real X with |X - v| <= e.
// Arithmetic keeps that true under IEEE-754 binary64 round-to-nearest: every
// operation adds the rounding error of its own result (at most u|v| with
// u = 2^-53; we add 2^-52 |v| to cover the 1/(1-u) factor) and an absolute
// 2^-1074 for underflow.  The bound e itself is computed in round-to-nearest,
// so after k operations it may be low by a relative k*u; sign() asks for
// |v| > e (1 + 2^-40), which covers any chain shorter than 2^12 operations.
//
// This is forward error analysis done at run time, as pbrt-v4's Interval but
// without switching the FPU rounding mode, so it is safe to mix with the
// float32 pipeline emulation and needs no per-thread state.  It is the filter
// of every exact predicate in nearcap: when sign() cannot decide, the caller
// recomputes the same expression over exact rationals.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "nearcap/numeric/sign.hpp"
#include "nearcap/numeric/vec3.hpp"

namespace nearcap {

struct BoundedDouble {
  double v = 0.0;  // the estimate
  double e = 0.0;  // |exact - v| <= e

  BoundedDouble() = default;
  // An exactly known double (an input of the scene, a constant).
  BoundedDouble(double exact) : v(exact), e(0.0) {}  // NOLINT(implicit)
  BoundedDouble(double value, double error) : v(value), e(error) {}

  static constexpr double kUlpFactor = 0x1p-52;  // 2u, covers |fl(x) - x| <= u|x| <= 2u|fl(x)|
  static constexpr double kUnderflow = std::numeric_limits<double>::denorm_min();
  static constexpr double kBoundSlack = 1.0 + 0x1p-40;

  // The certified sign, or nothing when zero lies within the error bound.
  std::optional<Sign> sign() const {
    const double margin = e * kBoundSlack;
    if (v > margin) return Sign::Positive;
    if (v < -margin) return Sign::Negative;
    if (e == 0.0 && v == 0.0) return Sign::Zero;
    return std::nullopt;
  }
  bool is_finite() const { return std::isfinite(v) && std::isfinite(e); }
};

inline BoundedDouble operator-(const BoundedDouble& a) { return {-a.v, a.e}; }

inline BoundedDouble operator+(const BoundedDouble& a, const BoundedDouble& b) {
  const double v = a.v + b.v;
  return {v, a.e + b.e + BoundedDouble::kUlpFactor * std::fabs(v)};
}
inline BoundedDouble operator-(const BoundedDouble& a, const BoundedDouble& b) {
  const double v = a.v - b.v;
  return {v, a.e + b.e + BoundedDouble::kUlpFactor * std::fabs(v)};
}
inline BoundedDouble operator*(const BoundedDouble& a, const BoundedDouble& b) {
  const double v = a.v * b.v;
  // |AB - ab| <= |a| eb + |b| ea + ea eb, plus the rounding of v.
  const double e = std::fabs(a.v) * b.e + std::fabs(b.v) * a.e + a.e * b.e + BoundedDouble::kUlpFactor * std::fabs(v) +
                   BoundedDouble::kUnderflow;
  return {v, e};
}
// Division: requires |b.v| > b.e (b certainly non-zero); callers check the sign first.
inline BoundedDouble operator/(const BoundedDouble& a, const BoundedDouble& b) {
  const double v = a.v / b.v;
  const double lower = std::fabs(b.v) - b.e;  // > 0 by precondition
  // |A/B - a/b| = |A b - a B| / |B b| <= (ea |b| + |a| eb) / (|b| (|b| - eb)) + ...
  const double e = (a.e + std::fabs(v) * b.e) / lower * (1.0 + 0x1p-50) + BoundedDouble::kUlpFactor * std::fabs(v) +
                   BoundedDouble::kUnderflow;
  return {v, e};
}
inline BoundedDouble& operator+=(BoundedDouble& a, const BoundedDouble& b) { return a = a + b; }
inline BoundedDouble& operator-=(BoundedDouble& a, const BoundedDouble& b) { return a = a - b; }
inline BoundedDouble& operator*=(BoundedDouble& a, const BoundedDouble& b) { return a = a * b; }

// The dot product of bounded vectors in one expression: the same estimate
// ((a.x b.x + a.y b.y) + a.z b.z) and the same error terms as the three
// products and two sums above (propagated errors, 2^-52 of each rounded
// result's magnitude, 2^-1074 per product), summed without the intermediate
// BoundedDoubles.  The exact reference's shadow-crossing filter runs three
// for every candidate light triangle: always inlined there, where GCC's
// size limits would otherwise make it a call (docs/findings/sweep-speed.md
// counts the instructions).
template <>
[[gnu::always_inline]] inline BoundedDouble dot(const Vec3<BoundedDouble>& a, const Vec3<BoundedDouble>& b) {
  const double px = a.x.v * b.x.v, py = a.y.v * b.y.v, pz = a.z.v * b.z.v;
  const double sxy = px + py, v = sxy + pz;
  const double propagated = (std::fabs(a.x.v) * b.x.e + std::fabs(b.x.v) * a.x.e + a.x.e * b.x.e) +
                            (std::fabs(a.y.v) * b.y.e + std::fabs(b.y.v) * a.y.e + a.y.e * b.y.e) +
                            (std::fabs(a.z.v) * b.z.e + std::fabs(b.z.v) * a.z.e + a.z.e * b.z.e);
  const double rounded = std::fabs(px) + std::fabs(py) + std::fabs(pz) + std::fabs(sxy) + std::fabs(v);
  return {v, propagated + BoundedDouble::kUlpFactor * rounded + 3 * BoundedDouble::kUnderflow};
}

}  // namespace nearcap
