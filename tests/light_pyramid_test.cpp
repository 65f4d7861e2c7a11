// The largest admissible l_near (exact/light_pyramid.hpp) and the l_near rules
// of the light frustum (gl/light_frustum.hpp).
#include <gtest/gtest.h>

#include <array>
#include <optional>

#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/light_pyramid.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/gl/light_frustum.hpp"
#include "nearcap/io/scene_file.hpp"
#include "support/sampled_scenes.hpp"

namespace nearcap {
namespace {

std::string box_scene(const std::string& light, const std::string& translate, double scale) {
  // The exact camera form: the near rectangle is [-1, 1]^2 at z = -1 exactly.
  return R"({"camera":{"view":[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]],
    "frustum":{"left":-1,"right":1,"bottom":-1,"top":1,"near":1,"far":100},"width":8,"height":8},
    "lights":[{"position":)" +
         light + R"(}],"objects":[{"mesh":")" + std::string(NEARCAP_SOURCE_DIR) + R"(/data/meshes/box.off",
    "translate":)" +
         translate + R"(,"scale":)" + std::to_string(scale) + "}]}";
}

TEST(LightPyramid, TheNearestOccluderPointInThePyramidExactly) {
  // Light at z = 2 (l_far = 3), a box of side 0.5 centred at z = 1: its top
  // face z = 1.25 crosses the pyramid's axis, 0.75 from the light.
  const Scene scene = parse_scene(box_scene("[0,0,2]", "[0,0,1]", 0.5), "box", ".");
  const CameraSpaceScene cs(scene);
  const AdmissibleLightNear a = max_admissible_light_near(cs, 0);
  ASSERT_TRUE(a.l_near.has_value());
  EXPECT_EQ(*a.l_near, Rational(3, 4));
  EXPECT_EQ(a.l_far, Rational(3));
  // Moved sideways out of the pyramid (half-width 0.25 at that depth... the box
  // from x = 2.75 to 3.25 is far outside): no occluder point in the pyramid.
  const Scene away = parse_scene(box_scene("[0,0,2]", "[3,0,1]", 0.5), "away", ".");
  const CameraSpaceScene cs_away(away);
  EXPECT_FALSE(max_admissible_light_near(cs_away, 0).l_near.has_value());
  // Only the box's corner enters the pyramid: the minimum is where a pyramid
  // edge meets the box, not at a box vertex.  The near rectangle is
  // [-1, 1]^2 at z = -1, so the pyramid's half-width at depth a is a / 3; the
  // box [0.75, 1.75]^2 x [-1, 0] first meets it on the corner edge through
  // (1, 1, -1), at x = y = 0.75: a = 2.25 (z = -0.25, inside the box).
  const Scene corner = parse_scene(box_scene("[0,0,2]", "[1.25,1.25,-0.5]", 1.0), "corner", ".");
  const CameraSpaceScene cs_corner(corner);
  const AdmissibleLightNear c = max_admissible_light_near(cs_corner, 0);
  ASSERT_TRUE(c.l_near.has_value());
  EXPECT_EQ(*c.l_near, Rational(9, 4));
}

TEST(LightPyramid, ALightInTheNearPlaneHasNoFrustum) {
  const Scene scene = parse_scene(box_scene("[0,0,-1]", "[0,0,-5]", 0.5), "in plane", ".");
  const CameraSpaceScene cs(scene);
  EXPECT_THROW(max_admissible_light_near(cs, 0), Error);
}

// Brute force by enumeration, independent of the clipping: the minimum of the
// axial distance over (triangle ∩ pyramid) lies at a triangle vertex inside
// the pyramid, where a triangle edge crosses a side plane inside the
// pyramid, or where a pyramid edge (the ray from l through a corner) pierces
// the triangle; every such point is computed exactly and tested for
// membership, and the smallest is compared with L*.
std::optional<Rational> enumerated_l_near(const CameraSpaceScene& cs) {
  const Frustum& f = cs.frustum();
  const RationalVec3& l = cs.exact_light(0);
  const Rational near(f.near);
  const int alpha = sgn(Rational(l.z + near));
  const std::array<RationalVec3, 4> corners{RationalVec3{Rational(f.left), Rational(f.bottom), -near},
                                            RationalVec3{Rational(f.right), Rational(f.bottom), -near},
                                            RationalVec3{Rational(f.right), Rational(f.top), -near},
                                            RationalVec3{Rational(f.left), Rational(f.top), -near}};
  // Inside the closed pyramid: in front of the light and, projected from l
  // onto the near plane, inside the rectangle.
  auto inside = [&](const RationalVec3& p) {
    const Rational depth = Rational(alpha) * (l.z - p.z);
    if (sgn(depth) <= 0) return false;
    const Rational t = (-near - l.z) / (p.z - l.z);
    const Rational x = l.x + t * (p.x - l.x), y = l.y + t * (p.y - l.y);
    return x >= Rational(f.left) && x <= Rational(f.right) && y >= Rational(f.bottom) && y <= Rational(f.top);
  };
  std::optional<Rational> best;
  auto consider = [&](const RationalVec3& p) {
    if (!inside(p)) return;
    const Rational depth = Rational(alpha) * (l.z - p.z);
    if (!best || depth < *best) best = depth;
  };
  for (std::size_t o = 0; o < cs.object_count(); ++o) {
    if (!cs.object(o).occluder) continue;
    for (const auto& t : cs.mesh(o).triangles) {
      const std::array<RationalVec3, 3> v{cs.exact_vertex(o, t[0]), cs.exact_vertex(o, t[1]), cs.exact_vertex(o, t[2])};
      for (const RationalVec3& p : v) consider(p);
      for (int e = 0; e < 3; ++e)
        for (int k = 0; k < 4; ++k) {  // edge e against side plane k
          const Vec3<Rational> n = cross(corners[k] - l, corners[(k + 1) % 4] - l);
          const Rational da = dot(n, v[e] - l), db = dot(n, v[(e + 1) % 3] - l);
          if (sgn(da) * sgn(db) < 0) consider(v[e] + Rational(da / (da - db)) * (v[(e + 1) % 3] - v[e]));
        }
      const Vec3<Rational> normal = cross(v[1] - v[0], v[2] - v[0]);
      for (int k = 0; k < 4; ++k) {  // pyramid edge k against the triangle
        const RationalVec3 dir = corners[k] - l;
        const Rational denom = dot(normal, dir);
        if (sgn(denom) == 0) continue;
        const Rational s = Rational(dot(normal, v[0] - l)) / denom;
        if (sgn(s) <= 0) continue;
        const RationalVec3 p = l + s * dir;
        // p inside the triangle: same side of the three edges within its plane.
        int pos = 0, neg = 0;
        for (int e = 0; e < 3; ++e) {
          const int side = sgn(dot(cross(v[(e + 1) % 3] - v[e], p - v[e]), normal));
          pos += side > 0;
          neg += side < 0;
        }
        if (pos == 0 || neg == 0) consider(p);
      }
    }
  }
  return best;
}

TEST(LightPyramid, EqualsTheEnumerationOfEveryCandidatePoint) {
  analysis::SamplerSpec spec = test::bundled_sampler_spec(31);
  spec.width = 8;
  spec.height = 8;
  spec.kinds = {analysis::HardCaseKind::Straddling, analysis::HardCaseKind::SeveralOccluders,
                analysis::HardCaseKind::EyeInShadow, analysis::HardCaseKind::LightNearNearPlane};
  const analysis::HardCaseSampler sampler(spec);
  int compared = 0, nonempty = 0;
  test::for_each_sampled_scene(sampler, 36, [&](const Scene& scene, const analysis::HardCase& sample) {
    const CameraSpaceScene cs(scene);
    if (sgn(Rational(cs.exact_light(0).z + Rational(scene.camera.frustum.near))) == 0) return;
    const AdmissibleLightNear a = max_admissible_light_near(cs, 0);
    const std::optional<Rational> brute = enumerated_l_near(cs);
    ++compared;
    nonempty += brute.has_value();
    ASSERT_EQ(a.l_near.has_value(), brute.has_value()) << "sample " << sample.index;
    if (brute) {
      EXPECT_EQ(*a.l_near, *brute) << "sample " << sample.index;
    }
  });
  EXPECT_GE(compared, 24);
  EXPECT_GE(nonempty, 6);
}

// On hard cases: the paper's l_far d / d_max never exceeds L* (it is
// admissible by construction); no occluder vertex in the pyramid lies nearer
// than L*; exact-max's float l_near never exceeds L*.
TEST(LightPyramid, ThePaperRatioIsAdmissibleAndNoVertexIsNearer) {
  analysis::SamplerSpec spec = test::bundled_sampler_spec(77);
  spec.width = 8;
  spec.height = 8;
  const analysis::HardCaseSampler sampler(spec);
  int checked = 0, with_l_near = 0;
  test::for_each_sampled_scene(sampler, 120, [&](const Scene& scene, const analysis::HardCase& sample) {
    const std::uint64_t k = sample.index;
    const CameraSpaceScene cs(scene);
    if (sgn(Rational(cs.exact_light(0).z + Rational(scene.camera.frustum.near))) == 0) return;
    const AdmissibleLightNear a = max_admissible_light_near(cs, 0);
    ++checked;
    if (!a.l_near) return;
    ++with_l_near;
    const Rational& best = *a.l_near;
    // The paper's rule without the cap, in double (d and d_max as the light frustum computes them).
    gl::LightFrustumChoice paper;
    const gl::LightFrustum lf = gl::light_frustum(scene, 0, paper);
    if (lf.d_max > 0) {
      const double ratio_l_near = to_double(a.l_far) * lf.d / lf.d_max;
      EXPECT_LE(ratio_l_near, to_double(best) * (1 + 1e-9)) << "sample " << k;
    }
    // No occluder vertex strictly inside the pyramid is nearer to the light.
    const RationalVec3& l = cs.exact_light(0);
    const int alpha = sgn(Rational(l.z + Rational(scene.camera.frustum.near)));
    const Frustum& f = scene.camera.frustum;
    for (std::size_t o = 0; o < cs.object_count(); ++o) {
      if (!cs.object(o).occluder) continue;
      for (VertexIndex v = 0; v < cs.mesh(o).positions.size(); ++v) {
        const RationalVec3 p = cs.exact_vertex(o, v);
        const Rational depth = Rational(alpha) * (l.z - p.z);
        if (sgn(depth) <= 0) continue;
        // The point where the ray from l through p meets the near plane.
        const Rational t = (Rational(-f.near) - l.z) / (p.z - l.z);
        const Rational x = l.x + t * (p.x - l.x), y = l.y + t * (p.y - l.y);
        const bool inside =
            x > Rational(f.left) && x < Rational(f.right) && y > Rational(f.bottom) && y < Rational(f.top);
        if (inside) {
          EXPECT_GE(depth, best) << "sample " << k << " object " << o << " vertex " << v;
        }
      }
    }
    gl::LightFrustumChoice exact;
    exact.near_rule = gl::LightNearRule::ExactMax;
    const gl::LightFrustum le = gl::light_frustum(scene, 0, exact);
    if (le.defined) {
      EXPECT_LE(Rational(static_cast<double>(le.l_near)), best) << "sample " << k;
    }
  });
  EXPECT_GE(checked, 80);
  EXPECT_GE(with_l_near, 20);
}

// The per-occluder pyramid test against the per-pixel truth: an occluder whose
// own near-cap covers a pixel centre always meets the pyramid; one that meets
// it and covers no pixel centre is rare (a sliver of shadow between centres).
TEST(LightPyramid, OccludersMeetingThePyramidAreThoseWithANearCap) {
  std::size_t meeting = 0, covering = 0, between_centres = 0, scenes = 0;
  for (analysis::HardCaseKind kind : {analysis::HardCaseKind::SeveralOccluders, analysis::HardCaseKind::EyeInShadow,
                                      analysis::HardCaseKind::Straddling, analysis::HardCaseKind::LightNearNearPlane,
                                      analysis::HardCaseKind::Grazing}) {
    analysis::SamplerSpec spec = test::bundled_sampler_spec(21);
    spec.kinds = {kind};
    const analysis::HardCaseSampler sampler(spec);
    test::for_each_sampled_scene(sampler, 12, [&](const Scene& s, const analysis::HardCase& sample) {
      const CameraSpaceScene cs(s);
      for (std::size_t light = 0; light < s.lights.size(); ++light) {
        std::vector<bool> meets;
        try {
          meets = occluders_meeting_light_pyramid(cs, light);
        } catch (const Error& e) {
          EXPECT_EQ(e.kind(), ErrorKind::Degenerate);  // the light in the near plane
          continue;
        }
        ++scenes;
        const PixelReference ref = compute_pixel_reference(cs, light);
        for (std::size_t o = 0; o < s.objects.size(); ++o) {
          if (!s.objects[o].occluder) {
            EXPECT_FALSE(meets[o]);
            continue;
          }
          const bool covers = ref.cap_pixels_by_object[o] > 0;
          if (covers) {
            EXPECT_TRUE(meets[o]) << to_string(kind) << " sample " << sample.index << " object " << o;
          }
          meeting += meets[o];
          covering += covers;
          between_centres += meets[o] && !covers;
        }
      }
    });
  }
  EXPECT_GT(scenes, 40u);
  EXPECT_GT(covering, 20u);
  EXPECT_LE(between_centres * 10, meeting) << between_centres << " of " << meeting;
}

}  // namespace
}  // namespace nearcap
