// nearcap calibrate: what each pass kind and CPU task costs on the current
// GL (docs/calibration.md).  A calibration set (hard-case samples and
// camera paths) is emulated with every calibrated method, its recorded
// draws drawn by the real GL pass kind by pass kind (render/lit_frame.hpp,
// LitFrameOptions::pass_kind_times), each with the triangles and fragments
// it drew (render/pass_kinds.hpp: the emulation's own counters per draw),
// and each occluder's CPU work timed with its size.  The observations go to
// a CSV (analysis/calibration_file.hpp); with --write-policy a device
// profile is fitted on them (analysis/device_profile.hpp) and written into
// a copy of the policy.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "nearcap/analysis/calibration_file.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/device_profile_fit.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/analysis/work_estimate.hpp"
#include "nearcap/check.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/light_pyramid.hpp"
#include "nearcap/gl/engine_classification.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/gl/shadow_volume_geometry.hpp"
#include "nearcap/io/output_files.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/render/egl_context.hpp"
#include "nearcap/render/lit_frame.hpp"
#include "nearcap/render/pass_kinds.hpp"
#include "nearcap/worker_threads.hpp"
#include "progress_line.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

struct CalibrateOptions {
  std::uint64_t samples = 40;
  SamplerOptions sampler;
  std::vector<std::string> paths;
  int width = 160, height = 120;
  std::string out;
  std::string policy = shipped_data_dir() + "/policy.json";
  bool policy_given = false;  // --policy on the command line
  std::string write_policy;
  bool no_atomiczp = false;  // the profile without its eye-count row (--no-atomiczp)
  double max_memory_gb = 0;  // 0: three quarters of the machine's
};

// A configuration's memory beyond the fixed part, per pixel of its frame:
// every method's emulated and GL frames, one configuration at a time
// (measured: 173 bytes per pixel between `calibrate --samples 6` at
// 1024x1024 and 2048x2048 and a fixed part of about 115 MB,
// docs/findings/exact-speed.md, "Memory"): 240 covers both measured peaks
// beside the estimate's 64 MB.
constexpr double kCalibrateBytesPerPixel = 240;
// What each configuration leaves behind to the end of the run: its
// observations (about 40 rows) and the heap around their names (measured:
// about 19 KB of peak resident memory per configuration between
// `calibrate --samples 40` and 1280 at its 160x120, docs/findings/exact-speed.md, "Memory").
constexpr double kCalibrateBytesPerConfiguration = 48e3;

// The methods calibrated: every candidate of the switch policy's decision.
// ZP+ with the clipped-sides cap is ZP+ drawn with LightProjection::
// ClippedSides.
struct CalibratedMethod {
  const char* name;
  gl::ShadowMethod method;
  bool clipped_sides;
};
constexpr CalibratedMethod kMethods[] = {
    {"zpass", gl::ShadowMethod::ZPass, false},
    {"zfail", gl::ShadowMethod::ZFail, false},
    {"zpplus", gl::ShadowMethod::ZPPlus, false},
    {"zpplus-clipped-sides", gl::ShadowMethod::ZPPlus, true},
    {"zpplus-corrected", gl::ShadowMethod::ZPPlusCorrected, false},
    {"atomiczp", gl::ShadowMethod::AtomicZP, false},
};
constexpr std::size_t kMethodCount = sizeof kMethods / sizeof kMethods[0];

// One configuration of the calibration set: a camera path's frame or a
// sampler's configuration, as scene text.
struct Configuration {
  std::string id;  // "path:near_plane_sweep:42", "sample:1:7"
  std::string scene_json;
};

// The configurations in order (each path's frames, then the samples), made
// on demand.
class CalibrationSet {
 public:
  explicit CalibrationSet(const CalibrateOptions& o) : sampler_(spec(o)) {
    for (const std::string& file : o.paths) {
      analysis::CameraPath p = analysis::load_camera_path(file);
      p.width = o.width;
      p.height = o.height;
      count_ += static_cast<std::size_t>(p.frames);
      paths_.push_back(std::move(p));
    }
    count_ += static_cast<std::size_t>(o.samples);
  }
  std::size_t count() const { return count_; }
  const std::vector<analysis::CameraPath>& paths() const { return paths_; }
  Configuration at(std::size_t k) const {
    for (const analysis::CameraPath& p : paths_) {
      if (k < static_cast<std::size_t>(p.frames)) {
        const int f = static_cast<int>(k);
        return {"path:" + std::filesystem::path(p.source).stem().string() + ":" + std::to_string(f),
                analysis::path_frame_json(p, f)};
      }
      k -= static_cast<std::size_t>(p.frames);
    }
    const analysis::HardCase h = sampler_.sample(k);
    return {"sample:" + std::to_string(h.seed) + ":" + std::to_string(h.index), h.scene_json};
  }

 private:
  static analysis::SamplerSpec spec(const CalibrateOptions& o) {
    analysis::SamplerSpec s = sampler_spec(o.sampler);
    s.width = o.width;
    s.height = o.height;
    return s;
  }
  std::vector<analysis::CameraPath> paths_;
  analysis::HardCaseSampler sampler_;
  std::size_t count_ = 0;
};

double ms_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// The work of one method's frames, by pass kind: per light frame the
// stencil kinds' triangles and fragments, and the depth pre-pass's (the lit
// passes draw the same).
struct MethodWork {
  std::vector<std::array<gl::DrawCounters, gl::kPassKindCount>> per_light;
  gl::DrawCounters depth;
};

MethodWork method_work(const std::vector<gl::ShadowFrame>& frames, const gl::EmulationSettings& settings) {
  MethodWork w;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::vector<gl::DrawCounters> counters = render::draw_counters(frames[k], settings.raster, settings.depth);
    std::array<gl::DrawCounters, gl::kPassKindCount>& by_kind = w.per_light.emplace_back();
    for (std::size_t d = 0; d < counters.size(); ++d)
      by_kind[static_cast<std::size_t>(render::draw_kind(frames[k].draws[d]))] += counters[d];
    if (k == 0) w.depth = by_kind[static_cast<std::size_t>(gl::PassKind::Depth)];
  }
  return w;
}

// One configuration's frames, every calibrated method and light, with the
// CPU observations made while emulating them.
struct EmulatedConfiguration {
  std::array<std::vector<gl::ShadowFrame>, kMethodCount> frames;  // per method, one per light; empty where refused
  std::vector<analysis::CpuObservation> cpu;
};

EmulatedConfiguration emulate(const Scene& scene, const std::string& id) {
  EmulatedConfiguration out;
  gl::EmulationSettings paper;
  paper.record_draws = true;
  gl::EmulationSettings clipped = paper;
  clipped.light_frustum.projection = gl::LightProjection::ClippedSides;
  std::array<bool, kMethodCount> refused{};
  std::optional<CameraSpaceScene> cs;
  try {
    cs.emplace(scene);
  } catch (const Error&) {
    // No exact camera space: no exact test observation for this configuration.
  }
  for (std::size_t k = 0; k < scene.lights.size(); ++k) {
    const std::string light_id = id + ":light" + std::to_string(k);
    gl::ShadowFrameBatch paper_batch(scene, k, paper), clipped_batch(scene, k, clipped);
    for (std::size_t m = 0; m < kMethodCount; ++m) {
      if (refused[m]) continue;
      try {
        out.frames[m].push_back((kMethods[m].clipped_sides ? clipped_batch : paper_batch).render(kMethods[m].method));
      } catch (const Error& e) {
        if (e.kind() != ErrorKind::Range && e.kind() != ErrorKind::Degenerate) throw;
        refused[m] = true;
        out.frames[m].clear();
      }
    }
    // Silhouettes: the paper batch computed them once, at its first frame.
    const std::vector<gl::ShadowFrame>& zpass = out.frames[0];
    const std::vector<gl::ShadowFrame>& clipped_zpplus = out.frames[3];
    if (zpass.size() == k + 1)
      for (const gl::OccluderCpuTimes& t : zpass.back().cpu.occluders)
        out.cpu.push_back({light_id + ":object" + std::to_string(t.object), analysis::CpuTask::Silhouette,
                           static_cast<double>(scene.objects[t.object].mesh->triangles.size()), t.silhouette_ms});
    // The counts the decision prices the clipped-sides cap and the exact
    // test by (analysis/work_estimate.hpp), per occluder of this light.
    std::vector<analysis::OccluderWorkInputs> inputs;
    for (std::size_t o = 0; o < scene.objects.size(); ++o)
      if (scene.objects[o].occluder) inputs.push_back(analysis::occluder_work_inputs(scene, o, k));
    auto inputs_of = [&inputs](std::size_t object) -> const analysis::OccluderWorkInputs& {
      const auto in = std::find_if(inputs.begin(), inputs.end(),
                                   [object](const analysis::OccluderWorkInputs& i) { return i.object == object; });
      NEARCAP_CHECK(in != inputs.end());
      return *in;
    };
    // The clipped-sides cap's construction, with its counts.
    if (clipped_zpplus.size() == k + 1)
      for (const gl::OccluderCpuTimes& t : clipped_zpplus.back().cpu.occluders) {
        const analysis::CpuTaskWork w = analysis::clipped_cap_work(inputs_of(t.object));
        out.cpu.push_back({light_id + ":object" + std::to_string(t.object), analysis::CpuTask::ClippedCap, w.triangles,
                           t.cap_build_ms, w.reaching, w.tested, w.straddling, w.examined});
      }
    // The exact empty-near-cap test of every occluder for this light.
    if (cs) {
      const analysis::CpuTaskWork w = analysis::exact_test_work(inputs);
      try {
        const auto t = std::chrono::steady_clock::now();
        const std::vector<bool> meets = occluders_meeting_light_pyramid(*cs, k);
        const double ms = ms_since(t);
        if (!meets.empty())
          out.cpu.push_back(
              {light_id, analysis::CpuTask::ExactTest, w.triangles, ms, w.reaching, w.tested, w.straddling});
      } catch (const Error& e) {
        if (e.kind() != ErrorKind::Degenerate) throw;  // the light in the near plane: no pyramid
      }
    }
  }
  return out;
}

// The pass observations of one method's lit frame.
void add_observations(const render::LitFrame& lit, const MethodWork& work, const std::vector<gl::ShadowFrame>& frames,
                      const std::string& id, const std::string& method, std::vector<analysis::PassObservation>& to) {
  for (const render::KindTime& t : lit.kind_times) {
    const std::size_t kind = static_cast<std::size_t>(t.kind);
    const bool whole_frame = t.kind == gl::PassKind::Depth;
    const gl::DrawCounters& c =
        whole_frame || t.kind == gl::PassKind::Lit ? work.depth : work.per_light[t.light_frame][kind];
    const std::string frame =
        whole_frame ? id + ":" + method : id + ":light" + std::to_string(frames[t.light_frame].light) + ":" + method;
    to.push_back({frame, t.kind, static_cast<double>(c.triangles), static_cast<double>(c.fragments), t.ms,
                  static_cast<double>(c.in_view)});
  }
}

// The p-th quantile (0..1) of `v`, linear between order statistics; NaN when empty.
double quantile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double x = p * static_cast<double>(v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(x);
  return i + 1 < v.size() ? v[i] + (x - static_cast<double>(i)) * (v[i + 1] - v[i]) : v[i];
}

std::string percent(double v) {
  if (!std::isfinite(v)) return "n/a";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %%", v * 100);
  return text;
}

void print_noise_floor(const analysis::CalibrationSet& set) {
  std::printf(
      "noise floor: %s drawn twice per configuration, each pass's time again / first (5th, 50th, 95th "
      "percentile):\n",
      kMethods[0].name);
  for (std::size_t k = 0; k < analysis::kPassKindCount; ++k) {
    analysis::CalibrationSet one;
    for (const analysis::PassObservation& o : set.passes)
      if (static_cast<std::size_t>(o.kind) == k) one.passes.push_back(o);
    for (const analysis::PassObservation& o : set.again)
      if (static_cast<std::size_t>(o.kind) == k) one.again.push_back(o);
    const std::vector<double> r = analysis::noise_floor_ratios(one);
    if (r.empty()) continue;
    std::printf("  %-10s %.3f  %.3f  %.3f  (%zu passes)\n", std::string(analysis::kPassKindNames[k]).c_str(),
                quantile(r, 0.05), quantile(r, 0.5), quantile(r, 0.95), r.size());
  }
  const std::vector<double> all = analysis::noise_floor_ratios(set);
  if (!all.empty())
    std::printf("  %-10s %.3f  %.3f  %.3f  (%zu passes)\n", "all", quantile(all, 0.05), quantile(all, 0.5),
                quantile(all, 0.95), all.size());
}

void print_fit_report(const analysis::DeviceProfile& p, const analysis::ProfileFitReport& r,
                      const analysis::EyeCountFitReport& eye, const analysis::FrameFitReport& frame,
                      bool eye_left_out) {
  std::printf("device profile for %s (held-out: frames with FNV-1a(frame) %% 5 == 0):\n", p.gl_renderer.c_str());
  std::printf("  %-12s %11s %13s %13s %13s %10s %10s\n", "pass kind", "ms per pass", "ms per Mtri", "per Mtri view",
              "ms per Mfrag", "train err", "held out");
  for (std::size_t k = 0; k < analysis::kPassKindCount; ++k) {
    const analysis::PassCost& c = p.passes[k];
    std::printf("  %-12s %11.4g %13.4g %13.4g %13.4g %10s %10s  (%zu / %zu passes)\n",
                std::string(analysis::kPassKindNames[k]).c_str(), c.intercept_ms, c.ms_per_mtriangle,
                c.ms_per_mtriangle_in_view, c.ms_per_mfragment, percent(r.train_median_relative_error[k]).c_str(),
                percent(r.held_out_median_relative_error[k]).c_str(), r.train_count[k], r.held_out_count[k]);
  }
  if (const auto& c = p.eye_count)
    std::printf("  %-12s %11.4g %13.4g %13s %13.4g %10s %10s  (%zu / %zu passes)\n", "eye_count", c->intercept_ms,
                c->ms_per_mtriangle, "-", c->ms_per_mfragment, percent(eye.train_median_relative_error).c_str(),
                percent(eye.held_out_median_relative_error).c_str(), eye.train_count, eye.held_out_count);
  else if (eye_left_out)
    std::printf("  eye_count    left out (--no-atomiczp): the policy does not offer AtomicZP\n");
  else
    std::printf("  eye_count    no training observation (no AtomicZP frame drawn): no eye_count row\n");
  std::printf("  %-12s %11s %13s %13s %13s %13s %13s %10s %10s\n", "cpu task", "ms per run", "ms per ktri",
              "per kreaching", "per ktested", "per kstraddle", "per kexamined", "train err", "held out");
  const analysis::CpuTaskCost silhouette{0, p.cpu.ms_per_ktriangle_silhouette, 0, 0, 0};
  const analysis::CpuTaskCost* cost[3] = {&silhouette, &p.cpu.clipped_cap, &p.cpu.exact_test};
  for (std::size_t t = 0; t < 3; ++t)
    std::printf("  %-12s %11.4g %13.4g %13.4g %13.4g %13.4g %13.4g %10s %10s  (%zu / %zu tasks)\n",
                std::string(analysis::kCpuTaskNames[t]).c_str(), cost[t]->intercept_ms, cost[t]->ms_per_ktriangle,
                cost[t]->ms_per_kreaching, cost[t]->ms_per_ktested, cost[t]->ms_per_kstraddling,
                cost[t]->ms_per_kexamined, percent(r.cpu_train_median_relative_error[t]).c_str(),
                percent(r.cpu_held_out_median_relative_error[t]).c_str(), r.cpu_train_count[t],
                r.cpu_held_out_count[t]);
  if (const auto& f = p.frame)
    std::printf(
        "  whole frame  %.4g ms per frame, %.4g ms less per pass drawn: frame time error %s train, %s held out "
        "(%zu / %zu frames); the passes' sum alone %s, %s\n",
        f->intercept_ms, f->ms_saved_per_pass, percent(frame.train_median_relative_error).c_str(),
        percent(frame.held_out_median_relative_error).c_str(), frame.train_count, frame.held_out_count,
        percent(frame.train_without_row).c_str(), percent(frame.held_out_without_row).c_str());
  else
    std::printf("  whole frame  no frame timed end to end: no frame row\n");
  std::printf("  (error: median |predicted - measured| / measured)\n");
  // What was fitted but never checked: too few configurations for the
  // held-out fifth to hold one of its observations.
  std::string unchecked;
  auto check = [&](std::string_view name, std::size_t train, std::size_t held_out) {
    if (train > 0 && held_out == 0) unchecked += (unchecked.empty() ? "" : ", ") + std::string(name);
  };
  for (std::size_t k = 0; k < analysis::kPassKindCount; ++k)
    check(analysis::kPassKindNames[k], r.train_count[k], r.held_out_count[k]);
  if (p.eye_count) check("eye_count", eye.train_count, eye.held_out_count);
  for (std::size_t t = 0; t < 3; ++t) check(analysis::kCpuTaskNames[t], r.cpu_train_count[t], r.cpu_held_out_count[t]);
  if (p.frame) check("whole frame", frame.train_count, frame.held_out_count);
  if (!unchecked.empty())
    std::fprintf(stderr,
                 "calibrate: warning: no held-out observation of %s: those costs are fitted but unchecked; calibrate "
                 "on more configurations (--samples, --path)\n",
                 unchecked.c_str());
}

// --path NAME: a file, or a bundled path's name (data/paths/NAME.json); a
// file that is neither is named by load_camera_path's error.
std::string resolve_path(const std::string& p) {
  const std::string bundled = bundled_path_file(p);
  return bundled.empty() ? p : bundled;
}

void run(CalibrateOptions o) {
  if (o.policy_given && o.write_policy.empty())
    throw Error(ErrorKind::Usage, "--policy goes with --write-policy (the policy the device profile is added to)");
  if (o.out.empty()) throw Error(ErrorKind::Usage, "nearcap calibrate writes its observations to --out FILE.csv");
  refuse_directory(o.out, "--out");
  std::optional<analysis::SwitchPolicy> policy;
  if (!o.write_policy.empty()) {
    refuse_directory(o.write_policy, "--write-policy");
    refuse_replacing_inputs(o.write_policy, {{o.policy, "policy file"}}, "--write-policy");
    if (o.write_policy == o.out)
      throw Error(ErrorKind::Usage, "--write-policy and --out name the same file '" + o.out + "'");
    policy = analysis::load_policy(o.policy);
  }
  for (std::string& p : o.paths) p = resolve_path(p);
  check_camera_path_names(o.paths);
  refuse_unread_sampler_options(o.sampler, o.samples);
  if (o.samples > 0) check_sampler_meshes(sampler_spec(o.sampler));
  const CalibrationSet set(o);
  check_memory_estimate("the configurations", o.width, o.height, "calibrate", kCalibrateBytesPerPixel, o.max_memory_gb,
                        "lower --samples, the --path frames or --width/--height", set.count(),
                        kCalibrateBytesPerConfiguration);
  // Every output checked before the measurements: not a file the command
  // reads (the policy, each camera path, its base scene and meshes, the
  // sampler's meshes), writable.
  std::vector<CommandInput> inputs;
  if (o.samples > 0) inputs = sampler_inputs(sampler_spec(o.sampler));
  if (policy) inputs.push_back({o.policy, "policy file"});
  for (const analysis::CameraPath& p : set.paths())
    for (CommandInput& in : camera_path_inputs(p)) inputs.push_back(std::move(in));
  refuse_replacing_inputs(o.out, inputs, "--out");
  if (!o.write_policy.empty()) refuse_replacing_inputs(o.write_policy, inputs, "--write-policy");
  io::check_output_files(o.write_policy.empty() ? std::vector<std::string>{o.out}
                                                : std::vector<std::string>{o.out, o.write_policy});
  if (set.count() == 0)
    throw Error(ErrorKind::Usage, "nothing to calibrate on: give --samples N (N > 0) and/or --path P");
  const render::EglContext context;
  render::LitFrameRenderer renderer;
  render::LitFrameOptions options;
  options.pass_kind_times = true;
  const render::LitFrameOptions whole;   // the same frame drawn as a renderer draws it, timed end to end
  const gl::EmulationSettings settings;  // the default raster and depth format of every frame

  analysis::CalibrationSet observations;
  MeshCache meshes;
  RejectedConfigurations rejected;
  std::size_t refused = 0, drawn = 0;
  // One configuration: every method's lit frame interleaved, then the first
  // method's again (the noise floor).  `record`: false for the warm-up.
  auto calibrate_one = [&](const Configuration& c, bool record) {
    std::optional<Scene> scene;
    try {
      scene = parse_scene(c.scene_json, c.id, ".", &meshes);
    } catch (const Error& e) {
      if (record) rejected.add(c.id, e);  // a sampled light inside an occluder, and the like: as sweep counts them
      return;
    }
    EmulatedConfiguration e = emulate(*scene, c.id);
    // Everything on the CPU first (the emulation and the counting run on
    // all cores), then their worker threads released (worker_threads.hpp):
    // no timed pass shares the processor with them.
    std::array<std::optional<MethodWork>, kMethodCount> work;
    for (std::size_t m = 0; m < kMethodCount; ++m)
      if (!e.frames[m].empty()) work[m] = method_work(e.frames[m], settings);
    release_worker_threads();
    // One untimed frame first: what follows the CPU work and the scene's
    // first uploads lands there, not in the first method's passes.
    bool first_drawn = false;
    for (std::size_t m = 0; m < kMethodCount; ++m) {
      if (!work[m]) {
        refused += record;
        continue;
      }
      render::LitFrame lit;
      try {
        if (!first_drawn) renderer.render(*scene, e.frames[m], settings.depth, options);
        first_drawn = true;
        lit = renderer.render(*scene, e.frames[m], settings.depth, options);
      } catch (const Error& err) {
        if (err.kind() != ErrorKind::Gl && err.kind() != ErrorKind::Range) throw;
        refused += record;
        work[m].reset();
        continue;
      }
      if (!record) continue;
      add_observations(lit, *work[m], e.frames[m], c.id, kMethods[m].name, observations.passes);
      // The whole frame again at once, without the per-pass waits: what the
      // passes' sum overstates (the profile's frame row).
      const render::LitFrame at_once = renderer.render(*scene, e.frames[m], settings.depth, whole);
      observations.frames.push_back({c.id + ":" + kMethods[m].name, at_once.ms});
      // AtomicZP's eye-count pass, per light frame: its own row.
      for (std::size_t k = 0; k < e.frames[m].size() && k < lit.eye_count_ms.size(); ++k) {
        const gl::ShadowFrame& f = e.frames[m][k];
        if (!f.eye_count) continue;
        observations.eye_count.push_back({c.id + ":light" + std::to_string(f.light) + ":" + kMethods[m].name,
                                          static_cast<double>(f.eye_count_triangles),
                                          static_cast<double>(scene->camera.width) * scene->camera.height,
                                          lit.eye_count_ms[k]});
      }
      ++drawn;
    }
    if (record && work[0]) {
      const render::LitFrame again = renderer.render(*scene, e.frames[0], settings.depth, options);
      add_observations(again, *work[0], e.frames[0], c.id, kMethods[0].name, observations.again);
    }
    if (record) observations.cpu.insert(observations.cpu.end(), e.cpu.begin(), e.cpu.end());
  };
  // The warm-up: the first configuration drawn once, unrecorded (the
  // driver's first draws, the caches).
  calibrate_one(set.at(0), false);
  refused = 0;
  ProgressLine progress(set.count());
  for (std::size_t k = 0; k < set.count(); ++k) {
    calibrate_one(set.at(k), true);
    progress.step(k + 1, "calibrate: configuration " + std::to_string(k + 1) + "/" + std::to_string(set.count()));
  }
  progress.end();
  rejected.refuse_all_rejected(set.count());
  // The observations first, on their own: the measuring is the dear part,
  // kept whatever the fit and the policy's write do; and named only once
  // written.
  io::write_output_files({{o.out, analysis::calibration_csv(observations)}});
  std::printf(
      "calibrated on %s: %zu configurations (%zu rejected), %zu method frames drawn (%zu refused), %zu pass "
      "and %zu cpu observations in %s\n",
      context.renderer().c_str(), set.count(), rejected.count(), drawn, refused,
      observations.passes.size() + observations.eye_count.size(), observations.cpu.size(), o.out.c_str());
  if (rejected.count() > 0) std::printf("calibrate: %s\n", rejected.sentence().c_str());
  print_noise_floor(observations);
  if (policy) {
    analysis::ProfileFitReport report;
    policy->device_profile =
        analysis::fit_device_profile(observations.passes, observations.cpu, context.renderer(), &report);
    // Frames fitted against another profile's prices: `evaluate --fit-unpriced` fits them again.
    policy->unpriced_frames.clear();
    analysis::EyeCountFitReport eye_report;
    policy->device_profile->eye_count = analysis::fit_eye_count_pass(observations.eye_count, &eye_report);
    // Without the eye-count row, AtomicZP's whole frames (whose eye-count
    // pass the profile then does not price) are left out of the frame row.
    std::vector<analysis::FrameObservation> frames = observations.frames;
    if (o.no_atomiczp) {
      policy->device_profile->eye_count.reset();
      const auto atomiczp = std::find_if(std::begin(kMethods), std::end(kMethods), [](const CalibratedMethod& m) {
        return m.method == gl::ShadowMethod::AtomicZP;
      });
      const std::string suffix = std::string(":") + atomiczp->name;
      frames.erase(std::remove_if(frames.begin(), frames.end(),
                                  [&suffix](const analysis::FrameObservation& f) {
                                    return f.frame.size() >= suffix.size() &&
                                           f.frame.compare(f.frame.size() - suffix.size(), suffix.size(), suffix) == 0;
                                  }),
                   frames.end());
    }
    analysis::FrameFitReport frame_report;
    policy->device_profile->frame = analysis::fit_frame_cost(frames, observations.passes, observations.eye_count,
                                                             *policy->device_profile, &frame_report);
    print_fit_report(*policy->device_profile, report, eye_report, frame_report, o.no_atomiczp);
    // A row with no training observation is fitted to nothing: its costs
    // would read 0 ms, a price the decision would trust.
    std::string unobserved;
    auto need = [&unobserved](std::string_view name, std::size_t train) {
      if (train == 0) unobserved += (unobserved.empty() ? "" : ", ") + std::string(name);
    };
    for (std::size_t k = 0; k < analysis::kPassKindCount; ++k) need(analysis::kPassKindNames[k], report.train_count[k]);
    for (std::size_t t = 0; t < 3; ++t) need(analysis::kCpuTaskNames[t], report.cpu_train_count[t]);
    if (!unobserved.empty())
      throw Error(ErrorKind::Usage, "no training observation of " + unobserved +
                                        ": the device profile would price it at 0 ms, so no policy is written (the "
                                        "observations are in " +
                                        o.out +
                                        "); calibrate on configurations that draw it (--samples, --kinds, "
                                        "--path)");
    // What the profile was measured on, beside how the policy was tuned.
    nlohmann::json provenance = nlohmann::json::parse(policy->provenance_json);
    nlohmann::json held_out = nlohmann::json::object(), cpu_held_out = nlohmann::json::object();
    for (std::size_t k = 0; k < analysis::kPassKindCount; ++k)
      if (std::isfinite(report.held_out_median_relative_error[k]))
        held_out[std::string(analysis::kPassKindNames[k])] = report.held_out_median_relative_error[k];
    if (policy->device_profile->eye_count && std::isfinite(eye_report.held_out_median_relative_error))
      held_out[std::string(analysis::kEyeCountPassName)] = eye_report.held_out_median_relative_error;
    nlohmann::json frame_held_out = nlohmann::json::object();
    if (std::isfinite(frame_report.held_out_median_relative_error))
      frame_held_out = {{"with_frame_row", frame_report.held_out_median_relative_error},
                        {"passes_sum", frame_report.held_out_without_row}};
    const char* tasks[] = {"silhouette", "clipped_cap", "exact_test"};
    for (std::size_t k = 0; k < 3; ++k)
      if (std::isfinite(report.cpu_held_out_median_relative_error[k]))
        cpu_held_out[tasks[k]] = report.cpu_held_out_median_relative_error[k];
    provenance["calibration"] = {
        {"gl_renderer", context.renderer()},
        {"samples", o.samples},
        {"seed", o.sampler.seed},
        {"paths", o.paths},
        {"width", o.width},
        {"height", o.height},
        {"configurations", set.count()},
        {"pass_observations", observations.passes.size() + observations.eye_count.size()},
        {"cpu_observations", observations.cpu.size()},
        {"frame_observations", frames.size()},
        {"eye_count_row", policy->device_profile->eye_count ? "fitted"
                          : o.no_atomiczp                   ? "left out"
                                                            : "none"},
        {"held_out_median_relative_error", {{"passes", held_out}, {"frame", frame_held_out}, {"cpu", cpu_held_out}}}};
    policy->provenance_json = json_text(provenance);
    io::write_output_files({{o.write_policy, analysis::policy_to_json(*policy)}});
    std::printf("policy with the device profile: %s\n", o.write_policy.c_str());
  }
}

}  // namespace

void register_calibrate(CLI::App& app) {
  auto [cmd, o] = add_subcommand<CalibrateOptions>(
      app, "calibrate",
      "measure what each pass kind (depth pre-pass, sides, light cap, dark cap, near-cap, lit pass) and each CPU task "
      "(silhouettes, the clipped-sides cap, the exact empty-near-cap test) costs on the current OpenGL (headless "
      "EGL), and AtomicZP's eye-count pass: a calibration set of hard-case samples and camera paths drawn with zpass, "
      "zfail, zpplus, zpplus-clipped-sides, zpplus-corrected and atomiczp, interleaved per configuration after a "
      "warm-up, each pass timed on "
      "its own with the triangles and fragments it drew, then the whole frame again at once, timed end to end; writes "
      "the observations as CSV (docs/calibration.md) and "
      "prints the noise floor (zpass drawn twice); with --write-policy, fits a device profile and writes the policy "
      "with it",
      run);
  add_samples_option(cmd, o.samples, "hard-case configurations of the sampler", 0, kMaxSweepSamples)
      ->capture_default_str();
  add_sampler_options(cmd, o.sampler, false);
  cmd.add_option("--path", o.paths,
                 "a camera path file, or a bundled path's name (near_plane_sweep, fly_around, ...): its every frame "
                 "(repeatable)");
  add_viewport_options(cmd, o.width, o.height);
  cmd.add_option("--out", o.out, "the observations' CSV file")->required();
  add_max_memory_option(cmd, o.max_memory_gb);
  note_given(cmd.add_option("--policy", o.policy, "the policy the device profile is added to (with --write-policy)")
                 ->capture_default_str(),
             o.policy_given);
  auto* write = cmd.add_option("--write-policy", o.write_policy,
                               "fit a device profile on the observations (Ceres), print its fit report, and write "
                               "--policy with it here (never over --policy)");
  cmd.add_flag("--no-atomiczp", o.no_atomiczp,
               "a profile without AtomicZP's eye-count row: the policy then does not offer AtomicZP, nor pay for "
               "testing its conditions (docs/policy.md)")
      ->needs(write);
}

}  // namespace nearcap::cli
