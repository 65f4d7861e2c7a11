// The engines' Z-pass / Z-fail rules (analysis/engine_policies.hpp) on scenes
// built to meet each of their tests, the exact per-occluder truth they are
// judged by (PixelReference::cap_pixels_by_object), and the frame drawn with
// a method per occluder (gl::ShadowFrameBatch::render).
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "box_scene.hpp"
#include "nearcap/analysis/engine_policies.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/io/scene_builder.hpp"
#include "nearcap/io/scene_file.hpp"
#include "support/sampled_scenes.hpp"

namespace nearcap {
namespace {

using analysis::EnginePolicy;

bool zfail(EnginePolicy p, const Scene& s) {
  const auto choices = analysis::engine_choices(p, s, 0);
  EXPECT_EQ(choices.size(), 1u);
  return !choices.empty() && choices.front().zfail;
}

std::size_t cap_pixels(const Scene& s, std::size_t object) {
  const CameraSpaceScene cs(s);
  return compute_pixel_reference(cs, 0).cap_pixels_by_object.at(object);
}

TEST(EnginePolicies, FarFromTheShadowEveryRuleButAlwaysZFailPicksZPass) {
  const Scene s = test::box_scene({6, 1, 6}, {0, 8, 0});
  EXPECT_EQ(cap_pixels(s, 0), 0u);  // Z-pass is right
  EXPECT_FALSE(zfail(EnginePolicy::Doom3, s));
  EXPECT_FALSE(zfail(EnginePolicy::Doom3BFG, s));
  EXPECT_FALSE(zfail(EnginePolicy::Ogre, s));
  EXPECT_TRUE(zfail(EnginePolicy::AlwaysZFail, s));
}

TEST(EnginePolicies, EyeInTheShadowBelowTheBoxEveryRulePicksZFail) {
  // The eye under the box, the light above: the light-view segment crosses it.
  const Scene s = test::box_scene({0.1, -1.5, 0.2}, {0, 8, 0});
  EXPECT_GT(cap_pixels(s, 0), 0u);  // Z-pass is wrong
  for (EnginePolicy p : analysis::kAllEnginePolicies) EXPECT_TRUE(zfail(p, s)) << to_string(p);
}

TEST(EnginePolicies, Doom3SaysZFailNearTheBoxWhereBfgsPreciseTestSaysZPass) {
  // The eye 0.03 from the box's -x face (znear 0.02), looking along +x, the
  // light far out on that side: Doom 3's box grown by 2 znear holds the eye;
  // the view-light segment stays more than 4 znear from every edge of the
  // light-facing face (its diagonal too) and never crosses it.
  test::BoxSceneOptions o;
  o.near = 0.02;
  o.target = {5, 0.2, 0.0};
  const Scene s = test::box_scene({-0.53, 0.2, 0.0}, {-8, 0.3, 0.2}, o);
  EXPECT_EQ(cap_pixels(s, 0), 0u);
  EXPECT_TRUE(zfail(EnginePolicy::Doom3, s));
  const auto bfg = analysis::engine_choices(EnginePolicy::Doom3BFG, s, 0);
  EXPECT_FALSE(bfg.front().zfail) << bfg.front().reason;
}

TEST(EnginePolicies, OgreMissesALightBetweenTheCameraAndTheNearPlane) {
  // Ogre's volume is bounded by the camera's plane and the plane through the
  // light; with the light between the camera and the near plane (d < 0) the
  // two leave nothing between them: Z-pass whatever the caster, here a small
  // box between the light and the near rectangle that shadows it.
  test::BoxSceneOptions o;
  o.near = 1.0;
  o.centre = {0, 0, 2.3};
  o.size = 0.2;
  const Scene s = test::box_scene({0, 0, 3}, {0, 0, 2.7}, o);
  EXPECT_GT(cap_pixels(s, 0), 0u);
  EXPECT_FALSE(zfail(EnginePolicy::Ogre, s));
  EXPECT_TRUE(zfail(EnginePolicy::Doom3, s));
}

TEST(EnginePolicies, NamesRoundTrip) {
  for (EnginePolicy p : analysis::kAllEnginePolicies) EXPECT_EQ(analysis::engine_policy_from_string(to_string(p)), p);
  EXPECT_FALSE(analysis::engine_policy_from_string("doom4"));
}

// The per-occluder truth: each occluder's pixels are those of the scene in
// which it is the only occluder.
TEST(EnginePolicies, CapPixelsByObjectAreEachOccludersOwnNearCap) {
  analysis::SamplerSpec spec = test::bundled_sampler_spec(11);
  spec.kinds = {analysis::HardCaseKind::SeveralOccluders};
  const analysis::HardCaseSampler sampler(spec);
  std::size_t nonzero = 0;
  const test::SampleWalk walk =
      test::for_each_sampled_scene(sampler, 6, [&](const Scene& s, const analysis::HardCase& sample) {
        const CameraSpaceScene cs(s);
        const PixelReference all = compute_pixel_reference(cs, 0);
        for (std::size_t o = 0; o < s.objects.size(); ++o) {
          if (!s.objects[o].occluder) continue;
          Scene alone = s;
          for (std::size_t k = 0; k < alone.objects.size(); ++k) alone.objects[k].occluder = (k == o);
          const CameraSpaceScene cs_alone(alone);
          const PixelReference ref = compute_pixel_reference(cs_alone, 0);
          std::size_t covered = 0;
          for (std::uint32_t c : ref.cap) covered += c > 0;
          EXPECT_EQ(all.cap_pixels_by_object[o], covered) << "sample " << sample.index << " object " << o;
          nonzero += covered > 0;
        }
      });
  EXPECT_EQ(walk.scenes, 6u);  // the reader accepts every one of these samples
  EXPECT_GT(nonzero, 0u);
}

// A frame with a method per occluder: with one method everywhere it is that
// method's frame; mixed, each occluder adds its own method's counts.
TEST(EnginePolicies, PerOccluderFrameAddsEachOccludersMethod) {
  analysis::SamplerSpec spec = test::bundled_sampler_spec(3);
  spec.kinds = {analysis::HardCaseKind::SeveralOccluders};
  const analysis::HardCaseSampler sampler(spec);
  gl::EmulationSettings settings;
  settings.zfail_far = gl::ZFailFar::DepthClampFar;  // every frame below on the finite projection
  std::size_t checked = 0;
  test::for_each_sampled_scene(sampler, 6, [&](const Scene& s, const analysis::HardCase&) {
    gl::ShadowFrameBatch batch(s, 0, settings);
    for (gl::ShadowMethod m : gl::kAllShadowMethods) {
      const gl::ShadowFrame one = batch.render(m);
      const gl::ShadowFrame per = batch.render(std::vector<gl::ShadowMethod>(s.objects.size(), m));
      EXPECT_EQ(one.stencil, per.stencil) << to_string(m);
      EXPECT_TRUE(per.mixed);
    }
    // Alternate Z-fail and Z-pass over the occluders; each half alone.
    std::vector<gl::ShadowMethod> mixed(s.objects.size(), gl::ShadowMethod::ZPass);
    Scene zfail_part = s, zpass_part = s;
    bool odd = false;
    for (std::size_t o = 0; o < s.objects.size(); ++o) {
      if (!s.objects[o].occluder) continue;
      mixed[o] = odd ? gl::ShadowMethod::ZFail : gl::ShadowMethod::ZPass;
      (odd ? zpass_part : zfail_part).objects[o].occluder = false;
      odd = !odd;
    }
    const gl::ShadowFrame frame = batch.render(mixed);
    const gl::ShadowFrame a = gl::render_shadow_frame(zfail_part, 0, gl::ShadowMethod::ZFail, settings);
    const gl::ShadowFrame b = gl::render_shadow_frame(zpass_part, 0, gl::ShadowMethod::ZPass, settings);
    ASSERT_EQ(frame.stencil.size(), a.stencil.size());
    for (std::size_t k = 0; k < frame.stencil.size(); ++k)
      EXPECT_EQ(frame.stencil[k], static_cast<std::uint8_t>(a.stencil[k] + b.stencil[k])) << "pixel " << k;
    ++checked;
  });
  EXPECT_EQ(checked, 6u);
}

TEST(EnginePolicies, PreloadBesideZpPlusAndAWrongCountAreRefused) {
  analysis::SamplerSpec spec = test::bundled_sampler_spec(3);
  spec.kinds = {analysis::HardCaseKind::SeveralOccluders};
  const std::optional<Scene> sampled = test::sampled_scene(analysis::HardCaseSampler(spec).sample(0));
  ASSERT_TRUE(sampled.has_value());
  const Scene& s = *sampled;
  std::vector<std::size_t> occluders;
  for (std::size_t o = 0; o < s.objects.size(); ++o)
    if (s.objects[o].occluder) occluders.push_back(o);
  ASSERT_GE(occluders.size(), 2u);
  gl::ShadowFrameBatch batch(s, 0);
  std::vector<gl::ShadowMethod> m(s.objects.size(), gl::ShadowMethod::ZPass);
  m[occluders[0]] = gl::ShadowMethod::Preload;
  EXPECT_NO_THROW(batch.render(m));
  m[occluders[1]] = gl::ShadowMethod::ZPPlus;
  EXPECT_THROW(batch.render(m), Error);
  EXPECT_THROW(batch.render(std::vector<gl::ShadowMethod>(s.objects.size() + 1, gl::ShadowMethod::ZPass)), Error);
}

}  // namespace
}  // namespace nearcap
