// The orientation predicates of a segment [l, P] against a triangle, as
// affine forms in the segment's end P: what segment_crossing.cpp and
// eye_count.cpp evaluate (in interval arithmetic, then exactly) and
// perturb (perturbation.hpp) at the sample point or at the eye.
#pragma once

#include "nearcap/exact/perturbation.hpp"

namespace nearcap {

// orient(l, P, u, v) = (P - l) . ((u - l) x (v - l)) as an affine form in P.
template <class T>
AffineForm<T> edge_form(const Vec3<T>& l, const Vec3<T>& u, const Vec3<T>& v) {
  const Vec3<T> g = cross(u - l, v - l);
  return {g, T(-dot(g, l))};
}
// orient(a, b, c, P) = ((b - a) x (c - a)) . (P - a) as an affine form in P.
template <class T>
AffineForm<T> plane_form(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c) {
  const Vec3<T> n = cross(b - a, c - a);
  return {n, T(-dot(n, a))};
}

}  // namespace nearcap
