// nearcap/numeric/sign.hpp — the result type of every combinatorial predicate.
#pragma once

namespace nearcap {

enum class Sign : int { Negative = -1, Zero = 0, Positive = 1 };

inline Sign operator-(Sign s) { return static_cast<Sign>(-static_cast<int>(s)); }
inline Sign operator*(Sign a, Sign b) { return static_cast<Sign>(static_cast<int>(a) * static_cast<int>(b)); }
template <class T>
Sign sign_of(const T& v) {
  return v > 0 ? Sign::Positive : (v < 0 ? Sign::Negative : Sign::Zero);
}

}  // namespace nearcap
