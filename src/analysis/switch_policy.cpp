// The runtime switch policy's decision (see switch_policy.hpp); reading and
// writing the policy file is policy_file.cpp.
#include "nearcap/analysis/switch_policy.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <set>
#include <tuple>

#include "general4.hpp"
#include "nearcap/analysis/near_rectangle_pyramid.hpp"
#include "nearcap/analysis/side_plane_clearance.hpp"
#include "nearcap/analysis/work_estimate.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/eye_count.hpp"
#include "nearcap/exact/light_facing.hpp"
#include "nearcap/exact/light_pyramid.hpp"
#include "nearcap/gl/eye_count.hpp"
#include "nearcap/gl/light_frustum.hpp"

namespace nearcap::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double log10_or_nan(double v) { return std::isfinite(v) ? std::log10(std::max(std::fabs(v), 1e-15)) : kNaN; }

}  // namespace

double policy_feature(std::string_view name, const ConditioningFeatures& f) {
  if (!f.light_frustum_defined) return kNaN;
  if (name == "log_light_near_distance") return log10_or_nan(f.light_near_distance);
  if (name == "log_l_far_over_width") return log10_or_nan(f.l_far_over_width);
  if (name == "log_delta_over_width") return log10_or_nan(f.delta_over_width);
  if (name == "log_skew") return log10_or_nan(f.skew);
  if (name == "log_cond_light_transform") return log10_or_nan(f.cond_light_transform);
  if (name == "log_cap_window_error_px") return log10_or_nan(f.cap_window_error_px);
  if (name == "log_coordinate_over_size") return log10_or_nan(f.coordinate_over_size);
  if (name == "l_near_over_l_far") return f.l_near_over_l_far;
  throw Error(ErrorKind::Usage, "unknown policy feature '" + std::string(name) + "'");
}

bool cheap_policy_feature(std::string_view name) {
  return name == "log_light_near_distance" || name == "log_l_far_over_width" || name == "log_delta_over_width" ||
         name == "log_skew";
}

ConditioningFeatures cheap_conditioning_features(const CameraSpaceScene& cs, std::size_t light) {
  const Scene& scene = cs.scene();
  const Frustum& fr = scene.camera.frustum;
  ConditioningFeatures f;
  f.light_near_distance = to_double(Rational((cs.exact_light(light).z + Rational(fr.near)) / Rational(fr.near)));
  // The float light frustum's l_far and offset, as gl::light_frustum has them.
  const gl::Vec4f delta = gl::light_in_camera_space(scene, light);
  const float side = delta.z + static_cast<float>(fr.near);
  f.light_frustum_defined = side != 0.0f;
  if (!f.light_frustum_defined) return f;
  const double l_far = std::fabs(static_cast<double>(side));
  const double width = fr.right - fr.left;
  const double cx = 0.5 * (fr.left + fr.right), cy = 0.5 * (fr.bottom + fr.top);
  const double offset = std::hypot(delta.x - cx, delta.y - cy);
  f.l_far_over_width = l_far / width;
  f.delta_over_width = offset / width;
  f.skew = offset / l_far;
  return f;
}

double CrackModel::probability(const ConditioningFeatures& f) const {
  double z = bias;
  for (std::size_t k = 0; k < features.size(); ++k) {
    const double x = policy_feature(features[k], f);
    if (!std::isfinite(x)) return kNaN;
    z += weights[k] * (x - mean[k]) / scale[k];
  }
  return 1.0 / (1.0 + std::exp(-z));
}

DeviceProfile scaled_profile(const DeviceProfile& p, double gl_factor, double cpu_factor) {
  if (!(std::isfinite(gl_factor) && gl_factor > 0) || !(std::isfinite(cpu_factor) && cpu_factor > 0))
    throw Error(ErrorKind::Usage, "a profile's speed-up factors must be finite and positive (GL " +
                                      std::to_string(gl_factor) + ", CPU " + std::to_string(cpu_factor) + ")");
  DeviceProfile s = p;
  s.origin = "scaled";
  for (PassCost& c : s.passes) {
    c.intercept_ms /= gl_factor;
    c.ms_per_mtriangle /= gl_factor;
    c.ms_per_mfragment /= gl_factor;
    c.ms_per_mtriangle_in_view /= gl_factor;
  }
  if (s.eye_count) {
    s.eye_count->intercept_ms /= gl_factor;
    s.eye_count->ms_per_mtriangle /= gl_factor;
    s.eye_count->ms_per_mfragment /= gl_factor;
  }
  if (s.frame) {
    s.frame->intercept_ms /= gl_factor;
    s.frame->ms_saved_per_pass /= gl_factor;
  }
  s.cpu.ms_per_ktriangle_silhouette /= cpu_factor;
  for (CpuTaskCost* c : {&s.cpu.clipped_cap, &s.cpu.exact_test}) {
    c->intercept_ms /= cpu_factor;
    c->ms_per_ktriangle /= cpu_factor;
    c->ms_per_kreaching /= cpu_factor;
    c->ms_per_ktested /= cpu_factor;
    c->ms_per_kstraddling /= cpu_factor;
    c->ms_per_kexamined /= cpu_factor;
  }
  // A factor below 1 can take a cost past what a profile holds
  // (kMaxCostCoefficientMs): refused, as the profile's reader would.
  try {
    device_profile_to_json(s);
  } catch (const Error& e) {
    throw Error(ErrorKind::Usage, "a profile scaled by GL " + std::to_string(gl_factor) + ", CPU " +
                                      std::to_string(cpu_factor) + ": " + e.what());
  }
  return s;
}

namespace {
PolicyDecision decide_by_cost(const SwitchPolicy& policy, const CameraSpaceScene& cs, const Frustum* tight,
                              std::size_t light, const gl::EmulationSettings& base, PolicyDecision d,
                              FacingCache* facings, DecisionPricing pricing, double* margin,
                              const PolicyDecision* forced);
}  // namespace

std::size_t largest_occluder_triangles(const Scene& scene) {
  std::size_t largest = 0;
  for (const SceneObject& o : scene.objects)
    if (o.occluder) largest = std::max(largest, o.mesh->triangles.size());
  return largest;
}

const UnpricedFrames* unpriced_tier(const SwitchPolicy& policy, std::size_t largest_occluder_triangles) {
  for (const UnpricedFrames& tier : policy.unpriced_frames)
    if (largest_occluder_triangles <= tier.max_occluder_triangles) return &tier;
  return nullptr;
}

namespace {

// decide(), and price_decision's pricing of a kept choice: `forced`, a
// decision whose methods and light projection the cost decision prices as
// drawn instead of choosing.
PolicyDecision decide_impl(const SwitchPolicy& policy, const CameraSpaceScene& cs, std::size_t light,
                           const gl::EmulationSettings& base, FacingCache* facings, DecisionPricing pricing,
                           KeptChoices* kept, const PolicyDecision* forced) {
  const auto t0 = std::chrono::steady_clock::now();
  const Scene& scene = cs.scene();
  PolicyDecision d;
  d.settings = base;
  d.settings.switch_clamp = policy.switch_clamp;
  d.settings.zpass_far = policy.zpass_far;
  d.settings.light_frustum.projection = policy.light_projection;
  if (policy.depth) d.settings.depth = *policy.depth;
  if (policy.near_plane) d.settings.near_plane = *policy.near_plane;
  if (policy.depth_mapping) {
    d.settings.depth_mapping = *policy.depth_mapping;
    // The reversed row puts infinity at depth 0 exactly; the nudges are the standard row's.
    if (*policy.depth_mapping == gl::DepthMapping::Reversed) d.settings.infinite_far = gl::InfiniteFar::Exact;
  }
  // The clipped-sides near-cap needs no light frustum: ZP+ with it stays
  // right where the paper's frustum is undefined.
  const bool frustum_free =
      gl::uses_near_cap(policy.capped_method) && policy.light_projection == gl::LightProjection::ClippedSides;
  // The frustum with the tight near plane, where the frame is drawn with it
  // (the work estimate's camera): the settings' plane, or the one a
  // depth-limited frame moves to below.
  std::optional<Frustum> tight;
  if (d.settings.near_plane == gl::NearPlane::Tight) tight = gl::tight_frustum(scene);
  double near = tight ? tight->near : scene.camera.frustum.near;
  d.depth_step_over_size = depth_step_against_limit(cs, near, d.settings.depth, d.settings.depth_mapping).over_size;
  d.depth_limited = d.depth_step_over_size >= kDepthLimitedStep;
  // A depth-limited frame the policy may move its near plane for (no near
  // plane of its own, no exact test tied to the scene's plane): drawn with
  // the tight near plane where that frame is not depth-limited.
  if (d.depth_limited && !policy.near_plane && !policy.exact_zpass && !tight) {
    const Frustum moved = gl::tight_frustum(scene);
    const double step = depth_step_against_limit(cs, moved.near, d.settings.depth, d.settings.depth_mapping).over_size;
    if (step < kDepthLimitedStep) {
      d.moved_from_near = near;
      d.moved_from_step_over_size = d.depth_step_over_size;
      d.settings.near_plane = gl::NearPlane::Tight;
      tight = moved;
      near = moved.near;
      d.depth_step_over_size = step;
      d.depth_limited = false;
    }
  }
  d.near = near;
  d.object_methods.assign(scene.objects.size(), gl::ShadowMethod::ZPass);
  // The cost decision's reasons are its prices (PolicyDecision::reason).
  if (!policy.device_profile) d.step_reasons.assign(scene.objects.size(), "");
  d.crack_probability = kNaN;
  if (policy.exact_zpass && d.settings.near_plane == gl::NearPlane::Tight)
    throw Error(ErrorKind::Usage,
                "the policy's exact Z-pass test decides for the scene's near plane, and the frame would use the tight "
                "one: a tight near plane needs a policy with exact_zpass false");
  if (policy.device_profile) {
    const gl::NearPlane near_plane = d.settings.near_plane;
    const bool depth_limited = d.depth_limited;
    if (kept && !forced && pricing == DecisionPricing::ChoiceOnly)
      if (std::optional<KeptChoices::Choice> k = kept->take(policy, scene, light, near_plane, depth_limited)) {
        d.object_methods = std::move(k->object_methods);
        d.settings.light_frustum.projection = k->projection;
        d.frames_since_priced = k->frames_since_priced;
        d.decide_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        return d;
      }
    // The margin is weighed only where a choice may be kept.
    const bool keeps = kept && !forced && pricing == DecisionPricing::ChoiceOnly;
    double margin = kNaN;
    d = decide_by_cost(policy, cs, tight ? &*tight : nullptr, light, base, std::move(d), facings, pricing,
                       keeps ? &margin : nullptr, forced);
    d.choice_margin = margin;
    if (keeps)
      kept->remember(policy, scene, light, near_plane, depth_limited, d.object_methods,
                     d.settings.light_frustum.projection, margin);
    d.decide_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return d;
  }
  if (!policy.exact_zpass) {
    // No per-occluder test: the capped method everywhere (with the
    // clipped-sides cap that is Z-pass plus the cap its own clipped sides
    // leave, nothing where they leave none).
    for (std::size_t o = 0; o < scene.objects.size(); ++o)
      if (scene.objects[o].occluder) {
        d.object_methods[o] = policy.capped_method;
        d.step_reasons[o] = "every occluder (no exact Z-pass test)";
      }
    d.decide_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return d;
  }
  std::vector<bool> meets;
  bool degenerate = false;
  try {
    meets = occluders_meeting_light_pyramid(cs, light);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Degenerate) throw;
    degenerate = true;  // the light in the near plane
  }
  bool any_capped = false;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    if (!scene.objects[o].occluder) continue;
    if (degenerate && frustum_free) {
      d.object_methods[o] = policy.capped_method;
      d.step_reasons[o] = "the light lies in the near plane: the clipped-sides near-cap needs no light frustum";
    } else if (degenerate) {
      d.object_methods[o] = policy.fallback_method;
      d.step_reasons[o] = "the light lies in the near plane: no light frustum";
    } else if (!meets[o]) {
      d.step_reasons[o] = "exact: meets no point of the light pyramid (empty near-cap)";
    } else {
      any_capped = true;
    }
  }
  if (any_capped) {
    gl::ShadowMethod chosen = policy.capped_method;
    std::string why;
    if (gl::uses_near_cap(chosen)) {
      // A model of cheap features alone needs neither the light frustum's
      // l_near (a pass over the occluders) nor the window errors.
      bool cheap = true;
      for (const std::string& name : policy.crack_model.features) cheap = cheap && cheap_policy_feature(name);
      gl::LightFrustum lf;
      ConditioningFeatures f;
      if (cheap) {
        f = cheap_conditioning_features(cs, light);
        lf.defined = f.light_frustum_defined;
        lf.undefined_reason = "the light lies in the camera's near plane (l_far = 0)";
      } else {
        lf = gl::light_frustum(scene, light, base.light_frustum);
        if (lf.defined) f = conditioning_features(cs, light, lf, base.arithmetic);
      }
      if (!lf.defined && !frustum_free) {
        chosen = policy.fallback_method;
        why = "meets the light pyramid, no light frustum (" + lf.undefined_reason + ")";
      } else {
        d.crack_probability = policy.crack_model.probability(f);
        if (!(d.crack_probability < policy.crack_model.threshold)) {
          chosen = policy.fallback_method;
          why = "meets the light pyramid, crack predicted (P = " + std::to_string(d.crack_probability) + ")";
        } else {
          why = "meets the light pyramid, no crack predicted (P = " + std::to_string(d.crack_probability) + ")";
        }
      }
    } else {
      why = "meets the light pyramid";
    }
    for (std::size_t o = 0; o < scene.objects.size(); ++o)
      if (scene.objects[o].occluder && !degenerate && meets[o]) {
        d.object_methods[o] = chosen;
        d.step_reasons[o] = why;
      }
  }
  d.decide_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return d;
}

}  // namespace

PolicyDecision decide(const SwitchPolicy& policy, const CameraSpaceScene& cs, std::size_t light,
                      const gl::EmulationSettings& base, FacingCache* facings, DecisionPricing pricing,
                      KeptChoices* kept) {
  return decide_impl(policy, cs, light, base, facings, pricing, kept, nullptr);
}

namespace {

// The decision's own helpers (the cost decision, switch_policy.hpp).

// A profile's price of one occluder's work, its passes' intercepts left out
// (a pass is drawn once per frame whatever its occluders: the frame's total
// counts each intercept once).
double marginal_ms(const DeviceProfile& profile, FrameWork w) {
  w.drawn = {};
  return profile.predict_ms(w);
}

// printf's %.4g (general4.hpp).
void append_ms(std::string& out, double ms) { append_general4(out, ms); }

std::string ms_text(double ms) {
  std::string s;
  append_ms(s, ms);
  return s;
}

// Whether the policy's capped method with the paper's cap is a candidate in
// this (frame, light): the light frustum exists and the crack model predicts
// no crack; `why` (where given) says why not, `probability` is the model's.
bool paper_cap_admitted(const SwitchPolicy& policy, const CameraSpaceScene& cs, std::size_t light,
                        const gl::EmulationSettings& base, double& probability, std::string* why) {
  probability = kNaN;
  if (!gl::uses_near_cap(policy.capped_method) || policy.light_projection == gl::LightProjection::ClippedSides) {
    if (why) *why = "the policy's crack model is not the paper cap's";
    return false;
  }
  bool cheap = true;
  for (const std::string& name : policy.crack_model.features) cheap = cheap && cheap_policy_feature(name);
  ConditioningFeatures f;
  bool defined = false;
  if (cheap) {
    f = cheap_conditioning_features(cs, light);
    defined = f.light_frustum_defined;
  } else {
    const gl::LightFrustum lf = gl::light_frustum(cs.scene(), light, base.light_frustum);
    defined = lf.defined;
    if (defined) f = conditioning_features(cs, light, lf, base.arithmetic);
  }
  if (!defined) {
    if (why) *why = "no light frustum";
    return false;
  }
  probability = policy.crack_model.probability(f);
  if (!(probability < policy.crack_model.threshold)) {
    if (why) *why = "crack predicted (P = " + ms_text(probability) + ")";
    return false;
  }
  return true;
}

// Whether cheap_conditioning_features(cs, light).light_near_distance is 0,
// the light's exact signed distance to the near plane over near rounded to
// a double: certainly not where the filtered estimate of z + near is away
// from zero by more than its bound and far above underflow (the quotient
// then rounds to a normal double); else as cheap_conditioning_features
// computes it, over rationals.
bool light_lies_on_near_plane(const CameraSpaceScene& cs, std::size_t light) {
  const double near = cs.frustum().near;
  const BoundedDouble side = cs.light(light).z + BoundedDouble(near);
  if (side.is_finite() && side.sign().value_or(Sign::Zero) != Sign::Zero &&
      std::fabs(side.v) - side.e > 0x1p-900 * near)
    return false;
  return cheap_conditioning_features(cs, light).light_near_distance == 0;
}

// Whether AtomicZP is right for occluder o under the light wherever Z-fail
// is (docs/atomiczp.md, "Where it is right"): the near plane does not cut
// the occluder, and its share of the eye count is decided robustly: the
// exact count's perturbation decided no tie at the eye (`on_boundary`), and
// the float32 count, computed as the GL's pass computes it (gl/eye_count.hpp,
// in `arithmetic`), equals it; and no side plane of its volume passes the
// eye closer than the float32 clip coordinates of its quad can place it
// (side_plane_clearance.hpp: the almost edge-on quad of a plane that nearly
// holds the eye covers pixels the exact one does not).  Counts add over
// occluders, so a frame's count over its AtomicZP occluders is right where
// each one's is.  `why` says why not, or what was found.  `drawn`: the
// frustum the frame is drawn with.
bool atomiczp_admitted(const CameraSpaceScene& cs, std::size_t o, std::size_t light, const Frustum& drawn,
                       gl::Arithmetic arithmetic, std::string& why) {
  // No view ray meets the occluder in front of the near plane: none of its
  // triangles meets the near-rectangle pyramid of the frustum the frame is
  // drawn with (near_rectangle_pyramid.hpp).  A view ray (inside the view
  // pyramid, past the eye) then meets it only beyond the near plane, where
  // the depth pre-pass draws it, so depth-clamped Z-pass misses none of its
  // light cap's crossings.
  if (!occluder_clear_of_near_rectangle_pyramid(cs, o, drawn)) {
    why = "the near plane cuts the occluder";
    return false;
  }
  std::vector<std::vector<Facing>> facing(cs.object_count());
  facing[o] = light_facing(cs, o, light, nullptr);
  const ExactEyeCount exact = exact_eye_count(cs, light, facing);
  if (exact.on_boundary) {
    why = "the eye is on a boundary of its volume (exact eye count on_boundary)";
    return false;
  }
  const gl::FloatEyeCount fl = gl::float_eye_count(cs.scene(), light, {o}, arithmetic);
  if (fl.count != exact.count) {
    why = "float eye count " + std::to_string(fl.count) + ", exact " + std::to_string(exact.count);
    return false;
  }
  const SidePlaneClearance clearance = side_plane_clearance(cs, o, light);
  if (clearance.within_bound) {
    why = "a side plane of its volume passes the eye within the float32 bound (" + ms_text(clearance.nearest_units) +
          " of " + ms_text(kSidePlaneBoundUnits) + " float32 units)";
    return false;
  }
  why = "eye count " + std::to_string(exact.count) + ", exact and float agree";
  return true;
}

// `tight`: the frustum with the tight near plane where the frame is drawn
// with it, for the work estimate; null where it is drawn with the scene's.
PolicyDecision decide_by_cost(const SwitchPolicy& policy, const CameraSpaceScene& cs, const Frustum* tight,
                              std::size_t light, const gl::EmulationSettings& base, PolicyDecision d,
                              FacingCache* facings, DecisionPricing pricing, double* margin,
                              const PolicyDecision* forced) {
  const DeviceProfile& profile = *policy.device_profile;
  const gl::ZPassFar far = policy.zpass_far;
  const CandidateMethod zpass{gl::ShadowMethod::ZPass, gl::LightProjection::Paper, far};
  const CandidateMethod zfail{gl::ShadowMethod::ZFail, gl::LightProjection::Paper, far};
  const CandidateMethod clipped{gl::ShadowMethod::ZPPlus, gl::LightProjection::ClippedSides, far};
  const CandidateMethod paper{policy.capped_method, gl::LightProjection::Paper, far};
  const CandidateMethod atomiczp{gl::ShadowMethod::AtomicZP, gl::LightProjection::Paper, far};
  // AtomicZP is a candidate only where the profile prices its eye-count pass.
  const bool atomiczp_priced = profile.eye_count.has_value();
  // A choice without the coverage every candidate shares (decide's header).
  const bool choice_only = pricing == DecisionPricing::ChoiceOnly;
  // A frame the policy draws without pricing: the choice is made here; the
  // full decision prices its candidates for the reasons, then draws it.
  const UnpricedFrames* const tier = unpriced_tier(policy, largest_occluder_triangles(cs.scene()));
  const bool unpriced = tier != nullptr;
  if (unpriced && choice_only) {
    const CandidateMethod& m = tier->method;
    if (m.method != gl::ShadowMethod::ZFail) d.settings.light_frustum.projection = m.cap;
    for (std::size_t o = 0; o < cs.scene().objects.size(); ++o)
      if (cs.scene().objects[o].occluder) d.object_methods[o] = m.method;
    return d;
  }
  // The scene as the frame draws it.
  std::optional<Scene> tight_scene;
  if (tight) {
    tight_scene = cs.scene();
    tight_scene->camera.frustum = *tight;
  }
  const Scene& scene = tight_scene ? *tight_scene : cs.scene();

  // The light in the near plane (exactly): no pyramid test, no light frustum.
  const bool light_on_near_plane = light_lies_on_near_plane(cs, light);
  std::string paper_why;
  const bool paper_ok = !light_on_near_plane && paper_cap_admitted(policy, cs, light, base, d.crack_probability,
                                                                   choice_only ? nullptr : &paper_why);
  if (light_on_near_plane && !choice_only) paper_why = "the light lies in the near plane: no light frustum";

  // zpass_ok: the near-cap is empty (certainly, or by the exact test);
  // atomiczp_ok: atomiczp_admitted.
  struct Occluder : OccluderPrices {
    OccluderWorkInputs in;
  };
  std::vector<Occluder> occluders;
  WorkInputsOptions inputs_options;
  inputs_options.pyramid_cull = policy.exact_zpass && !light_on_near_plane;
  // The sides' coverage is the same for every candidate but AtomicZP, and
  // their triangles in view too unless a finite far plane clips Z-pass's
  // and ZP+'s (and not Z-fail's).
  inputs_options.sides_coverage = !choice_only || atomiczp_priced || far == gl::ZPassFar::Finite;
  inputs_options.facings = facings;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    if (!scene.objects[o].occluder) continue;
    Occluder oc;
    oc.object = o;
    // The cull decides Z-pass only where the policy may pick it.
    oc.in = occluder_work_inputs(scene, o, light, inputs_options);
    oc.zfail_ms = marginal_ms(profile, occluder_work(oc.in, zfail));
    oc.clipped_ms = marginal_ms(profile, occluder_work(oc.in, clipped));
    if (paper_ok) oc.paper_ms = marginal_ms(profile, occluder_work(oc.in, paper));
    oc.zpass_ms = marginal_ms(profile, occluder_work(oc.in, zpass));
    if (atomiczp_priced) {
      oc.atomiczp_ms = marginal_ms(profile, occluder_work(oc.in, atomiczp));
      // Its conditions are tested only where it could be chosen: cheaper
      // than Z-fail, the candidate every frame option has, and not where
      // Z-pass is certainly right (Z-pass draws the same sides, no pass).
      if (policy.exact_zpass && !light_on_near_plane && oc.in.certainly_misses_light_pyramid)
        oc.atomiczp_why = "Z-pass is exact here and cheaper";
      else if (!(oc.atomiczp_ms < oc.zfail_ms))
        oc.atomiczp_why = "not cheaper than zfail";
      else
        oc.atomiczp_ok = atomiczp_admitted(cs, o, light, scene.camera.frustum, d.settings.arithmetic, oc.atomiczp_why);
    }
    occluders.push_back(std::move(oc));
  }
  bool any_atomiczp = false;
  for (const Occluder& oc : occluders) any_atomiczp = any_atomiczp || oc.atomiczp_ok;
  // Z-pass: free where the cull is certain; elsewhere only after the exact
  // test, whose cost the frame then pays for every occluder it tests.
  std::vector<bool> untested(occluders.size(), false);
  bool any_untested = false;
  for (std::size_t i = 0; i < occluders.size(); ++i) {
    Occluder& oc = occluders[i];
    if (!policy.exact_zpass) {
      oc.zpass_verdict = ZPassVerdict::NoExactTest;
    } else if (light_on_near_plane) {
      oc.zpass_verdict = ZPassVerdict::LightOnNearPlane;
    } else if (oc.in.certainly_misses_light_pyramid) {
      oc.zpass_ok = true;
      oc.zpass_verdict = ZPassVerdict::CertainlyMisses;
    } else {
      untested[i] = any_untested = true;
    }
  }

  // The frame-level options, each with its cheapest candidate per occluder
  // (Z-pass where `zpass_allowed`), the best of them: its predicted ms, the
  // methods, the work, the light projection; `log` keeps each option's ms.
  // Each with and without AtomicZP's eye-count pass (its intercept paid
  // once per frame) where some occluder admits it.
  struct Option {
    std::string_view name;
    gl::LightProjection projection;
    bool clipped = false, paper = false, eye_count = false;
  };
  std::vector<Option> options{{"no near-cap", policy.light_projection, false, false},
                              {"clipped-sides cap", gl::LightProjection::ClippedSides, true, false}};
  if (paper_ok) options.push_back({"paper cap", policy.light_projection, false, true});
  if (any_atomiczp) {
    static constexpr std::array<std::string_view, 3> with_eye_count{
        "no near-cap + eye count", "clipped-sides cap + eye count", "paper cap + eye count"};
    for (std::size_t k = 0, n = options.size(); k < n; ++k) {
      Option o = options[k];
      o.name = with_eye_count[k];
      o.eye_count = true;
      options.push_back(o);
    }
  }
  const double viewport_pixels = static_cast<double>(scene.camera.width) * scene.camera.height;
  const FrameWork shared = shared_frame_work(scene, !choice_only);
  struct Frame {
    double ms = kNaN;
    std::vector<CandidateMethod> choice;
    FrameWork work;
    gl::LightProjection projection = gl::LightProjection::Paper;
  };
  // `frames`, where given, receives every option's best frame.
  auto best_frame = [&](const std::vector<bool>& zpass_allowed, const FrameWork& extra,
                        std::vector<std::pair<std::string_view, double>>* log, std::vector<Frame>* frames) {
    Frame best;
    for (const Option& option : options) {
      Frame f;
      f.work = shared;
      f.work += extra;
      f.projection = option.projection;
      for (std::size_t i = 0; i < occluders.size(); ++i) {
        const Occluder& oc = occluders[i];
        CandidateMethod c = zfail;
        double ms = oc.zfail_ms;
        if (option.clipped && oc.clipped_ms < ms) {
          c = clipped;
          ms = oc.clipped_ms;
        }
        if (option.paper && oc.paper_ms < ms) {
          c = paper;
          ms = oc.paper_ms;
        }
        if (option.eye_count && oc.atomiczp_ok && oc.atomiczp_ms < ms) {
          c = atomiczp;
          ms = oc.atomiczp_ms;
        }
        if (zpass_allowed[i] && oc.zpass_ms <= ms) c = zpass;  // a tie: Z-pass, the simpler frame
        f.work += occluder_work(oc.in, c);
        f.choice.push_back(c);
      }
      if (f.work.eye_count.drawn) f.work.eye_count.fragments = viewport_pixels;  // the count's stencil write
      f.ms = profile.predict_ms(f.work);
      if (log) log->push_back({option.name, f.ms});
      if (frames) frames->push_back(f);
      if (!(f.ms >= best.ms)) best = std::move(f);
    }
    return best;
  };
  std::vector<bool> allowed(occluders.size(), false);
  for (std::size_t i = 0; i < occluders.size(); ++i) allowed[i] = occluders[i].zpass_ok;
  // The options' prices are kept where the decision is priced.
  std::vector<std::pair<std::string_view, double>>* const log = choice_only ? nullptr : &d.predicted_options;
  std::vector<Frame> option_frames;  // the chosen frame's options, for the margin
  std::vector<Frame>* const frames = margin ? &option_frames : nullptr;
  Frame chosen = best_frame(allowed, {}, log, frames);
  // The best frame with the exact test and Z-pass where it would allow it,
  // where it was weighed and not run (the test's saving fell short).
  double untested_alternative_ms = kNaN;
  if (any_untested) {
    // The test runs when the frame it could give at best, Z-pass for every
    // occluder it tests and the test paid, beats the frame without it.
    FrameWork test_work;
    std::vector<OccluderWorkInputs> inputs;
    inputs.reserve(occluders.size());
    for (const Occluder& oc : occluders) inputs.push_back(oc.in);
    test_work.exact_test = exact_test_work(inputs);
    std::vector<bool> optimistic = allowed;
    for (std::size_t i = 0; i < occluders.size(); ++i)
      if (untested[i]) optimistic[i] = true;
    const double test_ms = profile.cpu_ms(test_work);
    const double optimistic_ms = best_frame(optimistic, test_work, nullptr, nullptr).ms;
    if (optimistic_ms < chosen.ms) {
      const std::vector<bool> meets = occluders_meeting_light_pyramid(cs, light);
      for (std::size_t i = 0; i < occluders.size(); ++i) {
        if (!untested[i]) continue;
        Occluder& oc = occluders[i];
        oc.zpass_ok = allowed[i] = !meets[oc.object];
        oc.zpass_verdict = oc.zpass_ok ? ZPassVerdict::ExactEmpty : ZPassVerdict::ExactMeets;
        oc.exact_test_ms = test_ms;
      }
      d.predicted_options.clear();
      option_frames.clear();
      chosen = best_frame(allowed, test_work, log, frames);
    } else {
      untested_alternative_ms = optimistic_ms;
      for (std::size_t i = 0; i < occluders.size(); ++i)
        if (untested[i]) {
          occluders[i].zpass_verdict = ZPassVerdict::TestNotRun;
          occluders[i].exact_test_ms = test_ms;
        }
    }
  }
  if (margin && !unpriced && !forced && chosen.ms > 0) {
    // The kept-choice margin (kept_choices.hpp): the least rise of the
    // chosen frame's price that another choice weighed here brings (another
    // option's best frame where its methods differ, the frame with the exact
    // test where it was weighed and not run, or one occluder with another of
    // its candidates, by its marginal price), over the chosen frame's price,
    // both as this pricing weighs them (ChoiceOnly: without the coverage
    // every candidate draws alike).
    auto same = [](const CandidateMethod& a, const CandidateMethod& b) {
      return a.method == b.method && a.cap == b.cap;
    };
    double rise = std::numeric_limits<double>::infinity();
    for (const Frame& f : option_frames)
      if (!std::equal(f.choice.begin(), f.choice.end(), chosen.choice.begin(), chosen.choice.end(), same))
        rise = std::min(rise, f.ms - chosen.ms);
    if (!std::isnan(untested_alternative_ms)) rise = std::min(rise, untested_alternative_ms - chosen.ms);
    for (std::size_t i = 0; i < occluders.size(); ++i) {
      const Occluder& oc = occluders[i];
      const CandidateMethod& c = chosen.choice[i];
      const double chosen_ms = marginal_ms(profile, occluder_work(oc.in, c));
      // Each candidate the occluder has here, with its price.
      const std::array<std::tuple<CandidateMethod, bool, double>, 5> candidates{
          {{zfail, true, oc.zfail_ms},
           {clipped, true, oc.clipped_ms},
           {paper, paper_ok, oc.paper_ms},
           {atomiczp, oc.atomiczp_ok, oc.atomiczp_ms},
           {zpass, allowed[i], oc.zpass_ms}}};
      for (const auto& [candidate, admitted, ms] : candidates)
        if (admitted && !same(candidate, c)) rise = std::min(rise, ms - chosen_ms);
    }
    d.choice_margin_ms = rise;
    *margin = rise / chosen.ms;
  }
  // A choice drawn whatever the prices: the policy's unpriced frames, or a
  // kept choice priced as drawn.
  if (unpriced || forced) {
    Frame f;
    f.work = shared;
    for (const Occluder& oc : occluders) {
      CandidateMethod m = unpriced ? tier->method : zfail;
      if (forced && forced->object_methods[oc.object] != gl::ShadowMethod::ZFail)
        m = {forced->object_methods[oc.object], forced->settings.light_frustum.projection, far};
      f.work += occluder_work(oc.in, m);
      f.choice.push_back(m);
    }
    if (unpriced) {
      const CandidateMethod& m = tier->method;
      f.projection = m.method == gl::ShadowMethod::ZFail ? policy.light_projection : m.cap;
    } else {
      f.projection = forced->settings.light_frustum.projection;
    }
    f.ms = profile.predict_ms(f.work);
    chosen = std::move(f);
  }
  d.settings.light_frustum.projection = chosen.projection;
  if (choice_only) {
    for (std::size_t k = 0; k < occluders.size(); ++k) d.object_methods[occluders[k].object] = chosen.choice[k].method;
    return d;
  }
  const double best_total = chosen.ms;
  const std::vector<CandidateMethod>& best_choice = chosen.choice;
  d.predicted_work = chosen.work;
  d.predicted_ms = best_total;
  FramePrices prices;
  prices.paper = paper;
  prices.paper_ok = paper_ok;
  if (!paper_ok) prices.paper_why = std::move(paper_why);
  prices.atomiczp_priced = atomiczp_priced;
  if (unpriced) prices.unpriced = *tier;
  if (forced) prices.frames_since_priced = forced->frames_since_priced;
  prices.occluders.reserve(occluders.size());
  for (std::size_t k = 0; k < occluders.size(); ++k) {
    Occluder& oc = occluders[k];
    d.object_methods[oc.object] = best_choice[k].method;
    oc.chosen = best_choice[k];
    prices.occluders.push_back(std::move(static_cast<OccluderPrices&>(oc)));
  }
  d.prices = std::move(prices);
  return d;
}

std::string zpass_reason(const OccluderPrices& p) {
  switch (p.zpass_verdict) {
    case ZPassVerdict::NoExactTest:
      return "the policy has no exact Z-pass test";
    case ZPassVerdict::LightOnNearPlane:
      return "the light lies in the near plane";
    case ZPassVerdict::CertainlyMisses:
      return "certainly misses the light pyramid (empty near-cap)";
    case ZPassVerdict::ExactEmpty:
      return "exact: meets no point of the light pyramid (empty near-cap); the frame's test " +
             ms_text(p.exact_test_ms) + " ms";
    case ZPassVerdict::ExactMeets:
      return "meets the light pyramid (exact test); the frame's test " + ms_text(p.exact_test_ms) + " ms";
    case ZPassVerdict::TestNotRun:
      return "exact test not run (its predicted cost, " + ms_text(p.exact_test_ms) +
             " ms for the frame, above the saving)";
  }
  return "";
}

// The cost decision's reason for one occluder: the chosen candidate, then
// every candidate's predicted ms or why it is not one.
std::string cost_reason(const FramePrices& f, const OccluderPrices& p) {
  const CandidateMethod clipped{gl::ShadowMethod::ZPPlus, gl::LightProjection::ClippedSides};
  std::string why = "cost: ";
  why += p.chosen.name();
  if (f.unpriced) {
    why += " (unpriced: every occluder at most ";
    why += std::to_string(f.unpriced->max_occluder_triangles);
    why += " triangles)";
  }
  if (f.frames_since_priced > 0) {
    why += " (kept from the frame priced ";
    why += std::to_string(f.frames_since_priced);
    why += f.frames_since_priced == 1 ? " frame" : " frames";
    why += " before, where every other choice was priced ";
    why += std::to_string(static_cast<int>(std::lround(100 * KeptChoices::kMargin)));
    why += "% dearer or more)";
  }
  why += "; predicted ms: zfail ";
  append_ms(why, p.zfail_ms);
  why += ", ";
  why += clipped.name();
  why += " ";
  append_ms(why, p.clipped_ms);
  why += ", ";
  why += f.paper.name();
  why += " ";
  if (f.paper_ok) {
    append_ms(why, p.paper_ms);
  } else {
    why += "not a candidate (";
    why += f.paper_why;
    why += ")";
  }
  // A candidate that may not apply: its ms or "not a candidate", then why.
  auto append_candidate = [&why](const char* name, bool ok, double ms, const std::string& reason) {
    why += name;
    if (ok)
      append_ms(why, ms);
    else
      why += "not a candidate";
    why += " (";
    why += reason;
    why += ")";
  };
  append_candidate(", zpass ", p.zpass_ok, p.zpass_ms, zpass_reason(p));
  if (f.atomiczp_priced) append_candidate(", atomiczp ", p.atomiczp_ok, p.atomiczp_ms, p.atomiczp_why);
  return why;
}

}  // namespace

void price_decision(PolicyDecision& d, const SwitchPolicy& policy, const CameraSpaceScene& cs, std::size_t light,
                    const gl::EmulationSettings& base, FacingCache* facings) {
  if (!policy.device_profile) return;
  PolicyDecision full = decide_impl(policy, cs, light, base, facings, DecisionPricing::Full, nullptr,
                                    d.frames_since_priced > 0 ? &d : nullptr);
  d.predicted_ms = full.predicted_ms;
  d.predicted_work = full.predicted_work;
  d.predicted_options = std::move(full.predicted_options);
  d.prices = std::move(full.prices);
  // Where the choice's methods differ (a tie within rounding), the prices
  // name the methods drawn.
  if (d.prices)
    for (OccluderPrices& p : d.prices->occluders)
      if (p.object < d.object_methods.size() && p.chosen.method != d.object_methods[p.object]) {
        p.chosen.method = d.object_methods[p.object];
        p.chosen.cap = d.settings.light_frustum.projection;
      }
}

std::string PolicyDecision::depth_note() const {
  if (!depth_limited) return {};
  char note[512];
  std::snprintf(note, sizeof note,
                "depth-limited: one depth step spans %.3g of the scene's size at its farthest point (near plane "
                "%.3g): surfaces that close share a depth value, and no method is guaranteed right (Z-fail "
                "cracks in about a third of such sampled frames); reversed-Z with a float depth buffer (--depth "
                "float32 --depth-mapping reversed) or the tight near plane (--near-plane tight) fixes it",
                depth_step_over_size, near);
  return note;
}

std::string PolicyDecision::near_plane_note() const {
  if (std::isnan(moved_from_near)) return {};
  char note[512];
  std::snprintf(note, sizeof note,
                "drawn with the tight near plane (%.3g): with the scene's (%.3g) one depth step would span %.3g "
                "of the scene's size, and no method is right there",
                near, moved_from_near, moved_from_step_over_size);
  return note;
}

std::string PolicyDecision::reason(std::size_t object) const {
  if (prices)
    for (const OccluderPrices& p : prices->occluders)
      if (p.object == object) return cost_reason(*prices, p);
  return object < step_reasons.size() ? step_reasons[object] : std::string();
}

}  // namespace nearcap::analysis
