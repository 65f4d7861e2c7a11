// ZP+ section 5, Figure 5: classification of an infinite side quad against the
// camera's near plane, decided exactly (the inputs are camera-space z values).
#include "nearcap/exact/quad_case.hpp"

#include "nearcap/check.hpp"

namespace nearcap {

std::string_view to_string(QuadCase c) {
  switch (c) {
    case QuadCase::A:
      return "A";
    case QuadCase::B:
      return "B";
    case QuadCase::C1:
      return "C1";
    case QuadCase::C2:
      return "C2";
    case QuadCase::D:
      return "D";
    case QuadCase::Degenerate:
      return "degenerate";
  }
  return "?";
}

QuadCase quad_case_from_sides(const QuadSides& s) {
  if (s.a == Sign::Zero || s.d == Sign::Zero || s.a_inf == Sign::Zero || s.d_inf == Sign::Zero)
    return QuadCase::Degenerate;
  const bool e_m = s.a != s.d;
  const bool i2 = s.d != s.d_inf;
  const bool e_inf = s.d_inf != s.a_inf;
  const bool i1 = s.a_inf != s.a;
  NEARCAP_CHECK(!(e_m && i2 && e_inf && i1));
  if (i1 && i2) return QuadCase::B;
  if (e_m && e_inf) return QuadCase::D;
  if (e_m) return QuadCase::C1;
  if (e_inf) return QuadCase::C2;
  return QuadCase::A;
}

namespace {

// sign(p.z + near) for a finite point, sign(p.z - l.z) for the direction p - l:
// both are a difference of two certified estimates, decided by BoundedDouble
// and, within the bound, by rationals.
template <class ExactZ>
Sign z_difference_sign(const BoundedDouble& z, const BoundedDouble& ref, ExactZ&& exact, FilterStats* stats) {
  return filtered_sign(
      Predicate::NearPlaneSide, stats, [&] { return z - ref; }, exact);
}

}  // namespace

QuadSides quad_sides(const CameraSpaceScene& scene, std::size_t o, VertexIndex a, VertexIndex d, std::size_t light,
                     FilterStats* stats) {
  const BoundedDouble minus_near(-scene.frustum().near);
  const BoundedDouble& lz = scene.light(light).z;
  const BoundedDouble az = scene.vertex(o, a).z;
  const BoundedDouble dz = scene.vertex(o, d).z;
  const Rational exact_minus_near(-scene.frustum().near);
  return {z_difference_sign(
              az, minus_near, [&] { return Rational(scene.exact_vertex(o, a).z - exact_minus_near); }, stats),
          z_difference_sign(
              dz, minus_near, [&] { return Rational(scene.exact_vertex(o, d).z - exact_minus_near); }, stats),
          z_difference_sign(
              az, lz, [&] { return Rational(scene.exact_vertex(o, a).z - scene.exact_light(light).z); }, stats),
          z_difference_sign(
              dz, lz, [&] { return Rational(scene.exact_vertex(o, d).z - scene.exact_light(light).z); }, stats)};
}

}  // namespace nearcap
