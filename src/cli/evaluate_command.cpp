// nearcap evaluate --policy FILE [--path P]... [--samples N --seed S] --out DIR:
// the policy judged against an oracle and the fixed rules on held-out data,
// each (configuration, light) judged by the exact reference and timed end to
// end on the real GL (analysis/policy_evaluation.hpp).
//
// A command of its own rather than a `render --bench` option: it needs the
// exact reference per (configuration, light) (render's lit frames have none),
// the sampler's configurations beside the paths, and a rule set that is not
// --method's list of methods.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/engine_policies.hpp"
#include "nearcap/analysis/frame_time_drift.hpp"
#include "nearcap/analysis/policy_evaluation.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/analysis/unpriced_frames_fit.hpp"
#include "nearcap/check.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/output_files.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "nearcap/render/egl_context.hpp"
#include "nearcap/render/lit_frame.hpp"
#include "nearcap/worker_threads.hpp"
#include "output_script.hpp"
#include "progress_line.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

struct EvaluateOptions {
  std::string policy = shipped_data_dir() + "/policy.json";
  std::vector<std::string> paths;
  std::uint64_t samples = 0;
  SamplerOptions sampler;
  int width = 0, height = 0;  // 0: the sampler's 48 x 36, a path's own size
  int first_frame = 0, last_frame = -1;
  int repeats = 4;  // timing rounds per (configuration, light)
  std::string out;
  // Training data instead: the policy evaluated without its unpriced frames,
  // then written here with the ones fitted on these rows.
  std::string fit_unpriced;
  // Every frame of the policy priced: no choice kept from the frame before.
  bool price_every_frame = false;
  double max_memory_gb = 0;  // 0: three quarters of the machine's
};

// A configuration's memory beyond the fixed part, per pixel of its frame:
// the exact reference, its crack distances, every candidate's emulated and GL
// frames (measured: 153 bytes per pixel between `evaluate --samples 3` at
// 1024x1024 and 2048x2048 and a fixed part of about 100 MB,
// docs/findings/exact-speed.md, "Memory"): 240 covers both measured peaks
// beside the estimate's 64 MB.
constexpr double kEvaluateBytesPerPixel = 240;
// What each configuration leaves behind to the end of the run: its scene,
// its rows and the heap around them (measured: about 32 KB of peak resident
// memory per configuration between `evaluate --samples 40` and 320 at
// 48x36, docs/findings/exact-speed.md, "Memory").
constexpr double kEvaluateBytesPerConfiguration = 64e3;

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A held-out configuration: a path's frame or a sampler's index.
struct Configuration {
  std::string set, id;
  int frame = -1;
  std::string scene_json;
};

// One rule's frame of a (configuration, light): the methods per object (or
// one method for every occluder), the settings it is drawn with, and the
// CPU time of the decision that chose them.
struct RuleFrame {
  std::string rule;
  std::optional<gl::ShadowMethod> method;
  std::vector<gl::ShadowMethod> object_methods;
  gl::EmulationSettings settings;
  double decision_ms = 0;
  std::optional<double> profile_ms, predicted_ms;  // the policy's, with a device profile (EvaluationRow)
  std::optional<double> decision_warm_ms;          // the policy's: the same decision again at once (EvaluationRow)
  int frames_since_priced = 0;                     // the policy's: a kept choice (EvaluationRow)
  bool applies = true;
  gl::ShadowFrame frame;
  std::string refused;
};

// A decided frame's methods, as the candidates are named: each occluder's
// method once, in scene order, "+"-joined ("zpass+zpplus-clipped").
std::string methods_chosen(const Scene& scene, const RuleFrame& r) {
  std::vector<std::string> names;
  for (std::size_t o = 0; o < scene.objects.size() && o < r.object_methods.size(); ++o) {
    if (!scene.objects[o].occluder) continue;
    std::string name(gl::to_string(r.object_methods[o]));
    if (r.object_methods[o] == gl::ShadowMethod::ZPPlus)
      name =
          r.settings.light_frustum.projection == gl::LightProjection::ClippedSides ? "zpplus-clipped" : "zpplus-paper";
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : "+") + n;
  return out;
}

RuleFrame rule_frame(std::string rule, std::optional<gl::ShadowMethod> method,
                     std::vector<gl::ShadowMethod> object_methods, const gl::EmulationSettings& settings,
                     double decision_ms = 0) {
  RuleFrame r;
  r.rule = std::move(rule);
  r.method = method;
  r.object_methods = std::move(object_methods);
  r.settings = settings;
  r.decision_ms = decision_ms;
  return r;
}

// The rules' own switch policies: exact Z-pass, then Z-fail or clipped-sides
// ZP+ with no crack model (the probability 1/(1+e^30) under threshold 1).
analysis::SwitchPolicy exact_zpass_rule(gl::ShadowMethod capped, gl::LightProjection projection) {
  analysis::SwitchPolicy p;
  p.capped_method = capped;
  p.fallback_method = gl::ShadowMethod::ZFail;
  p.switch_clamp = gl::SwitchClamp::DepthClampFar;
  p.zpass_far = gl::ZPassFar::Infinite;
  p.light_projection = projection;
  p.exact_zpass = true;
  p.crack_model.bias = -30;
  p.crack_model.threshold = 1;
  return p;
}

// The median (CPU, end-to-end) of some rounds, by end-to-end time (the
// upper median of an even count).
std::pair<double, double> median(std::vector<std::pair<double, double>> v) {
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  return v[v.size() / 2];
}

// A rule's times from its rounds: the counted ones (the odd rounds' median)
// into cpu_ms and end_to_end_ms, and the end-to-end median of the even
// rounds as choice_ms (analysis::EvaluationRow); with one round, that round
// counted and no choice_ms.
void set_times(analysis::EvaluationRow& row, const std::vector<std::pair<double, double>>& rounds) {
  if (rounds.size() == 1) {
    std::tie(row.cpu_ms, row.end_to_end_ms) = rounds[0];
    return;
  }
  std::vector<std::pair<double, double>> even, odd;
  for (std::size_t k = 0; k < rounds.size(); ++k) (k % 2 == 0 ? even : odd).push_back(rounds[k]);
  std::tie(row.cpu_ms, row.end_to_end_ms) = median(odd);
  row.choice_ms = median(even).second;
}

gl::ShadowFrame draw(const Scene& scene, std::size_t light, const RuleFrame& r) {
  gl::ShadowFrameBatch batch(scene, light, r.settings);
  return r.method ? batch.render(*r.method) : batch.render(r.object_methods);
}

class Evaluation {
 public:
  Evaluation(const analysis::SwitchPolicy& policy, render::LitFrameRenderer& renderer, int repeats, bool keep_choices)
      : policy_(policy), renderer_(renderer), repeats_(repeats), keep_choices_(keep_choices) {
    base_.zpass_far = gl::ZPassFar::Infinite;
    base_.switch_clamp = gl::SwitchClamp::DepthClampFar;
    base_.record_draws = true;
  }

  // Every rule of every light of `c`, appended to `rows`.
  void run(const Configuration& c, const Scene& scene, std::vector<analysis::EvaluationRow>& rows) {
    if (c.set != drift_set_) {  // each set's predictions from its own frames alone, no choice kept across sets
      drift_ = analysis::FrameTimeDrift(c.frame >= 0 ? analysis::FrameTimeDrift::kPathWindow
                                                     : analysis::FrameTimeDrift::kWindow);
      kept_ = {};
      drift_set_ = c.set;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const CameraSpaceScene cs(scene);
    camera_space_ms_ = ms_since(t0);
    for (std::size_t light = 0; light < scene.lights.size(); ++light) run_light(c, scene, cs, light, rows);
  }

 private:
  std::vector<RuleFrame> rule_frames(const Scene& scene, const CameraSpaceScene& cs, std::size_t light) {
    std::vector<RuleFrame> out;
    auto with_projection = [&](gl::LightProjection p) {
      gl::EmulationSettings s = base_;
      s.light_frustum.projection = p;
      return s;
    };
    auto decided = [&](const std::string& name, const analysis::SwitchPolicy& p, analysis::KeptChoices* kept) {
      // The choice timed (decide_ms); its prices, the predicted frame time
      // among them, computed after.
      analysis::PolicyDecision d =
          analysis::decide(p, cs, light, base_, &facings_, analysis::DecisionPricing::ChoiceOnly, kept);
      analysis::price_decision(d, p, cs, light, base_, &facings_);
      d.settings.record_draws = true;
      RuleFrame r = rule_frame(name, std::nullopt, d.object_methods, d.settings, camera_space_ms_ + d.decide_ms);
      r.frames_since_priced = d.frames_since_priced;
      if (!std::isnan(d.predicted_ms)) {
        r.profile_ms = d.predicted_ms;
        r.predicted_ms = d.predicted_ms * drift_.scale() + r.decision_ms;
      }
      return r;
    };
    const RuleFrame exact_zfail =
        decided("exact-zpass+zfail", exact_zpass_rule(gl::ShadowMethod::ZFail, gl::LightProjection::Paper), nullptr);
    bool zpass_exact = true;  // the exact test finds every occluder's near-cap empty
    for (std::size_t o = 0; o < scene.objects.size(); ++o)
      if (scene.objects[o].occluder && exact_zfail.object_methods[o] != gl::ShadowMethod::ZPass) zpass_exact = false;
    RuleFrame zpass = rule_frame("zpass", gl::ShadowMethod::ZPass, {}, base_, exact_zfail.decision_ms);
    zpass.applies = zpass_exact;
    out.push_back(zpass);
    out.push_back(rule_frame("zfail", gl::ShadowMethod::ZFail, {}, base_));
    out.push_back(
        rule_frame("zpplus-paper", gl::ShadowMethod::ZPPlus, {}, with_projection(gl::LightProjection::Paper)));
    out.push_back(
        rule_frame("zpplus-clipped", gl::ShadowMethod::ZPPlus, {}, with_projection(gl::LightProjection::ClippedSides)));
    out.push_back(rule_frame("zpplus-corrected", gl::ShadowMethod::ZPPlusCorrected, {},
                             with_projection(gl::LightProjection::Paper)));
    out.push_back(rule_frame("atomiczp", gl::ShadowMethod::AtomicZP, {}, base_));
    out.push_back(exact_zfail);
    out.push_back(decided("exact-zpass+clipped",
                          exact_zpass_rule(gl::ShadowMethod::ZPPlus, gl::LightProjection::ClippedSides), nullptr));
    for (analysis::EnginePolicy p : {analysis::EnginePolicy::Doom3, analysis::EnginePolicy::Doom3BFG}) {
      const auto t0 = std::chrono::steady_clock::now();
      std::vector<gl::ShadowMethod> methods =
          analysis::object_methods(scene, analysis::engine_choices(p, scene, light));
      out.push_back(
          rule_frame(std::string(analysis::to_string(p)), std::nullopt, std::move(methods), base_, ms_since(t0)));
    }
    // The kept choices as this decision finds them: each repeat below
    // starts from them, and so makes the same decision the same way.
    const analysis::KeptChoices kept_before = kept_;
    RuleFrame policy = decided("policy", policy_, keep_choices_ ? &kept_ : nullptr);
    // The same decision again at once, warm: what a renderer's frame loop
    // pays.  Three calls, their median: one call of a few microseconds is
    // at the mercy of a preemption.  Each must decide the same.
    std::array<double, 3> warm{};
    for (double& ms : warm) {
      analysis::KeptChoices kept_again = kept_before;
      const analysis::PolicyDecision again =
          analysis::decide(policy_, cs, light, base_, &facings_, analysis::DecisionPricing::ChoiceOnly,
                           keep_choices_ ? &kept_again : nullptr);
      NEARCAP_CHECK(again.object_methods == policy.object_methods);
      ms = camera_space_ms_ + again.decide_ms;
    }
    std::sort(warm.begin(), warm.end());
    policy.decision_warm_ms = warm[1];
    out.push_back(std::move(policy));
    return out;
  }

  // The GL's lit frame of one light's shadow frame: end-to-end and CPU time.
  std::pair<double, double> time_frame(const Scene& scene, const RuleFrame& r) {
    render::LitFrameOptions options;
    const render::LitFrame lit = renderer_.render(scene, {r.frame}, r.settings.depth, options);
    const double cpu = r.decision_ms + r.frame.cpu.total();
    return {cpu + lit.upload_ms, cpu + lit.ms};
  }

  void run_light(const Configuration& c, const Scene& scene, const CameraSpaceScene& cs, std::size_t light,
                 std::vector<analysis::EvaluationRow>& rows) {
    const PixelReferenceTracer tracer(cs, light);
    const PixelReference ref = compute_pixel_reference(tracer);
    CrackDistances distances(tracer, ref);
    std::vector<RuleFrame> frames = rule_frames(scene, cs, light);
    const std::size_t occluder_triangles = analysis::largest_occluder_triangles(scene);
    std::vector<analysis::EvaluationRow> out;
    for (RuleFrame& r : frames) {
      analysis::EvaluationRow row;
      row.set = c.set;
      row.configuration = c.id;
      row.frame = c.frame;
      row.light = light;
      row.rule = r.rule;
      row.applies = r.applies;
      row.decision_ms = r.decision_ms;
      if (r.rule == "policy") row.chosen = methods_chosen(scene, r);
      row.profile_ms = r.profile_ms;
      row.predicted_ms = r.predicted_ms;
      row.decision_warm_ms = r.decision_warm_ms;
      row.occluder_triangles = occluder_triangles;
      row.frames_since_priced = r.frames_since_priced;
      try {
        r.frame = draw(scene, light, r);
        CrackReport report = judge_frame(r.frame, ref);
        distances.measure(report);
        row.wrong = report.wrong;
        row.cracks = *report.cracks;
      } catch (const Error& e) {
        if (e.kind() != ErrorKind::Range) throw;
        r.refused = e.what();
        row.refused = true;
      }
      out.push_back(row);
    }
    // The GL: a warm-up draw, then `repeats` rounds of every rule's frame
    // interleaved, then Z-fail's again from a batch of its own, as many
    // times (the noise floor); each timed by its rounds (set_times).  The
    // reference's and the emulation's worker threads are released first
    // (worker_threads.hpp): none spins beside a timed frame.
    release_worker_threads();
    const std::size_t zfail = 1;  // its index in rule_frames()
    if (frames[zfail].refused.empty()) {
      try {
        time_frame(scene, frames[zfail]);
      } catch (const Error& e) {
        if (e.kind() != ErrorKind::Gl) throw;
      }
    }
    std::vector<std::vector<std::pair<double, double>>> times(frames.size());
    for (int round = 0; round < repeats_; ++round)
      for (std::size_t k = 0; k < frames.size(); ++k) {
        if (!frames[k].refused.empty()) continue;
        try {
          times[k].push_back(time_frame(scene, frames[k]));
        } catch (const Error& e) {
          if (e.kind() != ErrorKind::Gl) throw;
          frames[k].refused = e.what();
          out[k].refused = true;
        }
      }
    for (std::size_t k = 0; k < frames.size(); ++k) {
      if (!frames[k].refused.empty()) continue;
      set_times(out[k], times[k]);
      // The policy's frame as measured, for the next frames' predictions.
      if (out[k].profile_ms) drift_.observe(*out[k].profile_ms, out[k].end_to_end_ms - out[k].decision_ms);
    }
    if (frames[zfail].refused.empty()) {
      RuleFrame again = frames[zfail];
      again.frame = draw(scene, light, again);
      release_worker_threads();
      std::vector<std::pair<double, double>> again_times;
      for (int round = 0; round < repeats_; ++round) again_times.push_back(time_frame(scene, again));
      analysis::EvaluationRow row = out[zfail];
      row.rule = std::string(analysis::kNoiseRule);
      set_times(row, again_times);
      out.push_back(row);
    }
    // The fixed rules that are a candidate's frame share its measurement.
    for (const auto& [rule, candidate] : {std::pair<std::string, std::string>{"always-zfail", "zfail"},
                                          std::pair<std::string, std::string>{"always-clipped", "zpplus-clipped"}}) {
      const auto it = std::find_if(out.begin(), out.end(),
                                   [&, c = candidate](const analysis::EvaluationRow& r) { return r.rule == c; });
      analysis::EvaluationRow alias = *it;
      alias.rule = rule;
      out.push_back(std::move(alias));
    }
    rows.insert(rows.end(), out.begin(), out.end());
  }

  const analysis::SwitchPolicy& policy_;
  render::LitFrameRenderer& renderer_;
  int repeats_;
  gl::EmulationSettings base_;
  // The configuration's exact camera-space scene, which every decision
  // reads: its construction is counted in each decision, as a renderer
  // builds it for each frame and light (`nearcap render`'s decision_ms).
  double camera_space_ms_ = 0;
  // The occluders' facings the decisions keep from one configuration to the
  // next, as `nearcap render` keeps them along a path (the decisions are the
  // same without).
  analysis::FacingCache facings_;
  // The policy's choices kept from one frame of a path to the next, as
  // `nearcap render` keeps them (kept_choices.hpp); unused with
  // --price-every-frame.
  bool keep_choices_;
  analysis::KeptChoices kept_;
  // The policy's measured over priced frame time, per set (predicted_ms).
  analysis::FrameTimeDrift drift_;
  std::string drift_set_;
};

void run(const EvaluateOptions& o) {
  if (o.out.empty())
    throw Error(ErrorKind::Usage, "nearcap evaluate writes evaluation.csv and table.md into --out DIR");
  refuse_non_directory(o.out, "--out");
  if (o.paths.empty() && o.samples == 0)
    throw Error(ErrorKind::Usage, "nearcap evaluate needs held-out data: --path P (repeatable) and/or --samples N");
  check_camera_path_names(o.paths);
  refuse_unread_sampler_options(o.sampler, o.samples);
  if (o.last_frame >= 0 && o.last_frame < o.first_frame)
    throw Error(ErrorKind::Usage, "--last-frame " + std::to_string(o.last_frame) + " is before --first-frame " +
                                      std::to_string(o.first_frame));
  analysis::SwitchPolicy policy = analysis::load_policy(o.policy);
  if (!o.fit_unpriced.empty()) {
    if (!policy.device_profile)
      throw Error(ErrorKind::Usage, "--fit-unpriced: " + o.policy + " has no device profile (nothing is priced)");
    refuse_directory(o.fit_unpriced, "--fit-unpriced");
    std::error_code in_ec, out_ec, same_ec;
    // Compared without a trailing separator: "DIR/" names what "DIR" names.
    const auto canonical = [](const std::string& p, std::error_code& ec) {
      std::filesystem::path c = std::filesystem::weakly_canonical(p, ec);
      while (!c.has_filename() && c.has_relative_path()) c = c.parent_path();
      return c;
    };
    const std::filesystem::path in = canonical(o.policy, in_ec);
    const std::filesystem::path outp = canonical(o.fit_unpriced, out_ec);
    if ((!in_ec && !out_ec && in == outp) ||
        (std::filesystem::equivalent(o.policy, o.fit_unpriced, same_ec) && !same_ec))
      throw Error(ErrorKind::Usage, "--fit-unpriced would replace the policy it evaluates (" + o.policy + ")");
    {
      std::error_code ec;
      if (!out_ec && canonical(o.out, ec) == outp && !ec)
        throw Error(ErrorKind::Usage, "--fit-unpriced '" + o.fit_unpriced + "' is the directory --out writes");
    }
    for (const char* name : {"evaluation.csv", "table.md"}) {
      std::error_code ec;
      const std::filesystem::path written = std::filesystem::weakly_canonical(std::filesystem::path(o.out) / name, ec);
      if (!out_ec && !ec && written == outp)
        throw Error(ErrorKind::Usage, "--fit-unpriced '" + o.fit_unpriced + "' is the " + name + " --out writes");
    }
    policy.unpriced_frames.clear();  // every frame priced: the fit compares against that
  }
  // Everything read and checked before the GL starts.
  std::vector<analysis::CameraPath> paths;
  for (const std::string& file : o.paths) {
    analysis::CameraPath p = load_camera_path_file(file);
    if (o.width > 0) p.width = o.width;
    if (o.height > 0) p.height = o.height;
    if (o.first_frame >= p.frames)
      throw Error(ErrorKind::Usage, "--first-frame " + std::to_string(o.first_frame) + ": " + file + " has " +
                                        std::to_string(p.frames) + " frames");
    if (o.last_frame >= p.frames)
      throw Error(ErrorKind::Usage, "--last-frame " + std::to_string(o.last_frame) + ": " + file + " has " +
                                        std::to_string(p.frames) + " frames (the last is " +
                                        std::to_string(p.frames - 1) + ")");
    paths.push_back(std::move(p));
  }
  // No output replaces what the command reads.
  std::vector<CommandInput> inputs{{o.policy, "policy file"}};
  if (o.samples > 0)
    for (CommandInput& in : sampler_inputs(sampler_spec(o.sampler))) inputs.push_back(std::move(in));
  for (const analysis::CameraPath& p : paths)
    for (CommandInput& in : camera_path_inputs(p)) inputs.push_back(std::move(in));
  std::vector<std::string> outputs;
  for (const char* name : {"evaluation.csv", "table.md"}) {
    outputs.push_back((std::filesystem::path(o.out) / name).string());
    refuse_replacing_inputs(outputs.back(), inputs);
  }
  if (!o.fit_unpriced.empty()) {
    refuse_replacing_inputs(o.fit_unpriced, inputs, "--fit-unpriced");
    outputs.push_back(o.fit_unpriced);
  }
  io::check_output_files(outputs);
  analysis::SamplerSpec spec = sampler_spec(o.sampler);
  if (o.width > 0) spec.width = o.width;
  if (o.height > 0) spec.height = o.height;
  if (o.samples > 0) check_sampler_meshes(spec);
  // The plot's Python, before the measuring that precedes it.
  const std::string plot_script = shipped_scripts_dir() + "/report/policy_oracle.py";
  const std::string plot_what = "the policy-against-oracle plot's script";
  if (!paths.empty()) check_output_script(plot_script, plot_what);
  // The largest frame's memory, and what every configuration keeps to the
  // end of the run, checked before any is listed or drawn.
  auto last_frame_of = [&](const analysis::CameraPath& p) { return o.last_frame >= 0 ? o.last_frame : p.frames - 1; };
  std::size_t count = static_cast<std::size_t>(o.samples);
  int width = 0, height = 0;
  auto keep_largest = [&](int w, int h) {
    if (static_cast<double>(w) * h > static_cast<double>(width) * height) width = w, height = h;
  };
  for (const analysis::CameraPath& p : paths) {
    check_memory_estimate(p.source, p.width, p.height, "evaluate", kEvaluateBytesPerPixel, o.max_memory_gb,
                          "lower --width/--height");
    count += static_cast<std::size_t>(last_frame_of(p) - o.first_frame + 1);
    keep_largest(p.width, p.height);
  }
  if (o.samples > 0) {
    check_memory_estimate("the sampler", spec.width, spec.height, "evaluate", kEvaluateBytesPerPixel, o.max_memory_gb,
                          "lower --width/--height");
    keep_largest(spec.width, spec.height);
  }
  check_memory_estimate("the configurations", width, height, "evaluate", kEvaluateBytesPerPixel, o.max_memory_gb,
                        "lower --samples, the paths' frames (--first-frame/--last-frame) or --width/--height", count,
                        kEvaluateBytesPerConfiguration);
  const analysis::HardCaseSampler sampler(spec);
  std::vector<Configuration> configurations;
  for (const analysis::CameraPath& p : paths) {
    const std::string name = std::filesystem::path(p.source).stem().string();
    for (int f = o.first_frame; f <= last_frame_of(p); ++f)
      configurations.push_back({name, "path:" + name + ":" + std::to_string(f), f, analysis::path_frame_json(p, f)});
  }
  const std::string seed_set = "seed-" + std::to_string(o.sampler.seed);
  for (std::uint64_t i = 0; i < o.samples; ++i) {
    const analysis::HardCase h = sampler.sample(i);
    configurations.push_back(
        {seed_set, "sample:" + std::to_string(h.seed) + ":" + std::to_string(h.index), -1, h.scene_json});
  }

  const render::EglContext context;
  render::LitFrameRenderer renderer;
  Evaluation evaluation(policy, renderer, o.repeats, !o.price_every_frame && o.fit_unpriced.empty());
  MeshCache meshes;
  std::vector<analysis::EvaluationRow> rows;
  RejectedConfigurations rejected;
  std::set<std::string> drawn_sets;
  ProgressLine progress(configurations.size());
  for (std::size_t k = 0; k < configurations.size(); ++k) {
    const Configuration& c = configurations[k];
    std::optional<Scene> scene;
    try {
      scene = parse_scene(c.scene_json, c.id, ".", &meshes);
      drawn_sets.insert(c.set);
    } catch (const Error& e) {
      rejected.add(c.id, e);  // a sampler's light inside an occluder, say: not a configuration
    }
    if (scene) evaluation.run(c, *scene, rows);
    progress.step(k + 1, "evaluate: " + std::to_string(k + 1) + "/" + std::to_string(configurations.size()) +
                             " configurations (" + c.id + ")");
  }
  progress.end();
  rejected.refuse_all_rejected(configurations.size());
  const analysis::EvaluationTable table = analysis::evaluate_rows(rows);

  const std::filesystem::path dir(o.out);
  std::string csv = analysis::evaluation_csv_header();
  for (const analysis::EvaluationRow& r : rows) csv += analysis::evaluation_csv_line(r);
  for (const analysis::EvaluationRow& r : table.oracle_rows) csv += analysis::evaluation_csv_line(r);
  std::string heading = "# " + std::filesystem::path(o.policy).filename().string() + " against the oracle\n\n";
  heading += "On " + context.renderer() + " (" + context.version() + "), policy " + o.policy;
  heading += !o.fit_unpriced.empty() ? " with every frame priced (--fit-unpriced)."
             : o.price_every_frame   ? " with every frame priced (--price-every-frame)."
                                     : ".";
  if (rejected.count() > 0) heading += " " + rejected.sentence() + ".";
  heading += "\n\n";
  const std::string markdown = heading + analysis::evaluation_table_markdown(table);
  io::StagedOutputFiles files;
  files.add({(dir / "evaluation.csv").string(), csv});
  files.add({(dir / "table.md").string(), markdown});
  std::string fit_line;
  if (!o.fit_unpriced.empty()) {
    const analysis::UnpricedFramesFit fit = analysis::fit_unpriced_frames(rows, policy.zpass_far);
    analysis::SwitchPolicy fitted = policy;
    fitted.unpriced_frames = fit.unpriced;
    char line[512];
    std::string tiers;  // "at most 12 triangles drawn with zfail, at most 6400 with ..."
    for (std::size_t k = 0; k < fit.unpriced.size(); ++k)
      tiers += (k == 0 ? "at most " : ", at most ") + std::to_string(fit.unpriced[k].max_occluder_triangles) +
               (k == 0 ? " triangles drawn with " : " with ") + fit.unpriced[k].method.name();
    if (!fit.unpriced.empty()) {
      std::snprintf(line, sizeof line, " (%zu of %zu frames; %.2f ms in all against %.2f ms with every frame priced); ",
                    fit.unpriced_frames, fit.frames, fit.fitted_total_ms, fit.priced_total_ms);
      fit_line = "evaluate: unpriced frames: every occluder " + tiers + line + o.fit_unpriced;
    } else {
      std::snprintf(line, sizeof line, "evaluate: unpriced frames: none (pricing every frame was cheapest, %.2f ms); ",
                    fit.priced_total_ms);
      fit_line = line + o.fit_unpriced;
    }
    nlohmann::json provenance = nlohmann::json::parse(fitted.provenance_json);
    provenance["unpriced_frames"] = {{"samples", o.samples},
                                     {"seed", o.sampler.seed},
                                     {"paths", o.paths},
                                     {"width", o.width},
                                     {"height", o.height},
                                     {"repeats", o.repeats},
                                     {"frames", fit.frames},
                                     {"unpriced_frames", fit.unpriced_frames},
                                     {"priced_total_ms", fit.priced_total_ms},
                                     {"fitted_total_ms", fit.fitted_total_ms}};
    fitted.provenance_json = json_text(provenance);
    files.add({o.fit_unpriced, analysis::policy_to_json(fitted)});
  }
  files.commit();
  std::cout << markdown;
  if (!fit_line.empty()) std::printf("%s\n", fit_line.c_str());
  std::printf("evaluate: %s/evaluation.csv, %s/table.md\n", o.out.c_str(), o.out.c_str());
  for (const analysis::CameraPath& p : paths) {
    const std::string name = std::filesystem::path(p.source).stem().string();
    if (!drawn_sets.count(name)) {
      std::printf("evaluate: no plot of %s: none of its frames loads\n", name.c_str());
      continue;
    }
    const std::string png = (dir / ("oracle-" + name + ".png")).string();
    run_output_script(plot_script,
                      {(dir / "evaluation.csv").string(), name, png, name + " (" + context.renderer() + ")"}, plot_what,
                      png);
    std::printf("evaluate: %s (the policy's frame time against the oracle's, per frame)\n", png.c_str());
  }
}

}  // namespace

void register_evaluate(CLI::App& app) {
  auto [cmd, o] = add_subcommand<EvaluateOptions>(
      app, "evaluate",
      "judge a switch policy against the oracle (the fastest candidate as right as Z-fail, in hindsight, per "
      "configuration and light) and the fixed rules (always Z-fail, always clipped-sides ZP+, exact Z-pass + Z-fail, "
      "exact Z-pass + clipped-sides ZP+, Doom 3, BFG) on held-out data: each judged by the exact reference, each "
      "timed end to end (CPU work and the GL's passes to glFinish) on the real GL, interleaved per frame after a "
      "warm-up, Z-fail timed twice for the noise floor; DIR/evaluation.csv, DIR/table.md (also on stdout) and per "
      "path DIR/oracle-NAME.png",
      run);
  cmd.add_option("--policy", o.policy, "the switch policy under test (nearcap tune writes one)")->capture_default_str();
  cmd.add_option("--fit-unpriced", o.fit_unpriced,
                 "training data instead of held-out: evaluate the policy with every frame priced, fit the frames its "
                 "decision should not price (tiers of the largest occluder's triangles up to a threshold, each with "
                 "one method) and write the policy with them to FILE");
  cmd.add_flag("--price-every-frame", o.price_every_frame,
               "price the policy's choice on every frame of a path (by default a choice that undercut every other "
               "by a wide margin is kept for the next few frames, as `nearcap render` keeps it)");
  cmd.add_option("--path", o.paths, "a held-out camera path (data/paths/), repeatable: one set each");
  add_samples_option(cmd, o.samples, "held-out configurations of the hard-case sampler (the set seed-S)", 0,
                     kMaxSweepSamples);
  add_sampler_options(cmd, o.sampler, false);
  add_viewport_options(cmd, o.width, o.height, " (default: 48 sampled, a path's own)",
                       " (default: 36 sampled, a path's own)");
  cmd.add_option("--first-frame", o.first_frame, "the first frame of each path")
      ->transform(integer_in(0, 1000000))
      ->capture_default_str();
  cmd.add_option("--last-frame", o.last_frame,
                 "the last frame of each path (default: its last; one past a path's end is refused)")
      ->transform(integer_in(0, 1000000));
  cmd.add_option("--repeats", o.repeats,
                 "timing rounds per configuration and light: every rule's frame drawn once per round, "
                 "interleaved; the oracle chooses by the median of the even rounds and every time counted is the "
                 "median of the odd rounds (one round: that round, for both)")
      ->transform(integer_in(1, 1000))
      ->capture_default_str();
  cmd.add_option("--out", o.out, "output directory (created if missing)");
  add_max_memory_option(cmd, o.max_memory_gb);
}

}  // namespace nearcap::cli
