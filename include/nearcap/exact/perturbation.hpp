// nearcap/exact/perturbation.hpp — nearcap's one degeneracy policy for sample points.
//
// Pixel centres, near-rectangle points and probe points are perturbed
// symbolically (Simulation of Simplicity):
//
//     p_eps = p + e1 * (0, 0, -1) + e2 * (1, 0, 0) + e3 * (0, 1, 0),
//     e1 >> e2 >> e3 > 0, all infinitesimal.
//
// In words: a point exactly on an edge or a plane is decided as if it were
// nudged first away from the camera (into the view frustum, -z), then right
// (+x), then up (+y).  Every predicate nearcap evaluates at a sample point is
// the sign of an affine form h . p + h0 (the ray and segment tests are
// arranged so, see pixel_reference.cpp), whose value at p_eps is
//     h . p + h0  - e1 h.z + e2 h.x + e3 h.y,
// so its sign is sign(h . p + h0), else sign(-h.z), else sign(h.x), else
// sign(h.y).  It is Zero only when h = 0: the form does not depend on the
// point at all, a degeneracy of the scene, not of the sample, which the caller
// resolves by its own documented rule.  No epsilon is involved anywhere.
#pragma once

#include "nearcap/numeric/bounded_double.hpp"
#include "nearcap/numeric/filter_stats.hpp"
#include "nearcap/numeric/rational.hpp"
#include "nearcap/numeric/vec3.hpp"

namespace nearcap {

template <class T>
struct AffineForm {
  Vec3<T> h;
  T h0;
  T at(const Vec3<T>& p) const { return dot(h, p) + h0; }
};

// The perturbed sign of an exact form at an exact point.
inline Sign perturbed_sign(const AffineForm<Rational>& f, const Vec3<Rational>& p) {
  const Sign s = sign_of(Rational(f.at(p)));
  if (s != Sign::Zero) return s;
  if (const Sign z = -sign_of(f.h.z); z != Sign::Zero) return z;
  if (const Sign x = sign_of(f.h.x); x != Sign::Zero) return x;
  return sign_of(f.h.y);
}

// Filtered version: `approx_form()` builds the form in BoundedDouble,
// `exact_form()` in Rational; `exact_point()` gives p exactly.  The exact path
// runs only when the filter cannot certify the sign of the value at p.
template <class ApproxForm, class ExactForm, class ExactPoint>
Sign perturbed_sign(Predicate pred, FilterStats* stats, const Vec3<BoundedDouble>& p, ApproxForm&& approx_form,
                    ExactForm&& exact_form, ExactPoint&& exact_point) {
  const AffineForm<BoundedDouble> fa = approx_form();
  if (const auto s = fa.at(p).sign(); s && *s != Sign::Zero) {
    if (stats) stats->record(pred, false);
    return *s;
  }
  if (stats) stats->record(pred, true);
  return perturbed_sign(exact_form(), exact_point());
}

}  // namespace nearcap
