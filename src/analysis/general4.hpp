// printf's "%.4g" of a double, appended to a string: the number format of the
// switch policy's reasons (PolicyDecision::reason), which a renderer formats
// for every frame it records.
//
// snprintf and std::to_chars(general, 4) both reach tables and code that a
// renderer's frame has evicted by the next (measured on llvmpipe: about half
// of the reasons' time, cold).  The common case (a positive
// number between 1e-20 and 1e20, not within rounding of a decimal tie or a
// power of ten) is formatted here from the four-digit integer nearest to
// v * 10^(3 - X), X its decimal exponent; every other value, and any whose
// rounding the scaled double cannot settle, goes to std::to_chars, whose
// output is printf's by definition.  tests/cost_decision_test.cpp compares
// the two on random and hand-picked values.
#pragma once

#include <array>
#include <charconv>
#include <cmath>
#include <string>

namespace nearcap::analysis {

inline void append_general4(std::string& out, double v) {
  // Powers of ten 1e-20 .. 1e20 (the nearest doubles; a value within
  // rounding of one of them takes the exact path below).
  static constexpr std::array<double, 41> kPow10{
      1e-20, 1e-19, 1e-18, 1e-17, 1e-16, 1e-15, 1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7,
      1e-6,  1e-5,  1e-4,  1e-3,  1e-2,  1e-1,  1e0,   1e1,   1e2,   1e3,   1e4,   1e5,  1e6,  1e7,
      1e8,   1e9,   1e10,  1e11,  1e12,  1e13,  1e14,  1e15,  1e16,  1e17,  1e18,  1e19, 1e20};
  constexpr int kLowest = -20;
  constexpr double kSlack = 1e-9;  // relative: far above the scaling's one rounding (2^-53)
  auto exact = [&out, v] {
    char buf[32];
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 4);
    out.append(buf, r.ptr);
  };
  if (!(v >= kPow10.front() && v < kPow10.back())) return exact();
  int x = 0;  // the largest with 10^x <= v
  while (x + 1 - kLowest < static_cast<int>(kPow10.size()) && kPow10[x + 1 - kLowest] <= v) ++x;
  while (kPow10[x - kLowest] > v) --x;
  if (std::fabs(v - kPow10[x - kLowest]) <= kSlack * v || std::fabs(kPow10[x + 1 - kLowest] - v) <= kSlack * v)
    return exact();
  // v * 10^(3 - x) in [1000, 10000), one rounding: 10^k is exact for k <= 22.
  const int k = 3 - x;
  if (k > 20) return exact();
  const double scaled = k >= 0 ? v * kPow10[k - kLowest] : v / kPow10[-k - kLowest];
  const double below = std::floor(scaled), fraction = scaled - below;
  if (std::fabs(fraction - 0.5) <= kSlack * scaled) return exact();  // a tie or close: printf's rounding decides
  long digits = static_cast<long>(below) + (fraction > 0.5 ? 1 : 0);
  if (digits == 10000) {  // rounded up to the next power of ten
    digits = 1000;
    ++x;
  }
  char d[4];
  for (int i = 3; i >= 0; --i, digits /= 10) d[i] = static_cast<char>('0' + digits % 10);
  int last = 3;  // the last significant digit, trailing zeros dropped
  while (last > 0 && d[last] == '0') --last;
  if (x >= -4 && x < 4) {  // fixed: 3 - x decimals, trailing zeros dropped
    if (x >= 0) {
      out.append(d, d + x + 1);
      if (last > x) {
        out += '.';
        out.append(d + x + 1, d + last + 1);
      }
    } else {
      out += "0.";
      out.append(static_cast<std::size_t>(-x - 1), '0');
      out.append(d, d + last + 1);
    }
    return;
  }
  out += d[0];  // exponential: d.ddd, then e, the sign and at least two digits
  if (last > 0) {
    out += '.';
    out.append(d + 1, d + last + 1);
  }
  out += x < 0 ? "e-" : "e+";
  const int e = x < 0 ? -x : x;
  if (e < 10) out += '0';
  out += std::to_string(e);
}

}  // namespace nearcap::analysis
