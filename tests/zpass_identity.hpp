// The Z-pass identity check shared by the property test and the stress test:
//
//   stencil(i, j) = cap(i, j) + sum over silhouette sides crossed by the open
//                   segment (p, q) of +1 (entering a shadow volume) or -1.
//
// The side of silhouette edge [a, d] (front face (a, d, c)) is the part of plane
// (l, a, d) inside the wedge at l between a and d, beyond the edge.  The open
// segment (p, q) lies on the view ray x = t P, 1 < t < t_q, so each test is a
// linear form in P under the reference's perturbation.  The stencil counts the
// volumes the point just before q lies in, so the identity holds as written
// also when the camera is inside an occluder and sees the inner side of a lit
// face.
#pragma once

#include "nearcap/exact/classification.hpp"
#include "nearcap/exact/light_facing.hpp"
#include "nearcap/exact/perturbation.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/exact/segment_crossing.hpp"

namespace nearcap::test {

using Form = AffineForm<Rational>;
inline Form linear(const RationalVec3& h) { return {h, Rational(0)}; }

struct SideCrossings {
  int signed_sum = 0;
  bool degenerate = false;  // a form vanished identically: this pixel proves nothing
};

// Signed crossings of the shadow-volume sides by the open segment (p, q).
inline SideCrossings side_crossings(const CameraSpaceScene& cs, const std::vector<ObjectClassification>& objects,
                                    const RationalVec3& P, const RationalVec3& n_q, const Rational& d_q) {
  SideCrossings out;
  const RationalVec3& l = cs.exact_light(0);
  const Sign sigma_q = sign_of(d_q);
  for (const ObjectClassification& oc : objects) {
    const TriangleMesh& mesh = cs.mesh(oc.object);
    const Sign h = cs.handedness(oc.object);
    for (const ClassifiedEdge& ce : oc.edges) {
      const RationalVec3 a = cs.exact_vertex(oc.object, ce.edge.a);
      const RationalVec3 d = cs.exact_vertex(oc.object, ce.edge.d);
      const RationalVec3 n_s = cross(a - l, d - l);
      const Sign s1 = perturbed_sign(linear(cross(l, a)), P);
      const Sign s3 = perturbed_sign(linear(cross(d, l)), P);
      const Sign sigma = perturbed_sign(linear(n_s), P);
      const Sign s2 = perturbed_sign(linear(cross(a, d)), P);
      const Rational nl = dot(n_s, l);
      const Sign beyond_p = perturbed_sign(Form{Rational(-1) * n_s, nl}, P);
      const Sign before_q = perturbed_sign(linear(nl * n_q - d_q * n_s), P);
      if (s1 == Sign::Zero || s2 == Sign::Zero || s3 == Sign::Zero || sigma == Sign::Zero || beyond_p == Sign::Zero ||
          before_q == Sign::Zero) {
        out.degenerate = true;
        continue;
      }
      const bool in_wedge = s1 == sigma && s3 == sigma;
      const bool beyond_edge = s2 == -sigma;
      const bool after_p = beyond_p == sigma;
      const bool before_hit = before_q * sigma * sigma_q == Sign::Negative;
      if (in_wedge && beyond_edge && after_p && before_hit) out.signed_sum += -static_cast<int>(sigma * h);
      (void)mesh;
    }
  }
  return out;
}

struct IdentityReport {
  int checked = 0, degenerate = 0, nonzero_cap = 0, shadowed = 0;
  bool holds = true;
  std::string failure;
};

// Checks cap against the brute-force count and the Z-pass identity at every
// pixel of the scene's viewport, for light 0.
inline IdentityReport check_zpass_identity(const Scene& scene) {
  IdentityReport report;
  const CameraSpaceScene cs(scene);
  std::vector<ObjectClassification> objects;
  std::vector<std::vector<Facing>> facing(cs.object_count());
  for (std::size_t o = 0; o < cs.object_count(); ++o)
    if (scene.objects[o].occluder) {
      objects.push_back(classify_object_exact(cs, o, 0, nullptr));
      facing[o] = light_facing(cs, o, 0, nullptr);
    }
  const PixelReferenceTracer tracer(cs, 0);
  for (int j = 0; j < scene.camera.height; ++j)
    for (int i = 0; i < scene.camera.width; ++i) {
      const PixelSample s = tracer.trace(i, j, nullptr);
      const SamplePoint p = pixel_centre(scene.camera.frustum, scene.camera.width, scene.camera.height, i, j);
      const std::size_t brute = near_cap_count_brute_force(cs, 0, facing, p, nullptr);
      const std::string where = "pixel (" + std::to_string(i) + ", " + std::to_string(j) + ")";
      if (s.cap != brute) {
        report.holds = false;
        report.failure = where + ": cap " + std::to_string(s.cap) + " vs brute force " + std::to_string(brute);
        return report;
      }
      if (!s.stencil) continue;
      const auto o = static_cast<std::size_t>(s.object);
      const auto& t = cs.mesh(o).triangles[s.face];
      const RationalVec3 a = cs.exact_vertex(o, t[0]), b = cs.exact_vertex(o, t[1]), c = cs.exact_vertex(o, t[2]);
      const RationalVec3 n_q = cross(b - a, c - a);
      const SideCrossings sides = side_crossings(cs, objects, p.exact, n_q, Rational(dot(n_q, a)));
      if (sides.degenerate) {
        ++report.degenerate;
        continue;
      }
      ++report.checked;
      report.nonzero_cap += s.cap > 0;
      report.shadowed += *s.stencil > 0;
      if (static_cast<long>(*s.stencil) != static_cast<long>(s.cap) + sides.signed_sum) {
        report.holds = false;
        report.failure = where + ": stencil " + std::to_string(*s.stencil) + " vs cap " + std::to_string(s.cap) +
                         " + sides " + std::to_string(sides.signed_sum);
        return report;
      }
    }
  return report;
}

}  // namespace nearcap::test
