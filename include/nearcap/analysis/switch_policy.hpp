// nearcap/analysis/switch_policy.hpp — the runtime switch policy: per frame,
// light and occluder, the cheapest method predicted not to crack.
//
// The decision, for each occluder under a light:
//   1. exact where it is cheap: an occluder that meets no point of the light
//      pyramid (exact/light_pyramid.hpp) has an empty near-cap, so Z-pass is
//      exact for it: Z-pass;
//   2. the others get the policy's capped method (ZP+ corrected) unless the
//      light has no light frustum (the light in the near plane) or the crack
//      model predicts that ZP+ cracks in this (frame, light): then the
//      fallback method (Z-fail).  ZP+ corrected still switches its case-D
//      occluders, clamped as `switch_clamp` says (far only by default: the
//      stress test shows GL_DEPTH_CLAMP's near clamp breaks the depth test).
//      With `light_projection` clipped-sides the capped ZP+ needs no light
//      frustum (gl/near_plane_cap.hpp): a light in the near plane keeps it,
//      for every occluder (the pyramid test cannot tell them apart there).
// With `exact_zpass` false there is no step 1 and no model: the capped
// method for every occluder (docs/policy.md measures why the
// shipped policy does so).
// Before either decision: a frame that the scene's near plane leaves
// depth-limited (below) is drawn with the tight near plane
// (gl/tight_near_plane.hpp) where that frame is not, when the policy has no
// near plane of its own and no exact Z-pass test (which decides for the
// scene's plane); every method cracks on such a frame with the scene's plane.
// The crack model is a logistic model on the conditioning features
// (analysis/conditioning.hpp), fitted by `nearcap tune` (policy_fit.hpp):
//   P(crack) = 1 / (1 + exp(-(bias + sum_k w_k (x_k - mean_k) / scale_k)))
// with x the features below, and a crack predicted when P >= threshold.
//
// policy.json (docs/policy.md): {"format": "nearcap-policy",
// "version": 2, "capped_method": "zpplus-corrected", "fallback_method":
// "zfail", "switch_clamp": "clamp-far", "zpass_far": "infinite",
// "light_projection": "paper", "exact_zpass": true (version 2; version 1
// files, which lack them, are read as "paper" and true),
// "crack_model": {"features": [...],
// "mean": [...], "scale": [...], "weights": [...], "bias": b, "threshold":
// t}, "cost_models": {"zfail": {"intercept_ms": c, "ms_per_mtriangle": a,
// "ms_per_mfragment": b}, ...} (possibly empty), "device_profile": {...}
// (version 4, optional: DeviceProfile's fields, parse_device_profile below),
// "unpriced_frames": [{"max_occluder_triangles": n, "method": "zfail" or
// "zpplus-clipped-sides"}, ...] (version 6, optional, with a
// device_profile: its tiers, n ascending, UnpricedFrames below; version 5
// files hold one tier, the object alone), "provenance": {...}}.
// Every field is checked: an unknown key, a duplicate key (in any object,
// provenance's too), a missing one (cost_models and provenance included), a
// wrong type, an unknown or repeated feature, an unknown method, lengths that
// disagree, a non-finite number or another version is a one-line error
// (schema) naming the field; text that is not JSON (a syntax error,
// ill-formed UTF-8, a number beyond double such as 1e999) is an error (parse)
// naming the field it is in or the line and column.  load_policy reads the
// file like a scene (io/input_files.hpp): a regular file within
// NEARCAP_MAX_INPUT_MB.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "nearcap/analysis/conditioning.hpp"
#include "nearcap/analysis/device_profile.hpp"
#include "nearcap/analysis/kept_choices.hpp"
#include "nearcap/analysis/work_estimate.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::analysis {

// The model's inputs, each a transform of a conditioning feature that keeps
// it in a few units: logs of the quantities that span decades.
// Each logged quantity is taken as its absolute value floored at 10^-15 (an
// exact zero would otherwise dominate a fit), so a log is at least -15.
inline constexpr std::array<std::string_view, 8> kPolicyFeatures{
    "log_light_near_distance",   // log10 |signed distance of the light to the near plane / near|
    "log_l_far_over_width",      // log10 l_far / near-rectangle width (tiny near planes: large)
    "log_delta_over_width",      // log10 of the light's sideways offset / near-rectangle width
    "log_skew",                  // log10 of the light pyramid's skew
    "log_cond_light_transform",  // log10 cond(P_l M_l)
    "log_cap_window_error_px",   // log10 of the near-cap window coordinates' error, pixels
    "log_coordinate_over_size",  // log10 largest coordinate / scene size
    "l_near_over_l_far",
};
// The feature's value; NaN when the light frustum is undefined.
double policy_feature(std::string_view name, const ConditioningFeatures& f);
// The features that need only the light and the camera (no pass over the
// geometry, no light frustum): a model of these alone decides in O(1).
bool cheap_policy_feature(std::string_view name);
// Those features' inputs (light_frustum_defined, light_near_distance,
// l_far_over_width, delta_over_width, skew; the rest left 0), as
// conditioning_features computes them.
ConditioningFeatures cheap_conditioning_features(const CameraSpaceScene& scene, std::size_t light);

struct CrackModel {
  std::vector<std::string> features;  // names from kPolicyFeatures
  std::vector<double> mean, scale, weights;
  double bias = 0;
  double threshold = 0.5;
  // P(crack) for these features; NaN when a feature is NaN.
  double probability(const ConditioningFeatures& f) const;
};

// A method's frame time from its work: time = intercept + a per million
// triangles drawn (all passes) + b per million fragments rasterized (all
// passes), fitted by `nearcap tune` on the sweep's emulated times.
struct CostModel {
  double intercept_ms = 0, ms_per_mtriangle = 0, ms_per_mfragment = 0;
  double predict_ms(double triangles, double fragments) const {
    return intercept_ms + ms_per_mtriangle * triangles * 1e-6 + ms_per_mfragment * fragments * 1e-6;
  }
};

// One tier of a policy's unpriced frames: frames whose every occluder has
// at most `max_occluder_triangles` triangles (and more than the tier
// below's): the cost decision gives each occluder `method` (Z-fail, or ZP+
// with the clipped-sides cap: both as right as Z-fail) and prices nothing.
// On such frames choosing gains less than the pricing costs (its code and
// data cold in a new configuration); the tiers are fitted on training
// frames from `nearcap evaluate`'s rows (unpriced_frames_fit.hpp).
struct UnpricedFrames {
  std::size_t max_occluder_triangles = 0;
  CandidateMethod method;  // zfail or zpplus-clipped-sides
};

// The triangles of the scene's largest occluder (0 without one).
std::size_t largest_occluder_triangles(const Scene& scene);

struct SwitchPolicy {
  gl::ShadowMethod capped_method = gl::ShadowMethod::ZPPlusCorrected;
  gl::ShadowMethod fallback_method = gl::ShadowMethod::ZFail;
  gl::SwitchClamp switch_clamp = gl::SwitchClamp::DepthClampFar;
  gl::ZPassFar zpass_far = gl::ZPassFar::Infinite;
  gl::LightProjection light_projection = gl::LightProjection::Paper;  // the capped ZP+'s near-cap
  // Step 1 (exact Z-pass where the near-cap is empty).  false: every
  // occluder gets the capped method, no test at all; right for ZP+ with the
  // clipped-sides cap, which draws no cap where its float sides leave none
  // in the viewport and is then Z-pass, fragment for fragment.
  bool exact_zpass = true;
  // Version 3, optional: the depth buffer and the camera's depth mapping the
  // policy's frames are drawn with (reversed-Z: float32 and reversed, with
  // the exact infinite far row); absent, the caller's settings.
  std::optional<gl::DepthFormat> depth;
  std::optional<gl::DepthMapping> depth_mapping;
  std::optional<gl::NearPlane> near_plane;  // the tight near plane, or the scene's
  CrackModel crack_model;
  // Optional, read and checked where a file has them: per-method frame-time
  // models.  decide() reads none and `nearcap tune` writes none (a model the
  // decision never reads is not written: policy_fit.hpp,
  // unread_policy_models); the decision's costs are the device profile's.
  std::vector<std::pair<gl::ShadowMethod, CostModel>> cost_models;
  // Version 4, optional: what each pass and CPU task costs on the GL the
  // policy was calibrated on (device_profile.hpp); the decision's costs.
  std::optional<DeviceProfile> device_profile;
  // Versions 5 (one tier) and 6, optional, with a device profile: the frames the cost
  // decision draws without pricing, tier by tier (UnpricedFrames), their
  // max_occluder_triangles ascending; empty: every frame priced.
  std::vector<UnpricedFrames> unpriced_frames;
  std::string provenance_json = "{}";  // how it was fitted (kept as written)
};

// The tier of the policy's unpriced frames a frame whose largest occluder
// has `largest_occluder_triangles` falls in (the first whose bound holds
// it), or null: the frame is priced.
const UnpricedFrames* unpriced_tier(const SwitchPolicy& policy, std::size_t largest_occluder_triangles);

inline constexpr int kPolicyVersion = 6;  // written; 1 to 6 are read

// Reads and checks policy.json text; `source` names it in errors.
SwitchPolicy parse_policy(const std::string& text, const std::string& source);
SwitchPolicy load_policy(const std::string& path);
// The policy as policy.json text, read back before it is returned: one its
// reader refuses throws that reader's error (source "the policy to write").
std::string policy_to_json(const SwitchPolicy& policy);

// A device profile on its own (the policy's "device_profile" object, as
// text), checked as strictly as a policy: every key present once, no other,
// strings where they are strings, costs finite and not negative; errors
// (schema, parse) name the field from the object's top ("passes.depth.
// intercept_ms").  A profile measured elsewhere or written by hand goes into
// a policy with `policy.device_profile = parse_device_profile(...)` and
// policy_to_json.
DeviceProfile parse_device_profile(const std::string& text, const std::string& source);
// Read back likewise (source "the device profile to write").
std::string device_profile_to_json(const DeviceProfile& profile);

// Why the cost decision may or may not draw an occluder with Z-pass.
enum class ZPassVerdict {
  NoExactTest,       // the policy has no exact Z-pass test
  LightOnNearPlane,  // the light lies in the near plane
  CertainlyMisses,   // the float light-pyramid cull: certainly an empty near-cap
  ExactEmpty,        // the exact test ran: an empty near-cap
  ExactMeets,        // the exact test ran: it meets the light pyramid
  TestNotRun,        // the exact test's predicted cost is above its saving
};

// The cost decision's prices of one occluder's candidates (ms, the device
// profile's, before drawing; NaN where a candidate is not priced), which
// PolicyDecision::reason formats.
struct OccluderPrices {
  std::size_t object = 0;
  CandidateMethod chosen;
  double zfail_ms = 0, clipped_ms = 0, zpass_ms = 0;
  double paper_ms = std::numeric_limits<double>::quiet_NaN(), atomiczp_ms = std::numeric_limits<double>::quiet_NaN();
  bool zpass_ok = false, atomiczp_ok = false;
  ZPassVerdict zpass_verdict = ZPassVerdict::NoExactTest;
  double exact_test_ms = 0;  // the frame's exact test (ExactEmpty, ExactMeets, TestNotRun)
  std::string atomiczp_why;  // where the profile prices AtomicZP: why it is or is not a candidate
};

// The cost decision's prices of a frame: every occluder's, and the paper
// cap's admission, shared by its occluders.
struct FramePrices {
  std::vector<OccluderPrices> occluders;
  CandidateMethod paper;  // the policy's capped method with the paper's cap
  bool paper_ok = false;
  std::string paper_why;  // why not, where !paper_ok
  bool atomiczp_priced = false;
  // The tier of the policy's unpriced frames applied: every occluder drawn
  // with its method whatever the prices, which the reason still lists.
  std::optional<UnpricedFrames> unpriced;
  // A kept choice priced (PolicyDecision::frames_since_priced): the reason
  // says so, and lists this frame's prices.
  int frames_since_priced = 0;
};

// The policy's choice for one (scene, light).
struct PolicyDecision {
  std::vector<gl::ShadowMethod> object_methods;  // one per scene object (receivers: Z-pass, unused)
  // Per object, why ("" for receivers). Formatted when asked: a frame loop
  // that decides every frame reads only the methods.
  std::string reason(std::size_t object) const;
  // What reason() formats: without a device profile, the steps' text per
  // object; with one, the prices.
  std::vector<std::string> step_reasons;
  std::optional<FramePrices> prices;
  double crack_probability = 0;  // the model's, NaN when not asked
  double decide_ms = 0;          // the decision's own time (with DecisionPricing::ChoiceOnly, the choice's)
  // 0: this frame's choice was priced; k > 0: the choice of the frame
  // priced k frames before, kept (kept_choices.hpp).
  int frames_since_priced = 0;
  // A priced cost decision's margin (kept_choices.hpp): the least rise of
  // the chosen frame's price that another choice it weighed brings (another
  // frame option's best frame where its methods differ, the frame with the
  // exact Z-pass test where it was weighed and not run, or one occluder with
  // another of its candidates, by its marginal price), in ms
  // (choice_margin_ms) and over the chosen frame's price (choice_margin),
  // both as the decision's pricing weighs them: with
  // DecisionPricing::ChoiceOnly without the coverage every candidate draws
  // alike, so the ratio is larger than over the whole frame's predicted
  // time.  Weighed where a ChoiceOnly decision is given a KeptChoices and
  // prices the frame; NaN elsewhere.
  double choice_margin = std::numeric_limits<double>::quiet_NaN();
  double choice_margin_ms = std::numeric_limits<double>::quiet_NaN();
  // The frame's depth step at its farthest point over the scene's size, for
  // the settings below, or a bound of it where the bound is below
  // kDepthLimitedStep (conditioning.hpp, depth_step_against_limit), and
  // whether it reaches kDepthLimitedStep: then no method is guaranteed
  // right, and depth_note() says so and what fixes it.
  double depth_step_over_size = 0;
  bool depth_limited = false;
  std::string depth_note() const;  // empty where not depth_limited
  // Where the scene's near plane would leave the frame depth-limited and the
  // policy moved it (settings.near_plane Tight, depth_limited false): why,
  // with both planes; empty elsewhere.
  std::string near_plane_note() const;
  // What the notes say, formatted only when asked: the near plane's
  // distance the frame is drawn with, and where the policy moved it, the
  // scene's and its depth step over the scene's size (NaN where not moved).
  double near = std::numeric_limits<double>::quiet_NaN();
  double moved_from_near = std::numeric_limits<double>::quiet_NaN();
  double moved_from_step_over_size = std::numeric_limits<double>::quiet_NaN();
  // The emulation settings the frame needs (the policy's switch clamp).
  gl::EmulationSettings settings;
  // With a device profile (the cost decision): the chosen frame's predicted
  // end-to-end time (ms) and work (work_estimate.hpp), and each frame-level
  // option weighed ("no near-cap", "clipped-sides cap", "paper cap") with
  // its predicted ms; NaN, zero and empty without a profile.
  double predicted_ms = std::numeric_limits<double>::quiet_NaN();
  FrameWork predicted_work;
  std::vector<std::pair<std::string_view, double>> predicted_options;  // names: static text
};
// Without a device profile, the steps in this header's opening comment.
// With one (the cost decision), every candidate right wherever Z-fail is
// right, per occluder, priced by the profile on the work estimate
// (work_estimate.hpp) before drawing:
//   Z-pass            where the near-cap is empty: certainly (the float
//                     light-pyramid cull, no cost) or by the exact test
//                     (exact/light_pyramid.hpp), which runs only when the
//                     best frame with Z-pass for every occluder it would
//                     test, the test paid for them, is predicted cheaper than
//                     the best frame without it;
//                     only with exact_zpass and the light off the near plane;
//   ZP+, clipped-sides cap;
//   the policy's capped method with the paper's cap, where the light frustum
//                     exists and the crack model predicts no crack (a policy
//                     whose light_projection is paper: its model is the paper
//                     cap's);
//   Z-fail;
//   AtomicZP          where the profile has its eye-count row (absent: not
//                     offered) and it is right wherever Z-fail is: each
//                     occluder triangle wholly beyond the near plane or
//                     wholly on or behind the eye's plane (exact: no point
//                     of it where a view ray meets it before the near
//                     plane), and the occluder's share of the eye count
//                     decided robustly: the exact count (exact/eye_count.hpp)
//                     not on_boundary, and the float32 count as the GL's pass
//                     computes it (gl/eye_count.hpp) equal to it; priced as
//                     Z-pass's sides plus its triangles in the frame's one
//                     eye-count pass (whose intercept and stencil write the
//                     frame pays once); tested only where cheaper than Z-fail
//                     and Z-pass is not certainly exact.
// A frame has one near-cap kind (its light projection; the paper's also
// makes the frame's projection finite, so Z-fail beside it clamps as
// switch_clamp says): the decision weighs three frame-level options (no
// near-cap, the clipped-sides cap, the paper cap; each also with the
// eye-count pass where some occluder admits AtomicZP), in each the cheapest
// candidate per occluder (pass intercepts left out of the per-occluder
// comparison), and keeps the option with the least predicted frame time,
// the shared passes (depth pre-pass, lit pass, silhouettes) and each drawn
// pass's intercept counted once.  Reasons name the chosen method and every
// candidate's predicted ms.  With `facings`, each occluder's facing under
// the light is taken from it where kept (a renderer's frame loop keeps one
// across frames: occluder_facing.hpp); the decision is the same either way.
//
// With DecisionPricing::ChoiceOnly the cost decision makes the same choice
// without what adds the same to every candidate's price: the sides'
// coverage (every candidate but AtomicZP draws the same sides; computed
// where the profile prices AtomicZP) and the depth and lit passes' (every
// frame option draws them).  Its predicted_ms is then NaN, its
// predicted_work and predicted_options empty and its prices absent:
// price_decision completes them.  A frame loop times the choice; the prices
// are what a report reads, as the reasons' text is.
//
// With `kept` (a frame loop's KeptChoices, kept_choices.hpp), a ChoiceOnly
// cost decision takes the choice kept from a recent priced frame where it
// qualifies (frames_since_priced > 0: no pricing, the frame's settings still
// settled above), and otherwise offers its choice and margin to be kept; a
// Full decision neither takes nor offers one.
enum class DecisionPricing { Full, ChoiceOnly };
PolicyDecision decide(const SwitchPolicy& policy, const CameraSpaceScene& scene, std::size_t light,
                      const gl::EmulationSettings& base, FacingCache* facings = nullptr,
                      DecisionPricing pricing = DecisionPricing::Full, KeptChoices* kept = nullptr);

// The prices of a ChoiceOnly decision `d` made with the same arguments: its
// predicted frame time, work, options and every candidate's prices, as the
// full decision computes them; d's methods and decide_ms are kept (a choice
// and the full decision differ only where two options' prices tie within
// rounding).  A kept choice (d.frames_since_priced > 0) is priced as drawn:
// its predicted frame time and work are its methods', the candidates'
// prices this frame's.  Nothing to do for a decision without a device
// profile.
void price_decision(PolicyDecision& d, const SwitchPolicy& policy, const CameraSpaceScene& scene, std::size_t light,
                    const gl::EmulationSettings& base, FacingCache* facings = nullptr);

}  // namespace nearcap::analysis
