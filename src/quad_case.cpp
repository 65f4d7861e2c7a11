// ZP+ section 5, Figure 5: classification of an infinite side quad against the
// camera's near plane, decided exactly (the inputs are camera-space z values).
#include "nearcap/quad_case.hpp"

#include <functional>

#include "nearcap/check.hpp"

namespace nearcap {

std::string_view to_string(QuadCase c) {
  switch (c) {
    case QuadCase::A: return "A";
    case QuadCase::B: return "B";
    case QuadCase::C1: return "C1";
    case QuadCase::C2: return "C2";
    case QuadCase::D: return "D";
    case QuadCase::Degenerate: return "degenerate";
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

// sign(p.z + near): which side of the near plane a finite point lies on.
Sign finite_side(const BoundedVec3& approx, const std::function<RationalVec3()>& exact, double near, FilterStats* stats) {
  return filtered_sign(
      Predicate::NearPlaneSide, stats, [&] { return approx.z + BoundedDouble(near); },
      [&] { return Rational(exact().z + Rational(near)); });
}

// sign(p.z - l.z): which way the direction p - l points across the near plane.
Sign direction_side(const BoundedVec3& approx, const std::function<RationalVec3()>& exact, const CameraSpaceScene& scene,
                    std::size_t light, FilterStats* stats) {
  return filtered_sign(
      Predicate::NearPlaneSide, stats, [&] { return approx.z - scene.light(light).z; },
      [&] { return Rational(exact().z - scene.exact_light(light).z); });
}

}  // namespace

QuadSides quad_sides(const CameraSpaceScene& scene, std::size_t o, VertexIndex a, VertexIndex d, std::size_t light,
                     FilterStats* stats) {
  const double near = scene.frustum().near;
  const BoundedVec3& pa = scene.vertex(o, a);
  const BoundedVec3& pd = scene.vertex(o, d);
  const std::function<RationalVec3()> ea = [&] { return scene.exact_vertex(o, a); };
  const std::function<RationalVec3()> ed = [&] { return scene.exact_vertex(o, d); };
  return {finite_side(pa, ea, near, stats), finite_side(pd, ed, near, stats),
          direction_side(pa, ea, scene, light, stats), direction_side(pd, ed, scene, light, stats)};
}

}  // namespace nearcap
