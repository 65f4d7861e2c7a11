// Depth precision and its two cures.  The camera's depth mapping
// (gl/float_transforms.hpp DepthMapping): the reversed matrices, the
// clipper's planes and window depth under GL_ZERO_TO_ONE; the tight near
// plane (gl/tight_near_plane.hpp); and what each does where a tiny near
// plane exhausts the standard mapping's depth: the sampler's tiny-near
// configurations, on which Z-fail is wrong on hundreds of pixels with either
// standard depth buffer and on 2 with reversed-Z or the tight near plane.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>

#include "box_scene.hpp"
#include "nearcap/analysis/conditioning.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/crack_distance.hpp"
#include "nearcap/gl/clipping.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/gl/tight_near_plane.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "support/sampled_scenes.hpp"

namespace nearcap {
namespace {

using gl::DepthMapping;
using gl::Vec4f;

const std::string kScenes = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/";

float window_depth(const gl::Mat4f& m, const Vec4f& eye, DepthMapping mapping) {
  return gl::to_window(gl::transform(m, eye), 64, 48, mapping).z;
}

TEST(DepthMapping, ReversedMatricesSendTheNearPlaneToOneAndTheFarPlaneToZero) {
  Frustum f;
  f.left = -0.5;
  f.right = 0.5;
  f.bottom = -0.375;
  f.top = 0.375;
  f.near = 0.25;
  f.far = 64;
  const gl::Mat4f finite = gl::frustum_matrix(f, DepthMapping::Reversed);
  // float32: a few roundings (matrix row, division, window map) of values up
  // to 2, each 2^-24 relative; 1e-6 is 16 float ulps of 1.
  EXPECT_NEAR(window_depth(finite, {0, 0, -0.25f, 1}, DepthMapping::Reversed), 1.0f, 1e-6f);
  EXPECT_NEAR(window_depth(finite, {0, 0, -64, 1}, DepthMapping::Reversed), 0.0f, 1e-6f);
  const gl::Mat4f infinite = gl::infinite_frustum_matrix(f, gl::InfiniteFar::Exact, DepthMapping::Reversed);
  EXPECT_EQ(window_depth(infinite, {0, 0, -0.25f, 1}, DepthMapping::Reversed), 1.0f);
  // A point at infinity: z = 0 exactly, on the far plane z >= 0 (kept), depth 0.
  const Vec4f at_infinity = gl::transform(infinite, {0.1f, 0.2f, -1, 0});
  EXPECT_EQ(at_infinity.z, 0.0f);
  EXPECT_EQ(gl::far_plane_distance(at_infinity, DepthMapping::Reversed), 0.0f);
  // Depth n / -z_eye: farther is smaller, and a float keeps it to 2^-24 relative.
  const float d1 = window_depth(infinite, {0, 0, -1000, 1}, DepthMapping::Reversed);
  const float d2 = window_depth(infinite, {0, 0, -1000.001f, 1}, DepthMapping::Reversed);
  EXPECT_GT(d1, d2);
  EXPECT_NEAR(d1, 0.25f / 1000, 0.25f / 1000 * 0x1p-21f);  // a division and the window map: 4 ulps
  // The standard mapping's nudges belong to its depth row.
  EXPECT_THROW(gl::infinite_frustum_matrix(f, gl::InfiniteFar::Epsilon, DepthMapping::Reversed), Error);
  // The x and y rows are the standard matrix's, bit for bit.
  const gl::Mat4f standard = gl::frustum_matrix(f);
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(finite.at(0, c), standard.at(0, c));
    EXPECT_EQ(finite.at(1, c), standard.at(1, c));
    EXPECT_EQ(finite.at(3, c), standard.at(3, c));
  }
}

TEST(DepthMapping, TheClipperCutsAtTheMappingsNearPlane) {
  Frustum f;
  f.near = 0.5;
  f.far = 100;
  // A triangle from behind the eye to well beyond the near plane: both
  // mappings cut it at z_eye = -near, where x and y agree to rounding.
  const Vec4f eye[3] = {{-0.2f, -0.2f, 1, 1}, {0.3f, -0.1f, -3, 1}, {0, 0.3f, -3, 1}};
  for (DepthMapping m : {DepthMapping::Standard, DepthMapping::Reversed}) {
    const gl::Mat4f p = gl::infinite_frustum_matrix(f, gl::InfiniteFar::Exact, m);
    gl::ClipSettings s;
    s.clip_far = false;
    s.depth_mapping = m;
    const auto poly =
        gl::clip_triangle(gl::transform(p, eye[0]), gl::transform(p, eye[1]), gl::transform(p, eye[2]), s);
    ASSERT_EQ(poly.size(), 4u);
    std::size_t on_near = 0;
    for (const Vec4f& v : poly) {
      EXPECT_GE(gl::near_plane_distance(v, m), 0.0f);
      if (std::fabs(v.w - 0.5f) < 1e-6f) {
        ++on_near;
        // The clipper's float32 interpolation and the window map: 16 ulps of 1.
        EXPECT_NEAR(gl::to_window(v, 64, 48, m).z, m == DepthMapping::Standard ? 0.0f : 1.0f, 1e-6f);
      }
    }
    EXPECT_EQ(on_near, 2u);
  }
}

struct Tally {
  std::size_t frames = 0, wrong = 0, cracks = 0;
};

// The sampler's tiny-near configurations of seed 5: near planes from 2^-10
// down to 10^-6 with scenes of size 1.  The tests below walk the first 100.
analysis::HardCaseSampler tiny_near_sampler() {
  analysis::SamplerSpec spec = test::bundled_sampler_spec(5);
  spec.kinds = {analysis::HardCaseKind::TinyNear};
  return analysis::HardCaseSampler(spec);
}

// Z-fail on the first 100 tiny-near configurations (tiny_near_sampler),
// judged against the exact reference with crack distances.
Tally zfail_on_tiny_near_planes(gl::DepthFormat depth, DepthMapping mapping, gl::ShadowMethod method,
                                gl::NearPlane near_plane = gl::NearPlane::Scene) {
  gl::EmulationSettings settings;
  settings.depth = depth;
  settings.depth_mapping = mapping;
  settings.near_plane = near_plane;
  settings.light_frustum.projection = gl::LightProjection::ClippedSides;
  Tally t;
  test::for_each_sampled_scene(tiny_near_sampler(), 100, [&](const Scene& scene, const analysis::HardCase&) {
    const CameraSpaceScene cs(scene);
    for (std::size_t light = 0; light < scene.lights.size(); ++light) {
      const PixelReferenceTracer tracer(cs, light);
      const PixelReference ref = compute_pixel_reference(tracer);
      CrackReport r = judge_frame(gl::render_shadow_frame(scene, light, method, settings), ref);
      CrackDistances(tracer, ref).measure(r);
      ++t.frames;
      t.wrong += r.wrong;
      t.cracks += *r.cracks;
    }
  });
  return t;
}

// README "Reversed-Z": the figures of `nearcap sweep --samples 100 --seed 5
// --kinds tiny-near` with each variant.
TEST(DepthMapping, ReversedFloatDepthIsRightWhereTinyNearPlanesExhaustTheStandardMapping) {
  const Tally fixed =
      zfail_on_tiny_near_planes(gl::DepthFormat::Fixed24, DepthMapping::Standard, gl::ShadowMethod::ZFail);
  const Tally floating =
      zfail_on_tiny_near_planes(gl::DepthFormat::Float32, DepthMapping::Standard, gl::ShadowMethod::ZFail);
  const Tally reversed =
      zfail_on_tiny_near_planes(gl::DepthFormat::Float32, DepthMapping::Reversed, gl::ShadowMethod::ZFail);
  EXPECT_GE(fixed.frames, 90u);
  // The standard mapping puts every depth beyond a tiny near plane within a
  // few float32 spacings of 1: the same wrong pixels with either buffer.
  EXPECT_GT(fixed.wrong, 500u);
  EXPECT_GT(fixed.cracks, 100u);
  EXPECT_GT(floating.wrong, 500u);
  // Reversed-Z: the float's dense values near 0 meet the distant depths.
  EXPECT_LE(reversed.wrong, 2u);
  EXPECT_EQ(reversed.cracks, 0u);
  // ZP+ with the clipped-sides cap (the shipped policy's method) the same.
  const Tally capped =
      zfail_on_tiny_near_planes(gl::DepthFormat::Float32, DepthMapping::Reversed, gl::ShadowMethod::ZPPlus);
  EXPECT_LE(capped.wrong, 2u);
  EXPECT_EQ(capped.cracks, 0u);
  // The tight near plane, with the standard mapping and a 24-bit buffer.
  const Tally tight = zfail_on_tiny_near_planes(gl::DepthFormat::Fixed24, DepthMapping::Standard,
                                                gl::ShadowMethod::ZFail, gl::NearPlane::Tight);
  EXPECT_LE(tight.wrong, 2u);
  EXPECT_EQ(tight.cracks, 0u);
  std::printf(
      "[ tiny-near ] Z-fail wrong (cracks): fixed24 %zu (%zu), float32 %zu (%zu), reversed float32 %zu (%zu), tight "
      "near plane %zu (%zu)\n",
      fixed.wrong, fixed.cracks, floating.wrong, floating.cracks, reversed.wrong, reversed.cracks, tight.wrong,
      tight.cracks);
}

// On the bundled scenes reversed-Z is as right as the standard mapping for
// every method but where GL_DEPTH_CLAMP is on (the case-D switch, whose
// model is known not to be llvmpipe's: README "The real GL beside the
// emulation").
TEST(DepthMapping, OnTheBundledScenesReversedIsNeverWronger) {
  for (const char* name :
       {"default.json", "no_near_clip.json", "eye_in_shadow.json", "near_split.json", "twisted.json", "room.json",
        "room_side_light.json", "far_grazing.json", "exact_camera.json", "near_cap_bunny_wall.json"}) {
    const Scene scene = load_scene(kScenes + name);
    const CameraSpaceScene cs(scene);
    const PixelReference ref = compute_pixel_reference(cs, 0);
    gl::EmulationSettings reversed;
    reversed.depth = gl::DepthFormat::Float32;
    reversed.depth_mapping = DepthMapping::Reversed;
    for (gl::ShadowMethod m : gl::kAllShadowMethods) {
      const gl::ShadowFrame a = gl::render_shadow_frame(scene, 0, m),
                            b = gl::render_shadow_frame(scene, 0, m, reversed);
      if (!a.zfail_objects.empty() || !a.fallback.empty()) continue;  // depth clamp
      EXPECT_LE(judge_frame(b, ref).wrong, judge_frame(a, ref).wrong) << name << ", " << gl::to_string(m);
      EXPECT_EQ(b.object, a.object) << name << ": the depth pre-pass sees the same objects";
    }
  }
}

TEST(TightNearPlane, MovesTheNearPlaneToHalfTheNearestDepthInViewKeepingTheFieldOfView) {
  // The eye at (0, 0, 5) looking down -z (60 degrees vertically, near 0.05)
  // at the unit box; the receiver's top face (y = -0.6) runs under the eye,
  // so the nearest point in view is where the view's bottom plane, moved
  // out by half a percent of the window's height (2 tan 30 degrees at depth
  // 1), meets it: depth 0.6 / (1.01 tan 30 degrees).
  test::BoxSceneOptions o;
  Scene scene = test::box_scene({0, 0, 5}, {0, 5, 0}, o);
  const Frustum f = scene.camera.frustum;
  const Frustum tight = gl::tight_frustum(scene);
  const double nearest = 0.6 / (1.01 * std::tan(M_PI / 6));
  EXPECT_NEAR(tight.near, 0.5 * nearest, 1e-9);
  EXPECT_NEAR(tight.left / tight.near, f.left / f.near, 1e-12);
  EXPECT_NEAR(tight.top / tight.near, f.top / f.near, 1e-12);
  EXPECT_EQ(tight.far, f.far);
  // Never nearer the eye than the scene's near plane.
  scene.camera.frustum.near = 0.9;
  scene.camera.frustum.left *= 18;
  scene.camera.frustum.right *= 18;
  scene.camera.frustum.bottom *= 18;
  scene.camera.frustum.top *= 18;
  EXPECT_EQ(gl::tight_frustum(scene).near, 0.9);
  // Nothing in view (the eye looking away from everything): unchanged.
  const Scene away = test::box_scene({0, 30, 5}, {0, 5, 0}, [] {
    test::BoxSceneOptions up;
    up.target = {0, 60, 6};  // looking up, away from the box and the ground
    return up;
  }());
  EXPECT_EQ(gl::tight_frustum(away).near, away.camera.frustum.near);
}

// The same image: no point in view is clipped by the moved near plane, so
// the depth pre-pass sees the same objects, and a ZP+ frame's cap, drawn for
// another near plane, is not judged against the scene's.
TEST(TightNearPlane, TheFrameSeesWhatTheScenesCameraSees) {
  std::size_t moved = 0;
  for (const char* name : {"default.json", "near_split.json", "twisted.json", "room.json", "eye_in_shadow.json",
                           "near_cap_bunny_wall.json"}) {
    const Scene scene = load_scene(kScenes + name);
    const CameraSpaceScene cs(scene);
    const PixelReference ref = compute_pixel_reference(cs, 0);
    gl::EmulationSettings tight;
    tight.near_plane = gl::NearPlane::Tight;
    for (gl::ShadowMethod m : {gl::ShadowMethod::ZFail, gl::ShadowMethod::ZPPlus}) {
      const gl::ShadowFrame a = gl::render_shadow_frame(scene, 0, m), b = gl::render_shadow_frame(scene, 0, m, tight);
      EXPECT_EQ(judge_frame(b, ref).visibility_mismatch, judge_frame(a, ref).visibility_mismatch) << name;
      EXPECT_FALSE(a.near_moved);
      EXPECT_EQ(a.near, scene.camera.frustum.near);
      if (b.near_moved) {
        ++moved;
        EXPECT_GT(b.near, scene.camera.frustum.near) << name;
        EXPECT_FALSE(judge_frame(b, ref).cap_mismatch.has_value()) << name;
      }
      if (m == gl::ShadowMethod::ZFail) {
        EXPECT_LE(judge_frame(b, ref).wrong, judge_frame(a, ref).wrong) << name;
      }
    }
  }
  EXPECT_GT(moved, 0u) << "no bundled frame moved its near plane: the checks above checked nothing";
}

}  // namespace
}  // namespace nearcap

namespace nearcap {
namespace {

// One depth step over the scene's size (analysis/conditioning.hpp): 2^-24
// D^2 / n for the standard mapping, so it scales as 1/n; reversed-Z with a
// float buffer at most 2^-23 D, independent of n.
TEST(DepthLimited, TheDepthStepFollowsTheMappingsFormula) {
  const Scene scene = load_scene(kScenes + "default.json");
  const CameraSpaceScene cs(scene);
  const double n = scene.camera.frustum.near;
  const double standard = analysis::depth_step_over_size(cs);
  EXPECT_EQ(standard, analysis::depth_step_over_size(cs, n, gl::DepthFormat::Fixed24, DepthMapping::Standard));
  EXPECT_DOUBLE_EQ(analysis::depth_step_over_size(cs, n / 1024, gl::DepthFormat::Fixed24, DepthMapping::Standard),
                   1024 * standard);
  EXPECT_EQ(analysis::depth_step_over_size(cs, n, gl::DepthFormat::Float32, DepthMapping::Standard), standard);
  const double reversed = analysis::depth_step_over_size(cs, n, gl::DepthFormat::Float32, DepthMapping::Reversed);
  EXPECT_EQ(reversed, analysis::depth_step_over_size(cs, n / 1024, gl::DepthFormat::Float32, DepthMapping::Reversed));
  EXPECT_LT(reversed, standard);
  EXPECT_LT(standard, analysis::kDepthLimitedStep);
}

// The decision's step (depth_step_against_limit) against the step itself,
// on every bundled scene and the first 100 tiny-near configurations of seed
// 5 (of every kind on seed 7 too), each with its near plane and 2^-10 and
// 2^-20 of it, in both mappings: where the step reaches kDepthLimitedStep it
// is the step; below, it is no smaller and still below; and the bound alone
// answers most frames (else the pass it skips is not skipped).
TEST(DepthLimited, TheDecisionsBoundAgreesWithTheStepAboutTheLimit) {
  std::size_t frames = 0, limited = 0, below = 0, bounded = 0;
  auto check = [&](const Scene& scene, const std::string& what) {
    const CameraSpaceScene cs(scene);
    for (const double scale : {1.0, 0x1p-10, 0x1p-20})
      for (const auto& [format, mapping] : {std::pair{gl::DepthFormat::Fixed24, DepthMapping::Standard},
                                            std::pair{gl::DepthFormat::Float32, DepthMapping::Reversed}}) {
        const double near = scene.camera.frustum.near * scale;
        const double step = analysis::depth_step_over_size(cs, near, format, mapping);
        const analysis::DepthStepAgainstLimit against = analysis::depth_step_against_limit(cs, near, format, mapping);
        const std::string where = what + " near x " + std::to_string(scale);
        ++frames;
        if (step >= analysis::kDepthLimitedStep) {
          ++limited;
          EXPECT_FALSE(against.bounded) << where;
          EXPECT_EQ(against.over_size, step) << where;
        } else if (std::isnan(step)) {
          EXPECT_FALSE(against.bounded) << where;
          EXPECT_TRUE(std::isnan(against.over_size)) << where;
        } else {
          ++below;
          bounded += against.bounded ? 1 : 0;
          EXPECT_GE(against.over_size, step) << where;
          EXPECT_LT(against.over_size, analysis::kDepthLimitedStep) << where;
          if (!against.bounded) {
            EXPECT_EQ(against.over_size, step) << where;
          }
        }
      }
  };
  for (const auto& entry : std::filesystem::directory_iterator(kScenes))
    if (entry.path().extension() == ".json") check(load_scene(entry.path().string()), entry.path().filename());
  test::for_each_sampled_scene(tiny_near_sampler(), 100,
                               [&](const Scene& scene, const analysis::HardCase&) { check(scene, "tiny-near"); });
  test::for_each_sampled_scene(analysis::HardCaseSampler(test::bundled_sampler_spec(7)), 100,
                               [&](const Scene& scene, const analysis::HardCase&) { check(scene, "seed 7"); });
  std::printf("[ depth    ] %zu frames: %zu at or above the limit, %zu below, %zu of them answered by the bound\n",
              frames, limited, below, bounded);
  EXPECT_GT(limited, 0u);
  EXPECT_GT(2 * bounded, below);
}

// Where no method is right (tiny near planes exhaust the 24-bit depth
// buffer), a policy held to the scene's near plane says so: on the first
// 100 tiny-near configurations of seed 5 every (configuration, light) where
// Z-fail cracks is flagged depth-limited, with the fixes named; the
// alternative policies, drawn with reversed-Z or the tight near plane, flag
// none of them, nor does the shipped one on any bundled scene.
TEST(DepthLimited, ThePolicysRecordSaysSoWhereNoMethodIsRight) {
  const std::string data = std::string(NEARCAP_SOURCE_DIR) + "/data/";
  analysis::SwitchPolicy pinned = analysis::load_policy(data + "policy.json");
  pinned.near_plane = gl::NearPlane::Scene;
  const analysis::SwitchPolicy shipped = analysis::load_policy(data + "policy.json");
  const analysis::SwitchPolicy reversed = analysis::load_policy(data + "policy-reversed-z.json");
  const analysis::SwitchPolicy tight = analysis::load_policy(data + "policy-tight-near.json");
  std::size_t frames = 0, flagged = 0, cracking = 0, cracking_unflagged = 0, cracks = 0, alternatives_flagged = 0;
  test::for_each_sampled_scene(tiny_near_sampler(), 100, [&](const Scene& scene, const analysis::HardCase&) {
    const CameraSpaceScene cs(scene);
    for (std::size_t light = 0; light < scene.lights.size(); ++light) {
      const analysis::PolicyDecision d = analysis::decide(pinned, cs, light, {});
      const PixelReferenceTracer tracer(cs, light);
      const PixelReference ref = compute_pixel_reference(tracer);
      CrackReport r = judge_frame(gl::render_shadow_frame(scene, light, gl::ShadowMethod::ZFail), ref);
      CrackDistances(tracer, ref).measure(r);
      ++frames;
      flagged += d.depth_limited;
      cracks += *r.cracks;
      if (*r.cracks > 0) {
        ++cracking;
        cracking_unflagged += !d.depth_limited;
      }
      if (d.depth_limited) {
        EXPECT_NE(d.depth_note().find("--depth-mapping reversed"), std::string::npos) << d.depth_note();
      } else {
        EXPECT_TRUE(d.depth_note().empty());
      }
      EXPECT_TRUE(d.near_plane_note().empty()) << "a policy with a near plane of its own keeps it";
      alternatives_flagged += analysis::decide(reversed, cs, light, {}).depth_limited;
      alternatives_flagged += analysis::decide(tight, cs, light, {}).depth_limited;
      alternatives_flagged += analysis::decide(shipped, cs, light, {}).depth_limited;
    }
  });
  std::printf(
      "[ depth    ] %zu frames: %zu flagged depth-limited; Z-fail cracks in %zu (%zu cracks), %zu of them "
      "unflagged\n",
      frames, flagged, cracking, cracks, cracking_unflagged);
  EXPECT_GT(cracking, 5u);
  EXPECT_EQ(cracking_unflagged, 0u);
  EXPECT_LT(flagged, frames);
  EXPECT_EQ(alternatives_flagged, 0u);
  for (const char* name : {"default.json", "near_split.json", "eye_in_shadow.json", "case_d.json", "room.json",
                           "exact_camera.json", "light_on_near_plane.json"}) {
    const Scene scene = load_scene(kScenes + name);
    const CameraSpaceScene cs(scene);
    const analysis::PolicyDecision d = analysis::decide(shipped, cs, 0, {});
    EXPECT_FALSE(d.depth_limited) << name;
    EXPECT_EQ(d.settings.near_plane, gl::NearPlane::Scene) << name;
  }
}

// A policy without a near plane of its own and without the exact Z-pass
// test (the shipped one) draws a depth-limited frame with the tight near
// plane, and only such a frame: on the same 100 configurations it moves
// exactly where a policy held to the scene's plane is depth-limited, says
// why, and its frame there has no crack, where Z-fail's has some.
TEST(DepthLimited, TheShippedPolicyMovesTheNearPlaneWhereTheDepthBufferIsTheLimit) {
  const std::string data = std::string(NEARCAP_SOURCE_DIR) + "/data/";
  const analysis::SwitchPolicy shipped = analysis::load_policy(data + "policy.json");
  ASSERT_FALSE(shipped.near_plane);
  ASSERT_FALSE(shipped.exact_zpass);
  analysis::SwitchPolicy pinned = shipped;
  pinned.near_plane = gl::NearPlane::Scene;
  std::size_t moved = 0, zfail_cracks_there = 0, policy_cracks_there = 0;
  test::for_each_sampled_scene(tiny_near_sampler(), 100, [&](const Scene& scene, const analysis::HardCase&) {
    const CameraSpaceScene cs(scene);
    for (std::size_t light = 0; light < scene.lights.size(); ++light) {
      const analysis::PolicyDecision d = analysis::decide(shipped, cs, light, {});
      const bool limited = analysis::decide(pinned, cs, light, {}).depth_limited;
      EXPECT_EQ(d.settings.near_plane == gl::NearPlane::Tight, limited);
      EXPECT_EQ(!d.near_plane_note().empty(), limited);
      EXPECT_FALSE(d.depth_limited);
      if (!limited) continue;
      ++moved;
      EXPECT_NE(d.near_plane_note().find("tight near plane"), std::string::npos) << d.near_plane_note();
      char planes[128];  // the plane it moved to, then the scene's
      std::snprintf(planes, sizeof planes, "tight near plane (%.3g): with the scene's (%.3g)",
                    gl::tight_frustum(scene).near, scene.camera.frustum.near);
      EXPECT_NE(d.near_plane_note().find(planes), std::string::npos) << planes << " in " << d.near_plane_note();
      const PixelReferenceTracer tracer(cs, light);
      const PixelReference ref = compute_pixel_reference(tracer);
      gl::ShadowFrameBatch batch(scene, light, d.settings);
      CrackReport policy = judge_frame(batch.render(d.object_methods), ref);
      CrackReport zfail = judge_frame(gl::render_shadow_frame(scene, light, gl::ShadowMethod::ZFail), ref);
      CrackDistances distances(tracer, ref);
      distances.measure(policy);
      distances.measure(zfail);
      policy_cracks_there += *policy.cracks;
      zfail_cracks_there += *zfail.cracks;
    }
  });
  std::printf("[ depth    ] the shipped policy moved the near plane in %zu frames: %zu cracks there (Z-fail %zu)\n",
              moved, policy_cracks_there, zfail_cracks_there);
  EXPECT_GT(moved, 5u);
  EXPECT_GT(zfail_cracks_there, 0u);
  EXPECT_EQ(policy_cracks_there, 0u);
}

}  // namespace
}  // namespace nearcap
