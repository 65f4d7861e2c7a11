// A frame loop's kept choices (analysis/kept_choices.hpp): a priced choice
// is kept for at most KeptChoices::kMaxKeptFrames decisions, only where its
// margin reaches KeptChoices::kMargin, only with methods every frame offers,
// and only while the frame's objects, light, window and near plane stay put;
// the decision with them on a bundled path draws what it draws without.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "box_scene.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/kept_choices.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap {
namespace {

using analysis::KeptChoices;
using gl::LightProjection;
using gl::ShadowMethod;

constexpr double kWide = 2 * KeptChoices::kMargin;

struct Frame {
  Scene scene = test::box_scene({0.5, 1, 4}, {2, 5, 2});
  gl::NearPlane near_plane = gl::NearPlane::Scene;
  bool depth_limited = false;
};

std::vector<ShadowMethod> every_occluder(const Scene& s, ShadowMethod m) {
  std::vector<ShadowMethod> out(s.objects.size(), ShadowMethod::ZPass);
  for (std::size_t o = 0; o < s.objects.size(); ++o)
    if (s.objects[o].occluder) out[o] = m;
  return out;
}

void remember(KeptChoices& kept, const analysis::SwitchPolicy& policy, const Frame& f, ShadowMethod m,
              LightProjection projection, double margin) {
  kept.remember(policy, f.scene, 0, f.near_plane, f.depth_limited, every_occluder(f.scene, m), projection, margin);
}

bool taken(KeptChoices& kept, const analysis::SwitchPolicy& policy, const Frame& f) {
  return kept.take(policy, f.scene, 0, f.near_plane, f.depth_limited).has_value();
}

TEST(KeptChoices, AWideMarginChoiceIsKeptForItsFramesThenPriced) {
  const analysis::SwitchPolicy policy;
  Frame f;
  KeptChoices kept;
  remember(kept, policy, f, ShadowMethod::ZFail, LightProjection::Paper, kWide);
  for (int k = 1; k <= KeptChoices::kMaxKeptFrames; ++k) {
    const std::optional<KeptChoices::Choice> c = kept.take(policy, f.scene, 0, f.near_plane, f.depth_limited);
    ASSERT_TRUE(c.has_value()) << "frame " << k;
    EXPECT_EQ(c->frames_since_priced, k);
    EXPECT_EQ(c->object_methods, every_occluder(f.scene, ShadowMethod::ZFail));
    EXPECT_EQ(c->projection, LightProjection::Paper);
  }
  EXPECT_FALSE(taken(kept, policy, f)) << "priced again after kMaxKeptFrames";
  EXPECT_FALSE(taken(kept, policy, f)) << "nothing kept until the next priced frame";
  EXPECT_EQ(kept.frames_kept(), static_cast<std::size_t>(KeptChoices::kMaxKeptFrames));
  // The margin itself is wide enough; another light has nothing kept.
  remember(kept, policy, f, ShadowMethod::ZFail, LightProjection::Paper, KeptChoices::kMargin);
  EXPECT_FALSE(kept.take(policy, f.scene, 1, f.near_plane, f.depth_limited).has_value());
  EXPECT_TRUE(taken(kept, policy, f));
}

TEST(KeptChoices, OnlyAWideMarginAndMethodsEveryFrameOffers) {
  const analysis::SwitchPolicy policy;
  const Frame f;
  struct Case {
    ShadowMethod method;
    LightProjection projection;
    double margin;
    bool kept;
  };
  const double below = std::nextafter(KeptChoices::kMargin, 0.0);
  for (const Case& c :
       {Case{ShadowMethod::ZFail, LightProjection::Paper, kWide, true},
        Case{ShadowMethod::ZPPlus, LightProjection::ClippedSides, kWide, true},
        Case{ShadowMethod::ZFail, LightProjection::Paper, below, false},
        Case{ShadowMethod::ZFail, LightProjection::Paper, std::numeric_limits<double>::quiet_NaN(), false},
        Case{ShadowMethod::ZPass, LightProjection::Paper, kWide, false},
        Case{ShadowMethod::ZPPlus, LightProjection::Paper, kWide, false},
        Case{ShadowMethod::ZPPlusCorrected, LightProjection::Paper, kWide, false},
        Case{ShadowMethod::AtomicZP, LightProjection::Paper, kWide, false}}) {
    KeptChoices kept;
    remember(kept, policy, f, c.method, c.projection, c.margin);
    EXPECT_EQ(taken(kept, policy, f), c.kept) << gl::to_string(c.method) << " margin " << c.margin;
    // A kept choice, then a priced frame that does not qualify: nothing kept.
    KeptChoices replaced;
    remember(replaced, policy, f, ShadowMethod::ZFail, LightProjection::Paper, kWide);
    remember(replaced, policy, f, c.method, c.projection, c.margin);
    EXPECT_EQ(taken(replaced, policy, f), c.kept) << gl::to_string(c.method) << " margin " << c.margin;
  }
}

TEST(KeptChoices, AnotherSceneSetupIsPriced) {
  const analysis::SwitchPolicy policy, other_policy;
  const Frame f;
  auto kept_after = [&](const Frame& g, const analysis::SwitchPolicy& p) {
    KeptChoices kept;
    remember(kept, policy, f, ShadowMethod::ZFail, LightProjection::Paper, kWide);
    return taken(kept, p, g);
  };
  EXPECT_TRUE(kept_after(f, policy));
  Frame moved_camera = f;  // the camera moves along a path: kept
  moved_camera.scene.camera.view.rows[0][3] += 0.25;
  EXPECT_TRUE(kept_after(moved_camera, policy));
  EXPECT_FALSE(kept_after(f, other_policy));
  Frame g = f;
  for (int axis = 0; axis < 3; ++axis) {
    g = f;
    g.scene.lights[0].position[axis] += 1e-9;
    EXPECT_FALSE(kept_after(g, policy)) << "the light moved along axis " << axis;
  }
  g = f;
  g.scene.objects[0].object_to_world.rows[1][3] += 1e-9;
  EXPECT_FALSE(kept_after(g, policy)) << "an object moved";
  g = f;
  g.scene.objects[0].mesh = std::make_shared<TriangleMesh>(*f.scene.objects[0].mesh);
  EXPECT_FALSE(kept_after(g, policy)) << "another mesh object";
  g = f;
  g.scene.objects.back().occluder = !g.scene.objects.back().occluder;
  EXPECT_FALSE(kept_after(g, policy)) << "an occluder flag";
  g = f;
  g.scene.objects.push_back(g.scene.objects[0]);
  EXPECT_FALSE(kept_after(g, policy)) << "another object";
  g = f;
  g.scene.camera.width += 1;
  EXPECT_FALSE(kept_after(g, policy)) << "the window";
  g = f;
  g.near_plane = gl::NearPlane::Tight;
  EXPECT_FALSE(kept_after(g, policy)) << "the near plane";
  g = f;
  g.depth_limited = true;
  EXPECT_FALSE(kept_after(g, policy)) << "depth-limited";
}

// Along near_plane_sweep and fly_around with the shipped policy: a frame
// loop with kept choices draws, frame by frame, what the decision without
// them draws (the paths' prices move slowly against the margin), keeps a
// choice on some frames, says so in the reason, and prices a kept choice as
// drawn.  A kept choice that differs from the fresh one is priced as drawn
// too: Z-fail kept on a frame whose fresh choice is the clipped-sides ZP+
// costs what the fresh decision's "no near-cap" option costs.
// The decision's margin, weighed where a choice may be kept: the least rise
// another option or the occluder's other candidate brings, from the full
// decision's own prices (the same in ms), over a price without what every
// candidate shares (at least the ratio over the full frame's).  A full
// decision does not weigh it.
void expect_margin(const analysis::SwitchPolicy& policy, const CameraSpaceScene& cs, analysis::FacingCache* facings,
                   const std::string& what) {
  const analysis::PolicyDecision full = analysis::decide(policy, cs, 0, {}, facings);
  KeptChoices kept;
  const analysis::PolicyDecision choice =
      analysis::decide(policy, cs, 0, {}, facings, analysis::DecisionPricing::ChoiceOnly, &kept);
  EXPECT_TRUE(std::isnan(full.choice_margin)) << what;
  ASSERT_TRUE(full.prices.has_value()) << what;
  ASSERT_EQ(full.prices->occluders.size(), 1u) << what;
  const analysis::OccluderPrices& p = full.prices->occluders[0];
  const bool zfail = p.chosen.method == ShadowMethod::ZFail;
  ASSERT_TRUE(zfail || p.chosen.method == ShadowMethod::ZPPlus) << what << ": " << full.reason(0);
  double rise = zfail ? p.clipped_ms - p.zfail_ms : p.zfail_ms - p.clipped_ms;
  for (const auto& [option, ms] : full.predicted_options)
    if (ms > full.predicted_ms) rise = std::min(rise, ms - full.predicted_ms);
  ASSERT_TRUE(std::isfinite(rise)) << what;
  EXPECT_NEAR(choice.choice_margin_ms, rise, 1e-9 * full.predicted_ms) << what << ": " << full.reason(0);
  EXPECT_GE(choice.choice_margin, rise / full.predicted_ms - 1e-12) << what;
}

TEST(KeptChoices, APathDrawsWhatItDrawsWithoutThem) {
  const analysis::SwitchPolicy policy = analysis::load_policy(std::string(NEARCAP_SOURCE_DIR) + "/data/policy.json");
  ASSERT_TRUE(policy.device_profile.has_value());
  analysis::SwitchPolicy zfail_capped = policy;
  zfail_capped.capped_method = ShadowMethod::ZFail;
  std::size_t frames = 0, kept_frames = 0;
  for (const char* name : {"near_plane_sweep", "fly_around"}) {
    const analysis::CameraPath path =
        analysis::load_camera_path(std::string(NEARCAP_SOURCE_DIR) + "/data/paths/" + name + ".json");
    MeshCache meshes;
    KeptChoices kept;
    analysis::FacingCache facings;
    for (int frame = 0; frame < path.frames; ++frame) {
      const Scene s = parse_scene(analysis::path_frame_json(path, frame), name, ".", &meshes);
      const CameraSpaceScene cs(s);
      const std::string what = std::string(name) + " frame " + std::to_string(frame);
      analysis::PolicyDecision d =
          analysis::decide(policy, cs, 0, {}, &facings, analysis::DecisionPricing::ChoiceOnly, &kept);
      const analysis::PolicyDecision fresh = analysis::decide(policy, cs, 0, {}, &facings);
      EXPECT_EQ(d.object_methods, fresh.object_methods) << what;
      expect_margin(policy, cs, &facings, what);
      // A policy whose capped method is Z-fail: its paper-cap candidate is
      // Z-fail itself, not another choice.
      expect_margin(zfail_capped, cs, &facings, what + " (capped method zfail)");
      EXPECT_EQ(d.settings.light_frustum.projection, fresh.settings.light_frustum.projection) << what;
      EXPECT_LE(d.frames_since_priced, KeptChoices::kMaxKeptFrames) << what;
      analysis::price_decision(d, policy, cs, 0, {}, &facings);
      EXPECT_EQ(d.predicted_ms, fresh.predicted_ms) << what;
      const bool says_kept = d.reason(0).find("kept from the frame priced") != std::string::npos;
      EXPECT_EQ(says_kept, d.frames_since_priced > 0) << what << ": " << d.reason(0);
      kept_frames += d.frames_since_priced > 0 ? 1 : 0;
      ++frames;
      if (std::string(name) == "near_plane_sweep" && frame == 0) {
        ASSERT_EQ(fresh.object_methods[0], ShadowMethod::ZPPlus) << fresh.reason(0);
        KeptChoices zfail_kept;
        zfail_kept.remember(policy, s, 0, d.settings.near_plane, d.depth_limited,
                            every_occluder(s, ShadowMethod::ZFail), LightProjection::Paper, kWide);
        analysis::PolicyDecision z =
            analysis::decide(policy, cs, 0, {}, &facings, analysis::DecisionPricing::ChoiceOnly, &zfail_kept);
        ASSERT_EQ(z.frames_since_priced, 1);
        EXPECT_EQ(z.object_methods[0], ShadowMethod::ZFail);
        analysis::price_decision(z, policy, cs, 0, {}, &facings);
        double no_near_cap = NAN;
        for (const auto& [option, ms] : fresh.predicted_options)
          if (option == "no near-cap") no_near_cap = ms;
        EXPECT_EQ(z.predicted_ms, no_near_cap) << z.reason(0);
        EXPECT_NE(z.reason(0).find("cost: zfail (kept from the frame priced 1 frame before"), std::string::npos)
            << z.reason(0);
      }
    }
  }
  EXPECT_EQ(frames, 150u);
  EXPECT_GT(kept_frames, frames / 3) << "most frames of these paths keep a choice";
}

}  // namespace
}  // namespace nearcap
