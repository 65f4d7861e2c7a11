// AtomicZP as a candidate of the switch policy's cost decision
// (switch_policy.hpp, decide with a device profile that has the eye-count
// row): offered only where it is right wherever Z-fail is (the near plane
// clear of the occluder, the eye count decided robustly), chosen where it
// is cheapest, priced with the frame's one eye-count pass, and absent from
// a profile without the row.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "box_scene.hpp"
#include "nearcap/analysis/calibration_file.hpp"
#include "nearcap/analysis/device_profile_fit.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/analysis/near_rectangle_pyramid.hpp"
#include "nearcap/analysis/side_plane_clearance.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/analysis/work_estimate.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/eye_count.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/gl/eye_count.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/io/scene_builder.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "support/sampled_scenes.hpp"

namespace nearcap {
namespace {

using analysis::DeviceProfile;
using analysis::PassKind;
using analysis::SwitchPolicy;
using gl::ShadowMethod;

std::size_t k(PassKind p) { return static_cast<std::size_t>(p); }

// Every pass at one price, the caps (their triangles and fragments) and the
// near-cap dear, and the eye-count pass cheap: AtomicZP is the cheapest
// candidate wherever it is offered and Z-pass is not right.
DeviceProfile atomiczp_favoured() {
  DeviceProfile p;
  p.origin = "hand";
  for (analysis::PassCost& c : p.passes) c = {0.1, 10.0, 1.0};
  for (PassKind dear : {PassKind::LightCap, PassKind::DarkCap, PassKind::NearCap}) {
    p.passes[k(dear)].intercept_ms = 5;
    p.passes[k(dear)].ms_per_mfragment = 1e3;
  }
  for (PassKind dear : {PassKind::LightCap, PassKind::DarkCap}) p.passes[k(dear)].ms_per_mtriangle = 1e4;
  p.eye_count = analysis::PassCost{0.1, 10.0, 0.01};
  p.cpu.ms_per_ktriangle_silhouette = 0.01;
  p.cpu.clipped_cap.intercept_ms = 5;
  return p;
}

// atomiczp_favoured() with the eye-count pass nearly free and the caps'
// triangles dear: AtomicZP cheaper than Z-fail on every occluder, so the
// candidate's conditions alone decide whether it is drawn.
DeviceProfile atomiczp_cheapest() {
  DeviceProfile p = atomiczp_favoured();
  p.eye_count = analysis::PassCost{0.001, 1.0, 0.001};
  for (PassKind dear : {PassKind::LightCap, PassKind::DarkCap}) p.passes[k(dear)].ms_per_mtriangle = 1e5;
  return p;
}

SwitchPolicy cost_policy(const DeviceProfile& profile) {
  SwitchPolicy p;
  p.capped_method = ShadowMethod::ZPPlus;
  p.light_projection = gl::LightProjection::ClippedSides;
  p.exact_zpass = false;
  p.device_profile = profile;
  return p;
}

Scene bundled(const std::string& name) { return load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name); }

// The decision's frame against Z-fail's and Z-pass's, judged by the exact
// reference: never wronger than Z-fail, on a frame where Z-pass is wrong
// (the case AtomicZP is for).  `what` names the frame in the printed line.
void expect_right_where_zpass_is_wrong(const Scene& s, const CameraSpaceScene& cs, const analysis::PolicyDecision& d,
                                       const char* what) {
  const PixelReference ref = compute_pixel_reference(cs, 0);
  gl::ShadowFrameBatch batch(s, 0, d.settings);
  const CrackReport chosen = judge_frame(batch.render(d.object_methods), ref);
  const CrackReport zfail = judge_frame(gl::render_shadow_frame(s, 0, ShadowMethod::ZFail, d.settings), ref);
  const CrackReport zpass = judge_frame(gl::render_shadow_frame(s, 0, ShadowMethod::ZPass, d.settings), ref);
  std::printf("%s: the decision's frame wrong on %zu, zfail %zu, zpass %zu of %zu seen\n", what, chosen.wrong,
              zfail.wrong, zpass.wrong, chosen.pixels_seen);
  EXPECT_LE(chosen.wrong, zfail.wrong) << what;
  EXPECT_GT(zpass.wrong, 100u) << what << ": Z-pass is wrong here, the case AtomicZP is for";
}

bool is_wrong(PixelVerdict v) { return v == PixelVerdict::WrongLit || v == PixelVerdict::WrongShadowed; }

// Pixels of `frame` wrong where Z-fail's frame (same settings) is right.
std::size_t wrong_where_zfail_right(const Scene& s, const PixelReference& ref, const gl::ShadowFrame& frame,
                                    const gl::EmulationSettings& settings) {
  const CrackReport judged = judge_frame(frame, ref);
  const CrackReport zfail = judge_frame(gl::render_shadow_frame(s, 0, ShadowMethod::ZFail, settings), ref);
  std::size_t worse = 0;
  for (std::size_t p = 0; p < judged.verdict.size(); ++p)
    worse += is_wrong(judged.verdict[p]) && !is_wrong(zfail.verdict[p]) ? 1 : 0;
  return worse;
}

// The box over the eye (the eye in its volume, the near plane clear of it):
// AtomicZP is offered and, with the profile above, chosen; the frame it
// gives is as right as Z-fail's.  Without the eye-count row it is neither
// chosen nor named.
TEST(AtomicZPCandidate, ChosenWhereRightAndCheapest) {
  const Scene s = test::box_scene({0.1, -1.5, 0.2}, {0, 8, 0});
  const CameraSpaceScene cs(s);
  ASSERT_EQ(exact_eye_count(cs, 0).count, 1u);
  const analysis::PolicyDecision d = analysis::decide(cost_policy(atomiczp_favoured()), cs, 0, {});
  EXPECT_EQ(d.object_methods[0], ShadowMethod::AtomicZP) << d.reason(0);
  EXPECT_NE(d.reason(0).find("cost: atomiczp"), std::string::npos) << d.reason(0);
  EXPECT_NE(d.reason(0).find("eye count 1, exact and float agree"), std::string::npos) << d.reason(0);
  EXPECT_TRUE(d.predicted_work.eye_count.drawn);
  EXPECT_DOUBLE_EQ(d.predicted_work.eye_count.triangles, 12.0);
  EXPECT_DOUBLE_EQ(d.predicted_work.eye_count.fragments, static_cast<double>(s.camera.width) * s.camera.height);
  EXPECT_DOUBLE_EQ(d.predicted_ms, atomiczp_favoured().predict_ms(d.predicted_work));
  bool eye_option = false;
  for (const auto& [name, ms] : d.predicted_options)
    eye_option = eye_option || name.find("eye count") != std::string::npos;
  EXPECT_TRUE(eye_option);

  expect_right_where_zpass_is_wrong(s, cs, d, "box over the eye");

  // No eye-count row: not a candidate, and the reasons do not name it.
  DeviceProfile without = atomiczp_favoured();
  without.eye_count.reset();
  const analysis::PolicyDecision w = analysis::decide(cost_policy(without), cs, 0, {});
  EXPECT_NE(w.object_methods[0], ShadowMethod::AtomicZP) << w.reason(0);
  EXPECT_EQ(w.reason(0).find("atomiczp"), std::string::npos) << w.reason(0);
  EXPECT_FALSE(w.predicted_work.eye_count.drawn);
  // A dear eye-count pass: priced out.
  DeviceProfile dear = atomiczp_favoured();
  dear.eye_count->intercept_ms = 100;
  EXPECT_NE(analysis::decide(cost_policy(dear), cs, 0, {}).object_methods[0], ShadowMethod::AtomicZP);
}

// The near plane cuts the occluder (case_d: the box through the near
// plane): AtomicZP misses the light cap's crossings in front of it
// (docs/atomiczp.md) and is not offered.
TEST(AtomicZPCandidate, NotOfferedWhereTheNearPlaneCutsTheOccluder) {
  for (const char* name : {"case_d.json", "light_on_near_plane.json"}) {
    const Scene s = bundled(name);
    const CameraSpaceScene cs(s);
    const analysis::PolicyDecision d = analysis::decide(cost_policy(atomiczp_favoured()), cs, 0, {});
    for (std::size_t o = 0; o < s.objects.size(); ++o) {
      if (!s.objects[o].occluder) continue;
      EXPECT_NE(d.object_methods[o], ShadowMethod::AtomicZP) << name << ": " << d.reason(o);
      EXPECT_NE(d.reason(o).find("atomiczp not a candidate (the near plane cuts the occluder)"), std::string::npos)
          << name << ": " << d.reason(o);
    }
  }
}

// A box wholly behind the eye, between it and a light behind the camera:
// the eye is in its volume, which fills the middle of the view (Z-pass is
// wrong there).  No point of the box is in front of the eye, so the near
// plane does not cut it: AtomicZP is offered, chosen, and as right as
// Z-fail.  A box beside the eye reaching from behind its plane to beyond
// the near plane (none of its vertices between them, its side faces across
// them outside the view) meets no view ray in front of the near plane: it
// is offered too, and the decision's frame is wrong on no pixel where
// Z-fail is right.  A thin plank just under the eye, from behind its plane
// to beyond the near plane across the view, is not.
TEST(AtomicZPCandidate, OfferedForAnOccluderBehindTheEyeOrAcrossTheEyesPlaneOutsideTheViewNotInside) {
  const TriangleMesh box = read_mesh(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/box.off");
  auto scene = [&](const Affine3d& at) {
    SceneBuilder b("box behind the eye");
    b.camera(look_at_camera({0, 0, 0}, {0, -0.5, -4}, {0, 1, 0}, 60, 0.05, 100, 64, 48));
    b.light({0, 0.5, 8});
    b.object(box, at);
    Affine3d ground = test::translate(0, -20.6, 0);
    for (int k = 0; k < 3; ++k) ground.rows[k][k] = 40;
    b.receiver(box, ground);
    return b.build();
  };
  const Scene behind = scene(test::translate(0, 0.25, 4));
  const CameraSpaceScene cs(behind);
  ASSERT_EQ(exact_eye_count(cs, 0).count, 1u);
  const analysis::PolicyDecision d = analysis::decide(cost_policy(atomiczp_favoured()), cs, 0, {});
  EXPECT_EQ(d.object_methods[0], ShadowMethod::AtomicZP) << d.reason(0);
  expect_right_where_zpass_is_wrong(behind, cs, d, "box behind the eye");

  Affine3d across = test::translate(0.5, 0, 0);
  for (int k = 0; k < 3; ++k) across.rows[k][k] = 0.6;  // x 0.2 .. 0.8, z -0.3 .. 0.3
  const Scene beside = scene(across);
  const CameraSpaceScene cs2(beside);
  const analysis::PolicyDecision d2 = analysis::decide(cost_policy(atomiczp_favoured()), cs2, 0, {});
  EXPECT_EQ(d2.object_methods[0], ShadowMethod::AtomicZP) << d2.reason(0);
  const PixelReference ref2 = compute_pixel_reference(cs2, 0);
  gl::ShadowFrameBatch batch2(beside, 0, d2.settings);
  const std::size_t worse = wrong_where_zfail_right(beside, ref2, batch2.render(d2.object_methods), d2.settings);
  std::printf("box beside the eye, across its plane: the decision's frame wrong on %zu pixels where zfail is right\n",
              worse);
  EXPECT_EQ(worse, 0u);

  Affine3d plank = test::translate(0, -0.012, 0);  // y -0.014 .. -0.010, x and z -0.5 .. 0.5
  plank.rows[0][0] = plank.rows[2][2] = 1;
  plank.rows[1][1] = 0.004;
  const Scene under = scene(plank);
  const CameraSpaceScene cs3(under);
  const analysis::PolicyDecision d3 = analysis::decide(cost_policy(atomiczp_favoured()), cs3, 0, {});
  EXPECT_NE(d3.object_methods[0], ShadowMethod::AtomicZP) << d3.reason(0);
  EXPECT_NE(d3.reason(0).find("atomiczp not a candidate (the near plane cuts the occluder)"), std::string::npos)
      << d3.reason(0);
}

// One triangle (camera space: the view is the identity, the frustum the
// default one, x and y in [-1, 1] at near 1) against the near-rectangle
// pyramid, by both entry points: the filtered one (vertex signs first) and
// the exact clipping alone.  They must agree.
bool meets_default_pyramid(const std::array<Vec3d, 3>& t) {
  Scene s;
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->positions = {t[0], t[1], t[2]};
  mesh->triangles = {{0, 1, 2}};
  s.objects.push_back({"triangle", mesh, Affine3d::identity(), true});
  const CameraSpaceScene cs(s);
  const bool filtered = analysis::triangle_meets_near_rectangle_pyramid(cs, 0, {0, 1, 2}, s.camera.frustum);
  const bool clipped = analysis::triangle_meets_near_rectangle_pyramid(
      {cs.exact_vertex(0, 0), cs.exact_vertex(0, 1), cs.exact_vertex(0, 2)}, s.camera.frustum);
  EXPECT_EQ(filtered, clipped);
  return filtered;
}

// Triangles from behind the eye's plane to beyond the near plane, no vertex
// between them (the per-vertex test leaves each to the pyramid): one across
// the view meets the pyramid, one beside it does not; one lying in the right
// side plane x = -z (touching the pyramid along a segment of that plane), one
// through the eye alone, and one with an edge through a corner of the near
// rectangle alone meet it (touching counts); the same three moved out by
// 2^-40 are clear.
TEST(AtomicZPCandidate, NearRectanglePyramidTouchingCountsAsMeeting) {
  const double out = std::ldexp(1.0, -40);
  // Across the view: through the view axis at y = 0.01.
  EXPECT_TRUE(meets_default_pyramid({{{-1, 0.01, 1}, {1, 0.01, 1}, {0, 0.01, -2}}}));
  // Beside the view, across the slab: clear.
  EXPECT_FALSE(meets_default_pyramid({{{3, 0, 1}, {3, 1, 1}, {3, 0, -2}}}));
  // In the side plane x = -z (through (0.5, 0, -0.5), inside |y| <= 0.5).
  EXPECT_TRUE(meets_default_pyramid({{{-1, 0, 1}, {2, 0, -2}, {2, 5, -2}}}));
  EXPECT_FALSE(meets_default_pyramid({{{-1 + out, 0, 1}, {2 + out, 0, -2}, {2 + out, 5, -2}}}));
  // Through the eye, otherwise outside (x / -z = 2.5 > 1 beyond it).
  EXPECT_TRUE(meets_default_pyramid({{{0, 0, 0}, {5, 0, -2}, {5, 1, -2}}}));
  EXPECT_FALSE(meets_default_pyramid({{{out, 0, 0}, {5 + out, 0, -2}, {5 + out, 1, -2}}}));
  // An edge through the near rectangle's corner (1, 1, -1) from outside it,
  // the triangle otherwise beyond x = -z and y = -z.
  EXPECT_TRUE(meets_default_pyramid({{{3, 3, 1}, {-1, -1, -3}, {5, 5, -3}}}));
  EXPECT_FALSE(meets_default_pyramid({{{3 + out, 3, 1}, {-1 + out, -1, -3}, {5 + out, 5, -3}}}));
}

// eye_in_shadow.json: the camera under the lit slab, Z-pass wrong on the
// whole frame.  The slab's faces reach from behind the eye's plane to beyond
// the near plane, across the slab between them outside the view: no view
// ray meets the slab in front of the near plane, AtomicZP is offered, chosen
// with the profile that favours it, and as right as Z-fail.
TEST(AtomicZPCandidate, OfferedOnEyeInShadowsSlabWhichCrossesTheEyesPlaneOutsideTheView) {
  const Scene s = bundled("eye_in_shadow.json");
  const CameraSpaceScene cs(s);
  // Some triangle of the slab lies across the eye's plane (the per-vertex
  // test alone would refuse it).
  std::size_t across = 0;
  for (const auto& t : s.objects[0].mesh->triangles) {
    int behind = 0, beyond = 0;
    for (VertexIndex v : t) {
      behind += sgn(cs.exact_vertex(0, v).z) >= 0 ? 1 : 0;
      beyond += cs.exact_vertex(0, v).z < Rational(-s.camera.frustum.near) ? 1 : 0;
    }
    across += behind != 3 && beyond != 3 ? 1 : 0;
  }
  std::printf("eye_in_shadow: %zu of the slab's triangles across the eye's plane\n", across);
  ASSERT_GT(across, 0u);
  const analysis::PolicyDecision d = analysis::decide(cost_policy(atomiczp_favoured()), cs, 0, {});
  EXPECT_EQ(d.object_methods[0], ShadowMethod::AtomicZP) << d.reason(0);
  expect_right_where_zpass_is_wrong(s, cs, d, "eye_in_shadow");
}

// The eye exactly on a side plane of the box's volume, the segment eye ->
// light through the box's top edge: the exact count is decided by the
// perturbation (on_boundary), no constant is right on the whole frame, and
// AtomicZP is not offered, although here the float count equals the exact
// one and the box is beyond the near plane.  The camera looks straight up
// at the box (up +z), so its view is exact and the eye is the camera-space
// origin exactly; the view direction points out of the volume, so the
// perturbed count is 0, as the float one.
TEST(AtomicZPCandidate, NotOfferedWhereTheEyeIsOnAVolumesBoundary) {
  const TriangleMesh box = read_mesh(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/box.off");
  // The plane through the light (0, 5, -3) and the top edge x = 0.5, y = 0.5
  // of the box centred at (0, 0, -3) holds x = 0.5 (5 - y) / 4.5: at y = -4,
  // x = 1.
  SceneBuilder b("eye on a side plane");
  b.camera(look_at_camera({1, -4, -3}, {1, 0, -3}, {0, 0, 1}, 60, 0.05, 100, 64, 48));
  b.light({0, 5, -3});
  b.object(box, test::translate(0, 0, -3));
  const Scene s = b.build();
  const CameraSpaceScene cs(s);
  const ExactEyeCount exact = exact_eye_count(cs, 0);
  const gl::FloatEyeCount fl = gl::float_eye_count(s, 0);
  std::printf("eye on the side plane: exact %zu (on_boundary %d), float %zu\n", exact.count, int(exact.on_boundary),
              fl.count);
  ASSERT_TRUE(exact.on_boundary);
  ASSERT_EQ(fl.count, exact.count) << "the test is of on_boundary alone";
  const analysis::PolicyDecision d = analysis::decide(cost_policy(atomiczp_favoured()), cs, 0, {});
  EXPECT_NE(d.object_methods[0], ShadowMethod::AtomicZP) << d.reason(0);
  EXPECT_NE(d.reason(0).find("on_boundary"), std::string::npos) << d.reason(0);
}

// The eye within a fraction of a float32 ulp of a side plane (the unit box
// under a light at (0, 5, 0), the eye beside it looking at it down -x, as in
// AtomicZP.FloatEyeCountWrongNearASidePlaneAndTheFrameInverts), where the
// float count is not the exact one and no tie is at the eye: not offered.
TEST(AtomicZPCandidate, NotOfferedWhereTheFloatEyeCountIsWrong) {
  const double step = std::ldexp(1.0, -30);  // 1/64 of float32's spacing at 0.5 .. 1
  int found = 0, offered = 0;
  for (int k = -2048; k <= 2048 && found < 3; ++k) {
    const double x = test::kSidePlaneX + k * step;
    test::BoxSceneOptions o;
    o.width = 32;
    o.height = 24;
    o.target = {x - 1, -0.1, 0};
    const Scene s = test::box_scene({x, -0.1, 0}, {0, 5, 0}, o);
    const CameraSpaceScene cs(s);
    if (gl::float_eye_count(s, 0).count == exact_eye_count(cs, 0).count) continue;
    ++found;
    const analysis::PolicyDecision d = analysis::decide(cost_policy(atomiczp_favoured()), cs, 0, {});
    offered += d.object_methods[0] == ShadowMethod::AtomicZP ? 1 : 0;
    EXPECT_NE(d.reason(0).find("float eye count"), std::string::npos) << "k " << k << ": " << d.reason(0);
  }
  std::printf("eyes with a wrong float count: %d found, AtomicZP offered at %d\n", found, offered);
  ASSERT_GT(found, 0);
  EXPECT_EQ(offered, 0);
}

analysis::HardCaseSampler eye_near_volume_sampler() {
  analysis::SamplerSpec spec = test::bundled_sampler_spec(28);
  spec.kinds = {analysis::HardCaseKind::EyeNearVolume};
  return analysis::HardCaseSampler(spec);
}

// Configuration 11 of `nearcap sweep --samples 40 --seed 28 --kinds
// eye-near-volume`: the eye a few nanometres from a side plane of the box's
// volume, both eye counts right, no tie at the eye, the near plane clear of
// the box, and still AtomicZP's frame wrong where Z-fail is right (the side
// quad seen almost edge-on).  Only the side-plane condition refuses it.
TEST(AtomicZPCandidate, NotOfferedWhereASidePlanePassesTheEyeWithinTheFloatBound) {
  const analysis::HardCaseSampler sampler = eye_near_volume_sampler();
  const analysis::HardCase sample = sampler.sample(11);
  const std::optional<Scene> s = test::sampled_scene(sample);
  ASSERT_TRUE(s) << sample.detail;
  const CameraSpaceScene cs(*s);
  const ExactEyeCount exact = exact_eye_count(cs, 0);
  ASSERT_FALSE(exact.on_boundary) << sample.detail;
  ASSERT_EQ(gl::float_eye_count(*s, 0).count, exact.count) << sample.detail;
  const analysis::SidePlaneClearance clearance = analysis::side_plane_clearance(cs, 0, 0);
  std::printf("configuration 11 (%s): eye count %zu, nearest side plane %.4g units of 2^-24 M (bound %g), %zu edges\n",
              sample.detail.c_str(), exact.count, clearance.nearest_units, analysis::kSidePlaneBoundUnits,
              clearance.edges);
  // AtomicZP's frame is wrong here where Z-fail is right: the refusal is needed.
  const PixelReference ref = compute_pixel_reference(cs, 0);
  const std::size_t worse =
      wrong_where_zfail_right(*s, ref, gl::render_shadow_frame(*s, 0, ShadowMethod::AtomicZP), {});
  std::printf("configuration 11: atomiczp wrong on %zu pixels where zfail is right\n", worse);
  EXPECT_GT(worse, 0u);
  const analysis::PolicyDecision d = analysis::decide(cost_policy(atomiczp_cheapest()), cs, 0, {});
  EXPECT_NE(d.object_methods[0], ShadowMethod::AtomicZP) << d.reason(0);
  EXPECT_NE(d.reason(0).find("atomiczp not a candidate (a side plane of its volume passes the eye within the float32 "
                             "bound"),
            std::string::npos)
      << d.reason(0);
}

// Over the 40 eye-near-volume configurations of seed 28: wherever the
// candidate admits AtomicZP for every occluder (and, with the profile that
// favours it, the decision draws it), the decision's frame is wrong on no
// pixel where Z-fail is right.  Prints how many were admitted and why the
// others were not.
TEST(AtomicZPCandidate, AsRightAsZFailWhereverAdmittedOnTheEyeNearVolumeConfigurations) {
  const analysis::HardCaseSampler sampler = eye_near_volume_sampler();
  std::size_t admitted = 0, refused = 0, side_plane = 0;
  test::for_each_sampled_scene(sampler, 40, [&](const Scene& s, const analysis::HardCase& sample) {
    const CameraSpaceScene cs(s);
    const analysis::PolicyDecision d = analysis::decide(cost_policy(atomiczp_cheapest()), cs, 0, {});
    bool all = true;
    for (std::size_t o = 0; o < s.objects.size(); ++o) {
      if (!s.objects[o].occluder) continue;
      const bool chosen = d.object_methods[o] == ShadowMethod::AtomicZP;
      all = all && chosen;
      if (!chosen && d.reason(o).find("side plane") != std::string::npos) ++side_plane;
      if (!chosen)
        std::printf("configuration %llu: %s\n", static_cast<unsigned long long>(sample.index), d.reason(o).c_str());
    }
    if (!all) {
      ++refused;
      return;
    }
    ++admitted;
    const PixelReference ref = compute_pixel_reference(cs, 0);
    gl::ShadowFrameBatch batch(s, 0, d.settings);
    const std::size_t worse = wrong_where_zfail_right(s, ref, batch.render(d.object_methods), d.settings);
    EXPECT_EQ(worse, 0u) << "configuration " << sample.index << " (" << sample.detail << "): " << d.reason(0);
  });
  std::printf(
      "eye-near-volume, seed 28: AtomicZP admitted for every occluder on %zu, not on %zu (%zu refused by "
      "the side-plane condition)\n",
      admitted, refused, side_plane);
  EXPECT_GT(admitted, 10u);
  EXPECT_GT(side_plane, 0u);
}

// On bundled scenes, with the profile that favours AtomicZP: wherever it is
// chosen, the decision's frame is wrong on no pixel where Z-fail is right,
// and the frame's count is over its AtomicZP occluders only.
TEST(AtomicZPCandidate, NeverWrongWhereZFailIsRightOnBundledScenes) {
  std::size_t chosen = 0;
  for (const char* name : {"default", "eye_in_shadow", "near_split", "case_d", "room", "room_side_light",
                           "no_near_clip", "near_cap_bunny_wall", "far_grazing", "atomiczp_side_plane"}) {
    const Scene s = bundled(std::string(name) + ".json");
    const CameraSpaceScene cs(s);
    const analysis::PolicyDecision d = analysis::decide(cost_policy(atomiczp_favoured()), cs, 0, {});
    std::size_t here = 0;
    for (std::size_t o = 0; o < s.objects.size(); ++o) here += d.object_methods[o] == ShadowMethod::AtomicZP ? 1 : 0;
    chosen += here;
    if (here == 0) continue;
    const PixelReference ref = compute_pixel_reference(cs, 0);
    gl::ShadowFrameBatch batch(s, 0, d.settings);
    const gl::ShadowFrame frame = batch.render(d.object_methods);
    const CrackReport policy = judge_frame(frame, ref);
    const CrackReport zfail = judge_frame(gl::render_shadow_frame(s, 0, ShadowMethod::ZFail, d.settings), ref);
    std::size_t worse = 0;
    for (std::size_t p = 0; p < policy.verdict.size(); ++p) {
      const bool policy_wrong =
          policy.verdict[p] == PixelVerdict::WrongLit || policy.verdict[p] == PixelVerdict::WrongShadowed;
      const bool zfail_wrong =
          zfail.verdict[p] == PixelVerdict::WrongLit || zfail.verdict[p] == PixelVerdict::WrongShadowed;
      worse += policy_wrong && !zfail_wrong ? 1 : 0;
    }
    std::printf("%s: atomiczp for %zu occluders; wrong %zu (zfail %zu), %zu where zfail is right\n", name, here,
                policy.wrong, zfail.wrong, worse);
    EXPECT_EQ(worse, 0u) << name;
  }
  EXPECT_GT(chosen, 0u);
}

// The profile's eye-count row is optional in policy.json: absent, the
// profile reads as without it and writes without it; present, it round-trips.
TEST(AtomicZPCandidate, EyeCountRowIsOptionalInTheProfile) {
  DeviceProfile p = atomiczp_favoured();
  p.eye_count.reset();
  const std::string without = analysis::device_profile_to_json(p);
  EXPECT_EQ(without.find("eye_count"), std::string::npos);
  EXPECT_FALSE(analysis::parse_device_profile(without, "test").eye_count);
  p.eye_count = analysis::PassCost{0.25, 3.5, 0.125};
  const std::string with = analysis::device_profile_to_json(p);
  const DeviceProfile back = analysis::parse_device_profile(with, "test");
  ASSERT_TRUE(back.eye_count);
  EXPECT_EQ(back.eye_count->intercept_ms, 0.25);
  EXPECT_EQ(back.eye_count->ms_per_mtriangle, 3.5);
  EXPECT_EQ(back.eye_count->ms_per_mfragment, 0.125);
  const DeviceProfile scaled = analysis::scaled_profile(back, 100.0);
  ASSERT_TRUE(scaled.eye_count);
  EXPECT_EQ(scaled.eye_count->intercept_ms, 0.0025);
  // A negative cost in the row is refused like any other pass's.
  std::string bad = with;
  const std::size_t at = bad.find("0.25");
  ASSERT_NE(at, std::string::npos);
  bad.replace(at, 4, "-0.25");
  EXPECT_THROW(analysis::parse_device_profile(bad, "test"), Error);
}

// `nearcap calibrate`'s eye-count rows: written as "pass" rows of kind
// eye_count, read back into the set's eye_count observations, and fitted
// into the profile's row (known costs recovered from noisy timings).
TEST(AtomicZPCandidate, EyeCountObservationsRoundTripAndFit) {
  analysis::CalibrationSet set;
  std::mt19937_64 rng(28);
  std::uniform_real_distribution<double> noise(0.95, 1.05);
  std::uniform_int_distribution<int> triangles(12, 40000);
  const double intercept = 0.3, per_mtriangle = 40.0;  // the true row, at 160 x 120
  for (int k = 0; k < 200; ++k) {
    const double t = triangles(rng);
    set.eye_count.push_back({"sample:28:" + std::to_string(k) + ":light0:atomiczp", t, 19200,
                             (intercept + per_mtriangle * t * 1e-6) * noise(rng)});
  }
  const std::string csv = analysis::calibration_csv(set);
  EXPECT_NE(csv.find(",eye_count,"), std::string::npos);
  const analysis::CalibrationSet back = analysis::parse_calibration_csv(csv, "test");
  ASSERT_EQ(back.eye_count.size(), set.eye_count.size());
  EXPECT_TRUE(back.passes.empty());
  for (std::size_t k = 0; k < set.eye_count.size(); ++k) {
    EXPECT_EQ(back.eye_count[k].frame, set.eye_count[k].frame);
    EXPECT_EQ(back.eye_count[k].triangles, set.eye_count[k].triangles);
    EXPECT_EQ(back.eye_count[k].ms, set.eye_count[k].ms);
  }
  analysis::EyeCountFitReport report;
  const std::optional<analysis::PassCost> row = analysis::fit_eye_count_pass(back.eye_count, &report);
  ASSERT_TRUE(row);
  // One viewport size: the intercept and the per-fragment term share the constant.
  const double constant = row->intercept_ms + row->ms_per_mfragment * 19200 * 1e-6;
  std::printf("fitted: constant %.4f ms (true %.4f), %.3f ms per Mtriangle (true %.3f); held-out error %.3f\n",
              constant, intercept, row->ms_per_mtriangle, per_mtriangle, report.held_out_median_relative_error);
  EXPECT_NEAR(constant, intercept, 0.03 * intercept);
  EXPECT_NEAR(row->ms_per_mtriangle, per_mtriangle, 0.05 * per_mtriangle);
  EXPECT_GT(report.held_out_count, 0u);
  EXPECT_LT(report.held_out_median_relative_error, 0.05);
  EXPECT_FALSE(analysis::fit_eye_count_pass({}));
  // An eye_count row is a pass row only (not a noise-floor "again" row).
  EXPECT_THROW(
      analysis::parse_calibration_csv(
          analysis::calibration_csv_header() + "again,sample:1:1:light0:atomiczp,eye_count,12,19200,0.1,,,,\n", "test"),
      Error);
}

}  // namespace
}  // namespace nearcap
