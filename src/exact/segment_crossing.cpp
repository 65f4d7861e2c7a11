// Segment [l, p_eps] against a triangle, with the sample-point perturbation.
#include "nearcap/exact/segment_crossing.hpp"

#include <cmath>

#include "nearcap/exact/perturbation.hpp"
#include "orient_forms.hpp"

namespace nearcap {

bool segment_crosses_triangle(const CameraSpaceScene& scene, std::size_t o, FaceIndex f, std::size_t light,
                              Facing facing, const SamplePoint& p, FilterStats* stats) {
  if (facing == Facing::EdgeOn) return false;
  const auto& t = scene.mesh(o).triangles[f];
  const BoundedVec3 a = scene.vertex(o, t[0]), b = scene.vertex(o, t[1]), c = scene.vertex(o, t[2]);
  const auto exact_point = [&]() -> const RationalVec3& { return p.exact; };
  const Sign p_side =
      perturbed_sign(
          Predicate::SegmentCrossing, stats, p.approx, [&] { return plane_form(a, b, c); },
          [&] {
            return plane_form(scene.exact_vertex(o, t[0]), scene.exact_vertex(o, t[1]), scene.exact_vertex(o, t[2]));
          },
          exact_point) *
      scene.handedness(o);
  const Sign l_side = facing == Facing::Front ? Sign::Positive : Sign::Negative;
  if (p_side == Sign::Zero || p_side == l_side) return false;
  const BoundedVec3& l = scene.light(light);
  Sign first = Sign::Zero;
  for (int k = 0; k < 3; ++k) {
    const BoundedVec3 u = scene.vertex(o, t[k]);
    const BoundedVec3 v = scene.vertex(o, t[(k + 1) % 3]);
    const Sign s = perturbed_sign(
        Predicate::SegmentCrossing, stats, p.approx, [&] { return edge_form(l, u, v); },
        [&] {
          return edge_form(scene.exact_light(light), scene.exact_vertex(o, t[k]),
                           scene.exact_vertex(o, t[(k + 1) % 3]));
        },
        exact_point);
    if (s == Sign::Zero) return false;
    if (k == 0)
      first = s;
    else if (s != first)
      return false;
  }
  return true;
}

std::size_t near_cap_count_brute_force(const CameraSpaceScene& scene, std::size_t light,
                                       const std::vector<std::vector<Facing>>& facing, const SamplePoint& p,
                                       FilterStats* stats) {
  std::size_t count = 0;
  for (std::size_t o = 0; o < scene.object_count(); ++o) {
    if (!scene.object(o).occluder) continue;
    const std::vector<Facing>& fo = facing[o];
    for (FaceIndex f = 0; f < fo.size(); ++f)
      if (fo[f] == Facing::Front && segment_crosses_triangle(scene, o, f, light, Facing::Front, p, stats)) ++count;
  }
  return count;
}

BoundedVec3 window_offset_estimate(const Frustum& fr, int width, int height, const WindowPoint& d) {
  // The integers and the powers of two are exact doubles.
  const double scale = std::ldexp(1.0, d.shift);
  const BoundedDouble w(width * scale), h(height * scale);
  return {BoundedDouble(static_cast<double>(d.x)) * (BoundedDouble(fr.right) - BoundedDouble(fr.left)) / w,
          BoundedDouble(static_cast<double>(d.y)) * (BoundedDouble(fr.top) - BoundedDouble(fr.bottom)) / h,
          BoundedDouble(0.0)};
}

BoundedVec3 window_point_estimate(const Frustum& fr, int width, int height, const WindowPoint& p) {
  const BoundedVec3 d = window_offset_estimate(fr, width, height, p);
  return {BoundedDouble(fr.left) + d.x, BoundedDouble(fr.bottom) + d.y, BoundedDouble(-fr.near)};
}

RationalVec3 window_point_exact(const Frustum& fr, int width, int height, const WindowPoint& p) {
  const double scale = std::ldexp(1.0, p.shift);
  return {Rational(fr.left) +
              Rational(static_cast<double>(p.x)) * (Rational(fr.right) - Rational(fr.left)) / Rational(width * scale),
          Rational(fr.bottom) +
              Rational(static_cast<double>(p.y)) * (Rational(fr.top) - Rational(fr.bottom)) / Rational(height * scale),
          Rational(-fr.near)};
}

BoundedVec3 pixel_centre_estimate(const Frustum& fr, int width, int height, int i, int j) {
  // x = left + (2i + 1) (right - left) / (2W).
  return window_point_estimate(fr, width, height, window_pixel_centre(i, j));
}

RationalVec3 pixel_centre_exact(const Frustum& fr, int width, int height, int i, int j) {
  return window_point_exact(fr, width, height, window_pixel_centre(i, j));
}

SamplePoint pixel_centre(const Frustum& fr, int width, int height, int i, int j) {
  return {pixel_centre_estimate(fr, width, height, i, j), pixel_centre_exact(fr, width, height, i, j)};
}

}  // namespace nearcap
