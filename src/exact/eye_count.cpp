// The exact eye count (see eye_count.hpp): segment_crossing.hpp's test with
// the sample point at the eye, which also reports whether the perturbation
// had to decide.
#include "nearcap/exact/eye_count.hpp"

#include "nearcap/exact/perturbation.hpp"
#include "orient_forms.hpp"

namespace nearcap {
namespace {

// The perturbed sign of a form at the eye (the origin, where its value is
// h0); `tie` is set when the value itself is exactly zero.
template <class ApproxForm, class ExactForm>
Sign sign_at_eye(FilterStats* stats, ApproxForm&& approx_form, ExactForm&& exact_form, bool& tie) {
  if (const auto s = approx_form().h0.sign(); s && *s != Sign::Zero) {
    if (stats) stats->record(Predicate::SegmentCrossing, false);
    return *s;
  }
  if (stats) stats->record(Predicate::SegmentCrossing, true);
  const AffineForm<Rational> f = exact_form();
  if (sign_of(f.h0) == Sign::Zero) tie = true;
  return perturbed_sign(f, RationalVec3{Rational(0), Rational(0), Rational(0)});
}

// Does [l, eye_eps] cross front-facing triangle f of object o?  A tie in a
// test that decides the answer sets `tie`.
bool eye_segment_crosses(const CameraSpaceScene& scene, std::size_t o, FaceIndex f, std::size_t light,
                         FilterStats* stats, bool& tie) {
  const auto& t = scene.mesh(o).triangles[f];
  bool plane_tie = false;
  const Sign eye_side =
      sign_at_eye(
          stats, [&] { return plane_form(scene.vertex(o, t[0]), scene.vertex(o, t[1]), scene.vertex(o, t[2])); },
          [&] {
            return plane_form(scene.exact_vertex(o, t[0]), scene.exact_vertex(o, t[1]), scene.exact_vertex(o, t[2]));
          },
          plane_tie) *
      scene.handedness(o);
  // The light is on the positive (outer) side of a front face; with the eye
  // exactly in the plane the edges still say whether the tie mattered.
  if (eye_side != Sign::Negative && !plane_tie) return false;
  bool edge_tie = false;
  Sign first = Sign::Zero;
  bool inside = true;  // the line eye->light passes inside the triangle
  for (int k = 0; k < 3 && inside; ++k) {
    const Sign s = sign_at_eye(
        stats, [&] { return edge_form(scene.light(light), scene.vertex(o, t[k]), scene.vertex(o, t[(k + 1) % 3])); },
        [&] {
          return edge_form(scene.exact_light(light), scene.exact_vertex(o, t[k]),
                           scene.exact_vertex(o, t[(k + 1) % 3]));
        },
        edge_tie);
    if (s == Sign::Zero)
      inside = false;
    else if (k == 0)
      first = s;
    else if (s != first)
      inside = false;
  }
  // A tie matters where the line eye->light meets the triangle's closure
  // (on an edge) or where the eye lies in the plane of a triangle the line
  // passes through.
  if (edge_tie || (plane_tie && inside)) tie = true;
  return inside && eye_side == Sign::Negative;
}

}  // namespace

ExactEyeCount exact_eye_count(const CameraSpaceScene& scene, std::size_t light,
                              const std::vector<std::vector<Facing>>& facing, FilterStats* stats) {
  ExactEyeCount out;
  for (std::size_t o = 0; o < scene.object_count(); ++o) {
    if (!scene.object(o).occluder) continue;
    const std::vector<Facing>& fo = facing[o];
    for (FaceIndex f = 0; f < fo.size(); ++f)
      if (fo[f] == Facing::Front && eye_segment_crosses(scene, o, f, light, stats, out.on_boundary)) ++out.count;
  }
  return out;
}

ExactEyeCount exact_eye_count(const CameraSpaceScene& scene, std::size_t light, FilterStats* stats) {
  std::vector<std::vector<Facing>> facing(scene.object_count());
  for (std::size_t o = 0; o < scene.object_count(); ++o)
    if (scene.object(o).occluder) facing[o] = light_facing(scene, o, light, stats);
  return exact_eye_count(scene, light, facing, stats);
}

}  // namespace nearcap
