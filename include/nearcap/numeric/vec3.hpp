// nearcap/numeric/vec3.hpp — a 3-vector over any number type, and affine 3x4 maps.
//
// One template serves the three arithmetics nearcap uses: double (estimates),
// BoundedDouble (filters with a certified error bound) and exact rationals
// (decisions the filter could not make).  Writing a predicate once, over Vec3<T>,
// and instantiating it for the filter and for the exact path is what keeps the
// two in agreement (CGAL's Filtered_predicate does the same).
#pragma once

#include <array>
#include <cstddef>
#include <utility>

namespace nearcap {

template <class T>
struct Vec3 {
  T x{}, y{}, z{};

  Vec3() = default;
  Vec3(T x_, T y_, T z_) : x(std::move(x_)), y(std::move(y_)), z(std::move(z_)) {}
  template <class U>
  explicit Vec3(const Vec3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}

  const T& operator[](std::size_t i) const { return i == 0 ? x : (i == 1 ? y : z); }
  T& operator[](std::size_t i) { return i == 0 ? x : (i == 1 ? y : z); }
};

template <class T>
Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
Vec3<T> operator-(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
Vec3<T> operator*(const T& s, const Vec3<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
T dot(const Vec3<T>& a, const Vec3<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// Orientation determinant det(b - a, c - a, d - a): positive when d lies on the
// side of plane (a, b, c) that its normal (b - a) x (c - a) points to.
template <class T>
T orientation_determinant(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c, const Vec3<T>& d) {
  return dot(cross(b - a, c - a), d - a);
}

using Vec3d = Vec3<double>;

// An affine map x -> L x + t stored as three rows [L | t] (the fourth row of the
// 4x4 form is [0 0 0 1]).  Entries are doubles: in nearcap's exactness
// convention they ARE the exact map (see docs/scene-format.md, "Exactness convention").
struct Affine3d {
  std::array<std::array<double, 4>, 3> rows{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

  static Affine3d identity() { return {}; }
  Vec3d apply(const Vec3d& p) const {
    return {rows[0][0] * p.x + rows[0][1] * p.y + rows[0][2] * p.z + rows[0][3],
            rows[1][0] * p.x + rows[1][1] * p.y + rows[1][2] * p.z + rows[1][3],
            rows[2][0] * p.x + rows[2][1] * p.y + rows[2][2] * p.z + rows[2][3]};
  }
};

// Composition in double (rounded).  Only used where the exactness convention
// says a value is "computed once in double" (building an object matrix from
// translate/rotate/scale); exact composition of two maps lives in exact_map.hpp.
Affine3d compose_rounded(const Affine3d& outer, const Affine3d& inner);

}  // namespace nearcap
