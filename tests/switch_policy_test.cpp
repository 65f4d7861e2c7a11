// The switch policy (analysis/switch_policy.hpp): its file format checked
// field by field, the logistic fit recovering known parameters (policy_fit),
// the documented split, and the decision on scenes built for each branch.
#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <filesystem>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "box_scene.hpp"
#include "cli_support.hpp"
#include "nearcap/analysis/policy_fit.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/io/scene_builder.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/judge/crack_map.hpp"

namespace nearcap {
namespace {

using analysis::PassKind;
using analysis::SwitchPolicy;

// Synthetic data from a known logistic model: the fit finds its weights.
TEST(PolicyFit, RecoversKnownLogisticParameters) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double w0 = 1.5, w1 = -2.0, b = -0.5;
  std::vector<std::vector<double>> x;
  std::vector<int> y;
  for (int i = 0; i < 20000; ++i) {
    const double a = normal(rng), c = normal(rng);
    const double p = 1.0 / (1.0 + std::exp(-(w0 * a + w1 * c + b)));
    x.push_back({a, c});
    y.push_back(unit(rng) < p ? 1 : 0);
  }
  analysis::LogisticFitOptions plain;
  plain.robust = false;
  plain.l2 = 0;
  const analysis::LogisticFit fit = analysis::fit_logistic(x, y, plain);
  // Weights are on standardized features; the data are standard already.
  // 20000 samples: the estimates' standard error is about 0.02 here
  // (1 / sqrt(n E[p (1 - p)] var x), E[p (1 - p)] about 0.12); 0.1 is five.
  EXPECT_NEAR(fit.weights[0] / fit.scale[0], w0, 0.1);
  EXPECT_NEAR(fit.weights[1] / fit.scale[1], w1, 0.1);
  EXPECT_NEAR(fit.bias - fit.weights[0] * fit.mean[0] / fit.scale[0] - fit.weights[1] * fit.mean[1] / fit.scale[1], b,
              0.1);
  // The robust loss keeps the direction of the separating plane.
  const analysis::LogisticFit robust = analysis::fit_logistic(x, y);
  // Same data: the robust ratio stays within two standard errors (about 0.02).
  EXPECT_NEAR(robust.weights[1] / robust.weights[0], fit.weights[1] / fit.weights[0], 0.05);
  EXPECT_GT(robust.weights[0], 0);
  EXPECT_LT(robust.weights[1], 0);
}

// Separable data (a handful of cracks, as a policy's are) must not break the
// fit: the weights grow, every trial point stays finite, the classes split.
TEST(PolicyFit, SeparableDataStillFit) {
  std::vector<std::vector<double>> x;
  std::vector<int> y;
  for (int i = 0; i < 300; ++i) {
    // The three positives beyond a gap: separable with a margin.
    x.push_back({static_cast<double>(i >= 297 ? i + 60 : i), static_cast<double>(i % 7)});
    y.push_back(i >= 297 ? 1 : 0);
  }
  // The robust loss reads three positives in 300 as outliers; it must still
  // converge to finite weights.
  const analysis::LogisticFit robust = analysis::fit_logistic(x, y);
  for (double w : robust.weights) EXPECT_TRUE(std::isfinite(w));
  analysis::LogisticFitOptions plain;
  plain.robust = false;
  plain.l2 = 1e-3;
  const analysis::LogisticFit fit = analysis::fit_logistic(x, y, plain);
  auto p = [&](const std::vector<double>& v) {
    double z = fit.bias;
    for (std::size_t k = 0; k < v.size(); ++k) z += fit.weights[k] * (v[k] - fit.mean[k]) / fit.scale[k];
    return 1.0 / (1.0 + std::exp(-z));
  };
  double lowest_positive = 1, highest_negative = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    (y[i] ? lowest_positive : highest_negative) =
        y[i] ? std::min(lowest_positive, p(x[i])) : std::max(highest_negative, p(x[i]));
  EXPECT_GT(lowest_positive, highest_negative);  // the classes split
  EXPECT_LT(p(x[0]), 0.01);
  EXPECT_GT(fit.weights[0], 0);
}

// Times from known costs with noise and a tenth of outliers (a frame timed
// while the machine was busy): the robust fit finds the costs, plain least
// squares is pulled away.
TEST(PolicyFit, CostModelRecoversKnownCostsDespiteOutliers) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> triangles(1e3, 2e5), fragments(1e4, 2e6), unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.02);
  const double c0 = 0.3, per_mtri = 40.0, per_mfrag = 5.0;
  std::vector<analysis::CostSample> rows;
  for (int i = 0; i < 2000; ++i) {
    analysis::CostSample s;
    s.triangles = triangles(rng);
    s.fragments = fragments(rng);
    s.ms = c0 + per_mtri * s.triangles * 1e-6 + per_mfrag * s.fragments * 1e-6 + noise(rng);
    if (unit(rng) < 0.1) s.ms += 5 + 20 * unit(rng);  // an outlier
    s.held_out = i % 5 == 0;
    rows.push_back(s);
  }
  const analysis::CostModel robust = analysis::fit_cost_model(rows);
  // With 1600 fitted rows of noise 0.02 ms the slopes' standard errors are
  // about 0.009 and 0.001 ms per million; the outliers, all slower, bias the
  // robust intercept by about 0.01 ms.  The bounds are 20 times or more that.
  EXPECT_NEAR(robust.intercept_ms, c0, 0.05);
  EXPECT_NEAR(robust.ms_per_mtriangle, per_mtri, 0.2);
  EXPECT_NEAR(robust.ms_per_mfragment, per_mfrag, 0.05);
  const analysis::CostModel plain = analysis::fit_cost_model(rows, false);
  EXPECT_GT(std::fabs(plain.intercept_ms - c0), 0.5);  // the outliers pull it
  EXPECT_LT(analysis::median_relative_error(robust, rows, true), 0.05);
}

TEST(PolicyFit, TheSplitHoldsOutAboutAFifthByConfiguration) {
  int held = 0;
  for (int i = 0; i < 5000; ++i) held += analysis::held_out_configuration("sample:1:" + std::to_string(i));
  EXPECT_GT(held, 850);
  EXPECT_LT(held, 1150);
  EXPECT_EQ(analysis::held_out_configuration("path:zoom:3"), analysis::held_out_configuration("path:zoom:3"));
}

std::string valid_policy() {
  return R"({"format": "nearcap-policy", "version": 1, "capped_method": "zpplus-corrected",
  "fallback_method": "zfail", "switch_clamp": "clamp-far", "zpass_far": "infinite",
  "crack_model": {"features": ["log_skew", "l_near_over_l_far"], "mean": [0, 0.2], "scale": [1, 0.1],
                  "weights": [1.5, -0.5], "bias": -3, "threshold": 0.01},
  "cost_models": {}, "provenance": {"command": "test"}})";
}

TEST(SwitchPolicy, ReadsWhatItWrites) {
  const SwitchPolicy p = analysis::parse_policy(valid_policy(), "p.json");
  EXPECT_EQ(p.capped_method, gl::ShadowMethod::ZPPlusCorrected);
  EXPECT_EQ(p.switch_clamp, gl::SwitchClamp::DepthClampFar);
  SwitchPolicy with_costs = p;
  with_costs.cost_models.push_back({gl::ShadowMethod::ZFail, {0.5, 30, 4}});
  const SwitchPolicy c = analysis::parse_policy(analysis::policy_to_json(with_costs), "c.json");
  ASSERT_EQ(c.cost_models.size(), 1u);
  EXPECT_EQ(c.cost_models[0].first, gl::ShadowMethod::ZFail);
  EXPECT_EQ(c.cost_models[0].second.ms_per_mtriangle, 30);
  EXPECT_EQ(p.light_projection, gl::LightProjection::Paper);  // version 1: no light_projection, the paper's
  SwitchPolicy sides = p;
  sides.light_projection = gl::LightProjection::ClippedSides;
  const std::string written = analysis::policy_to_json(sides);
  EXPECT_NE(written.find("\"version\": 6"), std::string::npos) << written;
  EXPECT_EQ(written.find("\"depth"), std::string::npos) << "unset version-3 fields are not written: " << written;
  EXPECT_EQ(analysis::parse_policy(written, "s.json").light_projection, gl::LightProjection::ClippedSides);
  EXPECT_TRUE(analysis::parse_policy(written, "s.json").exact_zpass);
  sides.exact_zpass = false;
  EXPECT_FALSE(analysis::parse_policy(analysis::policy_to_json(sides), "s.json").exact_zpass);
  sides.capped_method = gl::ShadowMethod::ZFail;
  sides.fallback_method = gl::ShadowMethod::Preload;
  try {
    analysis::parse_policy(analysis::policy_to_json(sides), "s.json");
    ADD_FAILURE() << "exact_zpass false accepted without a ZP+ capped method";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("exact_zpass: false needs a ZP+ capped method"), std::string::npos)
        << e.what();
  }
  // Version 3: the depth buffer and mapping, read back; the frames decided with them.
  SwitchPolicy reversed = p;
  reversed.depth = gl::DepthFormat::Float32;
  reversed.depth_mapping = gl::DepthMapping::Reversed;
  const SwitchPolicy r = analysis::parse_policy(analysis::policy_to_json(reversed), "r.json");
  EXPECT_EQ(r.depth, gl::DepthFormat::Float32);
  EXPECT_EQ(r.depth_mapping, gl::DepthMapping::Reversed);
  EXPECT_FALSE(r.near_plane.has_value());
  EXPECT_FALSE(p.depth.has_value());
  reversed.near_plane = gl::NearPlane::Tight;
  reversed.capped_method = gl::ShadowMethod::ZPPlus;
  EXPECT_THROW(analysis::parse_policy(analysis::policy_to_json(reversed), "t.json"), Error);  // with the exact test
  reversed.exact_zpass = false;
  EXPECT_EQ(analysis::parse_policy(analysis::policy_to_json(reversed), "t.json").near_plane, gl::NearPlane::Tight);
  const SwitchPolicy q = analysis::parse_policy(analysis::policy_to_json(p), "q.json");
  EXPECT_EQ(q.crack_model.features, p.crack_model.features);
  EXPECT_EQ(q.crack_model.weights, p.crack_model.weights);
  EXPECT_EQ(q.crack_model.threshold, p.crack_model.threshold);
  EXPECT_EQ(q.provenance_json, p.provenance_json);
}

TEST(SwitchPolicy, ABadFileIsOneLineNamingTheField) {
  auto replaced = [](const std::string& from, const std::string& to) {
    std::string s = valid_policy();
    const std::size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  const std::pair<std::string, std::string> cases[] = {
      {"{", "malformed JSON"},
      {replaced("\"version\": 1", "\"version\": 7"), "version: 7 is not a version"},
      {replaced("\"zpass_far\": \"infinite\"", "\"zpass_far\": \"infinite\", \"depth\": \"float32\""),
       "depth: is a version 3 field (this file says version 1)"},
      {replaced("\"version\": 1, \"capped_method\"", "\"version\": 3, \"depth\": \"float16\", \"capped_method\""),
       "depth: must be \"fixed24\" or \"float32\""},
      {replaced("\"version\": 1, \"capped_method\"",
                "\"version\": 3, \"depth_mapping\": \"inverted\", \"capped_method\""),
       "depth_mapping: must be \"standard\" or \"reversed\""},
      {replaced("\"version\": 1, \"capped_method\"", "\"version\": 3, \"near_plane\": \"far\", \"capped_method\""),
       "near_plane: must be \"scene\" or \"tight\""},
      {replaced("\"zpass_far\": \"infinite\"", "\"zpass_far\": \"infinite\", \"light_projection\": \"paper\""),
       "light_projection: is a version 2 field"},
      {replaced("\"version\": 1, \"capped_method\"",
                "\"version\": 2, \"light_projection\": \"sides\", \"capped_method\""),
       "light_projection: must be \"paper\""},
      {replaced("\"version\": 1, \"capped_method\"", "\"version\": 2, \"exact_zpass\": 0, \"capped_method\""),
       "exact_zpass: expected true or false, found number"},
      {replaced("\"zpass_far\": \"infinite\"", "\"zpass_far\": \"infinite\", \"exact_zpass\": false"),
       "exact_zpass: is a version 2 field"},
      {replaced("\"version\": 1,", ""), "version: missing"},
      {replaced("\"format\": \"nearcap-policy\"", "\"format\": \"x\""), "format"},
      {replaced("\"bias\": -3", "\"bias\": -3, \"extra\": 1"), "crack_model.extra: unknown key"},
      {replaced("\"mean\": [0, 0.2]", "\"mean\": [0]"), "crack_model.mean: 1 values for 2 features"},
      {replaced("\"log_skew\"", "\"log_magic\""), "crack_model.features[0]: 'log_magic' is not a policy feature"},
      {replaced("\"zfail\"", "\"zpplus\""), "fallback_method: must be zfail or preload"},
      {replaced("\"zfail\"", "\"atomiczp\""), "fallback_method: must be zfail or preload"},
      {replaced("\"zpplus-corrected\"", "\"zpplus-improved\""),
       "capped_method: must be \"zpass\", \"zfail\", \"zpplus\", \"zpplus-corrected\", \"preload\" or \"atomiczp\", "
       "not \"zpplus-improved\""},
      {replaced("\"zpplus-corrected\"", "\"zpass\""), "capped_method: must not be zpass"},
      {replaced("\"scale\": [1, 0.1]", "\"scale\": [1, 0]"), "crack_model.scale[1]: must be positive"},
      {replaced("\"threshold\": 0.01", "\"threshold\": 2"), "crack_model.threshold: must be in (0, 1]"},
      {replaced("\"threshold\": 0.01", "\"threshold\": \"low\""),
       "crack_model.threshold: expected a number, found string"},
      {replaced("\"clamp-far\"", "\"clamp-near\""), "switch_clamp"},
      {replaced("\"cost_models\": {}", "\"cost_models\": {\"zfast\": {}}"),
       "cost_models.zfast: 'zfast' is not a method"},
      {replaced("\"cost_models\": {}", "\"cost_models\": {\"zfail\": {\"intercept_ms\": 1}}"),
       "cost_models.zfail.ms_per_mtriangle: missing"},
  };
  for (const auto& [text, fragment] : cases) {
    try {
      analysis::parse_policy(text, "p.json");
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const Error& e) {
      // Text that is not JSON is a parse error; JSON that is not a policy, a schema error.
      EXPECT_EQ(e.kind(), fragment == "malformed JSON" ? ErrorKind::Parse : ErrorKind::Schema) << e.what();
      const std::string what = e.what();
      EXPECT_NE(what.find(fragment), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_EQ(what.rfind("p.json: ", 0), 0u) << what;
    }
  }
}

// The box scene at 32x24 (tests/box_scene.hpp).
Scene box_scene(const Vec3d& eye, const Vec3d& light) {
  test::BoxSceneOptions o;
  o.width = 32;
  o.height = 24;
  return test::box_scene(eye, light, o);
}

TEST(SwitchPolicy, DecidesExactlyWhereItCanAndByTheModelElsewhere) {
  SwitchPolicy p = analysis::parse_policy(valid_policy(), "p.json");
  {  // far from the shadow: exact Z-pass, the model not asked
    const Scene s = box_scene({6, 1, 6}, {0, 8, 0});
    const CameraSpaceScene cs(s);
    const analysis::PolicyDecision d = analysis::decide(p, cs, 0, {});
    EXPECT_EQ(d.object_methods[0], gl::ShadowMethod::ZPass);
    EXPECT_NE(d.reason(0).find("exact"), std::string::npos) << d.reason(0);
    EXPECT_TRUE(std::isnan(d.crack_probability));
    EXPECT_EQ(d.settings.switch_clamp, gl::SwitchClamp::DepthClampFar);
  }
  const Scene s = box_scene({0.1, -1.5, 0.2}, {0, 8, 0});  // the eye in the box's shadow
  const CameraSpaceScene cs(s);
  p.crack_model.threshold = 1.0;  // never predicts a crack
  analysis::PolicyDecision d = analysis::decide(p, cs, 0, {});
  EXPECT_EQ(d.object_methods[0], gl::ShadowMethod::ZPPlusCorrected) << d.reason(0);
  EXPECT_GT(d.crack_probability, 0);
  p.crack_model.threshold = 1e-300;  // always predicts one
  d = analysis::decide(p, cs, 0, {});
  EXPECT_EQ(d.object_methods[0], gl::ShadowMethod::ZFail) << d.reason(0);
  EXPECT_NE(d.reason(0).find("crack predicted"), std::string::npos) << d.reason(0);
  // A probability at the threshold predicts a crack (no crack is below it).
  p.crack_model = {};
  p.crack_model.bias = 0;  // P = 0.5 with no features
  p.crack_model.threshold = 0.5;
  d = analysis::decide(p, cs, 0, {});
  EXPECT_EQ(d.crack_probability, 0.5);
  EXPECT_EQ(d.object_methods[0], gl::ShadowMethod::ZFail) << d.reason(0);
}

// Whether decide() reads a policy's models, asked of decide() itself: the
// same frames decided with the model at two extremes, a decision that
// differs somewhere means it is read.  The frames: the box seen from far
// away (nothing meets the light pyramid) and from inside its shadow (it
// does), the bundled scene with the light in the near plane, the default
// scene, and the room paths' 12,000-triangle twisted torus in the box's
// place (above the shipped policy's unpriced frames, which hold the box).
std::vector<Scene> probe_scenes() {
  test::BoxSceneOptions torus;
  torus.width = 32;
  torus.height = 24;
  torus.occluder = "twisted_torus.off";
  return {box_scene({6, 1, 6}, {0, 8, 0}), box_scene({0.1, -1.5, 0.2}, {0, 8, 0}),
          load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/light_on_near_plane.json"),
          load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/default.json"),
          test::box_scene({0.1, -1.5, 0.2}, {0, 8, 0}, torus)};
}

bool decisions_differ(const std::vector<SwitchPolicy>& variants) {
  for (const Scene& s : probe_scenes()) {
    const CameraSpaceScene cs(s);
    std::vector<gl::ShadowMethod> first;
    for (const SwitchPolicy& p : variants) {
      const std::vector<gl::ShadowMethod> methods = analysis::decide(p, cs, 0, {}).object_methods;
      if (first.empty()) first = methods;
      if (methods != first) return true;
    }
  }
  return false;
}

// The crack model at P = 0 and at P = 1 (its features kept).  With a
// device profile, one under which the paper cap is the cheapest candidate
// wherever it is admitted (Z-fail's caps, the clipped-sides cap's CPU work
// and the exact test dear), so that admitting it shows.
bool decide_reads_crack_model(const SwitchPolicy& p) {
  SwitchPolicy never = p, always = p;
  if (p.device_profile) {
    analysis::DeviceProfile d;
    d.origin = "hand";
    for (std::size_t k = 0; k < analysis::kPassKindCount; ++k) d.passes[k] = {1e-3, 1, 1};
    for (PassKind k : {PassKind::LightCap, PassKind::DarkCap}) d.passes[static_cast<std::size_t>(k)] = {1, 1e6, 1e6};
    d.cpu.clipped_cap.ms_per_ktested = 1e6;
    d.cpu.exact_test.ms_per_ktested = 1e6;
    never.device_profile = always.device_profile = d;
  }
  never.crack_model.bias = -1000;
  always.crack_model.bias = 1000;
  return decisions_differ({never, always});
}

// Profiles where one pass kind or one CPU task costs everything.
bool decide_reads_device_profile(const SwitchPolicy& p) {
  std::vector<SwitchPolicy> variants;
  for (std::size_t k = 0; k < analysis::kPassKindCount + 3; ++k) {
    analysis::DeviceProfile d;
    d.origin = "hand";
    if (k < analysis::kPassKindCount)
      d.passes[k] = {1e3, 1e6, 1e6};
    else if (k == analysis::kPassKindCount)
      d.cpu.ms_per_ktriangle_silhouette = 1e6;
    else if (k == analysis::kPassKindCount + 1)
      d.cpu.clipped_cap.ms_per_ktested = 1e6;
    else
      d.cpu.exact_test.ms_per_ktested = 1e6;
    SwitchPolicy v = p;
    v.device_profile = d;
    variants.push_back(v);
  }
  return decisions_differ(variants);
}

bool has(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// unread_policy_models (what tune refuses to write and the shipped policies
// must not carry) says what decide() does, over the switches that decide
// whether a model is asked: with and without a device profile, with and
// without the exact Z-pass test, a capped method that draws a near-cap or
// not, the paper's cap or the clipped-sides one.
TEST(SwitchPolicy, TheUnreadModelsAreTheOnesDecideNeverReads) {
  const SwitchPolicy base = analysis::parse_policy(valid_policy(), "p.json");
  int checked = 0;
  for (bool profile : {false, true})
    for (bool exact : {true, false})
      for (gl::LightProjection projection : {gl::LightProjection::Paper, gl::LightProjection::ClippedSides})
        for (gl::ShadowMethod capped :
             {gl::ShadowMethod::ZPPlusCorrected, gl::ShadowMethod::ZPPlus, gl::ShadowMethod::ZFail}) {
          if (!exact && !gl::uses_near_cap(capped)) continue;  // not a policy (parse_policy refuses it)
          SwitchPolicy p = base;
          if (profile) p.device_profile = analysis::DeviceProfile{};
          p.exact_zpass = exact;
          p.light_projection = projection;
          p.capped_method = capped;
          p.fallback_method = capped == gl::ShadowMethod::ZFail ? gl::ShadowMethod::Preload : gl::ShadowMethod::ZFail;
          const std::vector<std::string> unread = analysis::unread_policy_models(p);
          const std::string where = std::string("profile ") + (profile ? "yes" : "no") + ", exact_zpass " +
                                    (exact ? "true" : "false") + ", " + std::string(gl::to_string(projection)) +
                                    ", capped " + std::string(gl::to_string(capped));
          EXPECT_EQ(has(unread, "crack_model"), !decide_reads_crack_model(p)) << where;
          if (profile) {
            EXPECT_FALSE(has(unread, "device_profile")) << where;
            EXPECT_TRUE(decide_reads_device_profile(p)) << where;
          }
          ++checked;
        }
  EXPECT_EQ(checked, 20);
  // A model without features is not a fitted one: nothing to report unread.
  SwitchPolicy none = base;
  none.exact_zpass = false;
  none.crack_model = {};
  EXPECT_TRUE(analysis::unread_policy_models(none).empty());
  none.cost_models.push_back({gl::ShadowMethod::ZFail, {}});
  EXPECT_TRUE(has(analysis::unread_policy_models(none), "cost_models"));  // decide() reads no cost model
}

// Each shipped policy loads (a broken file throws, which fails the test),
// and carries no model its own decision bypasses, checked on decide() too.
TEST(SwitchPolicy, TheShippedPolicyLoads) {
  for (const char* file : {"policy.json", "policy-reversed-z.json", "policy-tight-near.json"}) {
    SCOPED_TRACE(file);
    const SwitchPolicy p = analysis::load_policy(std::string(NEARCAP_SOURCE_DIR) + "/data/" + file);
    EXPECT_TRUE(analysis::unread_policy_models(p).empty())
        << "unread: " << ::testing::PrintToString(analysis::unread_policy_models(p));
    if (!p.crack_model.features.empty()) {
      EXPECT_TRUE(decide_reads_crack_model(p));
    }
    if (p.device_profile) {
      EXPECT_TRUE(decide_reads_device_profile(p));
    }
    // Each tier of its unpriced frames draws its frames with its method: on
    // a frame whose occluder (a bundled mesh) falls in the tier, the other
    // method draws another frame.
    for (std::size_t t = 0; t < p.unpriced_frames.size(); ++t) {
      SwitchPolicy other = p;
      other.unpriced_frames[t].method =
          p.unpriced_frames[t].method.method == gl::ShadowMethod::ZFail
              ? analysis::CandidateMethod{gl::ShadowMethod::ZPPlus, gl::LightProjection::ClippedSides, p.zpass_far}
              : analysis::CandidateMethod{gl::ShadowMethod::ZFail, gl::LightProjection::Paper, p.zpass_far};
      const std::size_t above = t == 0 ? 0 : p.unpriced_frames[t - 1].max_occluder_triangles + 1;
      std::optional<Scene> in_tier;
      for (const char* mesh : {"box.off", "eight.off", "torus.off", "knot1.off", "twisted_torus.off"}) {
        test::BoxSceneOptions o;
        o.width = 32;
        o.height = 24;
        o.occluder = mesh;
        Scene s = test::box_scene({0.1, -1.5, 0.2}, {0, 8, 0}, o);
        const std::size_t n = analysis::largest_occluder_triangles(s);
        if (n >= above && n <= p.unpriced_frames[t].max_occluder_triangles) {
          in_tier = std::move(s);
          break;
        }
      }
      ASSERT_TRUE(in_tier) << "no bundled mesh falls in unpriced tier " << t;
      const CameraSpaceScene cs(*in_tier);
      EXPECT_NE(analysis::decide(p, cs, 0, {}).object_methods, analysis::decide(other, cs, 0, {}).object_methods)
          << "tier " << t;
    }
    for (const std::string& f : p.crack_model.features)  // the decision stays O(1) beyond the pyramid test
      EXPECT_TRUE(analysis::cheap_policy_feature(f)) << f;
    EXPECT_GT(p.crack_model.threshold, 0);
    // Its held-out side: every crack of the capped method beyond the fallback's predicted.
    const nlohmann::json provenance = nlohmann::json::parse(p.provenance_json);
    EXPECT_EQ(provenance["held_out"]["cracks"], provenance["held_out"]["cracks_predicted"]);
  }
}

// The light in the near plane: no light frustum, so the paper's ZP+ falls
// back to Z-fail; with the clipped-sides near-cap the capped method stays,
// and the frame's settings carry the formulation.
// A light a hair beyond the near plane: the exact pyramid is defined, the
// float32 light frustum is not (the light's depth rounds onto the plane).
// The clipped-sides cap needs no light frustum: ZP+ stays, no fallback.
TEST(SwitchPolicy, TheClippedSidesCapNeedsNoFloatLightFrustumEither) {
  Scene s = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/light_on_near_plane.json");
  const Affine3d& view = s.camera.view;
  const Vec3d forward{-view.rows[2][0], -view.rows[2][1], -view.rows[2][2]};  // camera -z in world space
  s.lights[0].position = s.lights[0].position + (1e-10 * s.camera.frustum.near) * forward;
  const CameraSpaceScene cs(s);
  SwitchPolicy p = analysis::parse_policy(valid_policy(), "p.json");
  p.light_projection = gl::LightProjection::ClippedSides;
  p.crack_model = {};
  p.crack_model.bias = -30;
  p.crack_model.threshold = 1;
  ASSERT_FALSE(gl::light_frustum(s, 0, {}).defined) << "the float light frustum should be undefined here";
  const analysis::PolicyDecision d = analysis::decide(p, cs, 0, {});
  std::size_t capped = 0;
  for (std::size_t o = 0; o < s.objects.size(); ++o)
    if (s.objects[o].occluder) {
      EXPECT_NE(d.object_methods[o], p.fallback_method) << d.reason(o);
      capped += d.object_methods[o] == gl::ShadowMethod::ZPPlusCorrected;
    }
  EXPECT_GT(capped, 0u);
}

TEST(SwitchPolicy, TheClippedSidesCapNeedsNoLightFrustum) {
  const Scene s = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/light_on_near_plane.json");
  const CameraSpaceScene cs(s);
  SwitchPolicy p = analysis::parse_policy(valid_policy(), "p.json");
  p.crack_model.threshold = 1.0;  // never predicts a crack
  std::size_t occluders = 0;
  analysis::PolicyDecision d = analysis::decide(p, cs, 0, {});
  for (std::size_t o = 0; o < s.objects.size(); ++o)
    if (s.objects[o].occluder) {
      ++occluders;
      EXPECT_EQ(d.object_methods[o], gl::ShadowMethod::ZFail) << d.reason(o);
    }
  EXPECT_GT(occluders, 0u);
  p.light_projection = gl::LightProjection::ClippedSides;
  p.crack_model = {};  // no features, never a crack (what tune writes when nothing cracked in training)
  p.crack_model.bias = -30;
  p.crack_model.threshold = 1;
  d = analysis::decide(p, cs, 0, {});
  EXPECT_EQ(d.settings.light_frustum.projection, gl::LightProjection::ClippedSides);
  for (std::size_t o = 0; o < s.objects.size(); ++o)
    if (s.objects[o].occluder) {
      EXPECT_EQ(d.object_methods[o], gl::ShadowMethod::ZPPlusCorrected) << d.reason(o);
    }
  const PixelReference ref = compute_pixel_reference(cs, 0);
  const CrackReport zfail = judge_frame(gl::render_shadow_frame(s, 0, gl::ShadowMethod::ZFail), ref);
  gl::ShadowFrameBatch batch(s, 0, d.settings);
  EXPECT_LE(judge_frame(batch.render(d.object_methods), ref).wrong, zfail.wrong);
  // Version 3: the policy's depth buffer and mapping reach the frame's
  // settings, with the exact infinite row the reversed mapping needs.
  p.depth = gl::DepthFormat::Float32;
  p.depth_mapping = gl::DepthMapping::Reversed;
  gl::EmulationSettings nudged;
  nudged.infinite_far = gl::InfiniteFar::Doom3;
  d = analysis::decide(p, cs, 0, nudged);
  EXPECT_EQ(d.settings.depth, gl::DepthFormat::Float32);
  EXPECT_EQ(d.settings.depth_mapping, gl::DepthMapping::Reversed);
  EXPECT_EQ(d.settings.infinite_far, gl::InfiniteFar::Exact);
  gl::ShadowFrameBatch reversed(s, 0, d.settings);
  EXPECT_LE(judge_frame(reversed.render(d.object_methods), ref).wrong, zfail.wrong);
  p.near_plane = gl::NearPlane::Tight;
  p.exact_zpass = false;  // the exact test decides for the scene's near plane
  EXPECT_EQ(analysis::decide(p, cs, 0, {}).settings.near_plane, gl::NearPlane::Tight);
  p.exact_zpass = true;
  EXPECT_THROW(analysis::decide(p, cs, 0, {}), Error);
}

// The shipped policy on the bundled scenes and a bundled path: never more
// cracks than Z-fail in any frame, and Z-pass's cost where Z-pass is right.
// Both shipped policies: data/policy.json and data/policy-reversed-z.json.
class ShippedPolicy : public ::testing::TestWithParam<const char*> {};

TEST_P(ShippedPolicy, NeverCracksMoreThanZFailOnBundledScenes) {
  const SwitchPolicy policy = analysis::load_policy(std::string(NEARCAP_SOURCE_DIR) + "/data/" + GetParam());
  std::size_t scenes = 0, exact_zpass = 0;
  for (const char* name : {"default", "no_near_clip", "eye_in_shadow", "near_split", "case_d", "light_on_near_plane",
                           "near_cap_bunny_wall", "near_cap_bunny_cut", "twisted", "room", "room_side_light"}) {
    const Scene s = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name + ".json");
    const CameraSpaceScene cs(s);
    const PixelReferenceTracer tracer(cs, 0);
    const PixelReference ref = compute_pixel_reference(tracer);
    CrackDistances distances(tracer, ref);
    CrackReport zfail = judge_frame(gl::render_shadow_frame(s, 0, gl::ShadowMethod::ZFail), ref);
    distances.measure(zfail);
    const analysis::PolicyDecision d = analysis::decide(policy, cs, 0, {});
    gl::ShadowFrameBatch batch(s, 0, d.settings);
    CrackReport chosen = judge_frame(batch.render(d.object_methods), ref);
    distances.measure(chosen);
    EXPECT_LE(*chosen.cracks, *zfail.cracks) << name;
    for (std::size_t o = 0; o < s.objects.size(); ++o)
      if (s.objects[o].occluder && d.object_methods[o] == gl::ShadowMethod::ZPass) {
        ++exact_zpass;
        EXPECT_EQ(ref.cap_pixels_by_object[o], 0u) << name << " object " << o;  // Z-pass only where it is right
      }
    ++scenes;
  }
  EXPECT_EQ(scenes, 11u);
  if (policy.exact_zpass) {
    EXPECT_GT(exact_zpass, 0u);
  } else {
    EXPECT_EQ(exact_zpass, 0u);  // no test: the capped method everywhere
  }
}

INSTANTIATE_TEST_SUITE_P(DataFiles, ShippedPolicy,
                         ::testing::Values("policy.json", "policy-reversed-z.json", "policy-tight-near.json"),
                         [](const ::testing::TestParamInfo<const char*>& param) {
                           const std::string name(param.param);
                           return name == "policy.json"              ? std::string("Standard")
                                  : name == "policy-reversed-z.json" ? std::string("ReversedZ")
                                                                     : std::string("TightNear");
                         });

TEST(SwitchPolicy, TheAlternativePoliciesCarryTheirDepthChoices) {
  const SwitchPolicy p = analysis::load_policy(std::string(NEARCAP_SOURCE_DIR) + "/data/policy-reversed-z.json");
  EXPECT_EQ(p.depth, gl::DepthFormat::Float32);
  EXPECT_EQ(p.depth_mapping, gl::DepthMapping::Reversed);
  const SwitchPolicy standard = analysis::load_policy(std::string(NEARCAP_SOURCE_DIR) + "/data/policy.json");
  EXPECT_FALSE(standard.depth.has_value());
  EXPECT_EQ(p.capped_method, standard.capped_method);
  EXPECT_EQ(p.light_projection, standard.light_projection);
  const SwitchPolicy tight = analysis::load_policy(std::string(NEARCAP_SOURCE_DIR) + "/data/policy-tight-near.json");
  EXPECT_EQ(tight.near_plane, gl::NearPlane::Tight);
  EXPECT_FALSE(tight.depth.has_value());
  EXPECT_FALSE(standard.near_plane.has_value());
}

// End to end as a user runs it: a sweep, nearcap tune, then the policy it
// wrote in nearcap cracks.
TEST(SwitchPolicy, TuneThenCracksFromTheCommandLine) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("nearcap_tune_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string rows = (dir / "rows.csv").string(), policy = (dir / "policy.json").string();
  ASSERT_EQ(test::run_cli("sweep --samples 120 --seed 8 --kinds tiny-near,far-from-origin,eye-in-shadow --width 16 "
                          "--height 12 --methods zpplus-corrected,zfail --switch-clamp clamp-far --out " +
                              rows,
                          "tune_sweep")
                .exit_code,
            0);
  const test::CliResult tuned = test::run_cli("tune " + rows + " --out " + policy, "tune");
  ASSERT_EQ(tuned.exit_code, 0) << tuned.err;
  EXPECT_NE(tuned.out.find("held out:"), std::string::npos) << tuned.out;
  const SwitchPolicy p = analysis::load_policy(policy);
  const nlohmann::json provenance = nlohmann::json::parse(p.provenance_json);
  EXPECT_GT(provenance["train"]["samples"].get<int>(), 50);
  EXPECT_EQ(provenance["train"]["cracks"], provenance["train"]["cracks_predicted"]);  // every training crack
  const test::CliResult cracks = test::run_cli(
      "cracks data/scenes/near_cap_bunny_wall.json --light 0 --method zfail,policy --policy " + policy, "tune_cracks");
  ASSERT_EQ(cracks.exit_code, 0) << cracks.err;
  const nlohmann::json record = nlohmann::json::parse(cracks.out);
  ASSERT_EQ(record["methods"].size(), 2u);
  const nlohmann::json& chosen = record["methods"][1];
  EXPECT_EQ(chosen["method"], "policy");
  ASSERT_EQ(chosen["occluders"].size(), 1u);
  EXPECT_FALSE(chosen["occluders"][0]["why"].get<std::string>().empty());
  EXPECT_GE(chosen["decide_ms"].get<double>(), 0.0);
  // Rows without the policy's variant: a one-line usage error, nothing written.
  const test::CliResult bad =
      test::run_cli("tune " + rows + " --variant default --out " + (dir / "never.json").string(), "tune_bad");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("no training samples"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "never.json"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nearcap
