// nearcap render without --compare: each method's lit frame drawn by a real
// OpenGL (headless EGL), every light or --light K, of a scene or along a
// camera path, with --bench its passes and CPU work timed.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "frame_source.hpp"
#include "method_records.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/frame_time_drift.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/image_io.hpp"
#include "nearcap/io/output_files.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/render/egl_context.hpp"
#include "nearcap/render/lit_frame.hpp"
#include "nearcap/worker_threads.hpp"
#include "output_script.hpp"
#include "progress_line.hpp"
#include "render_command.hpp"

namespace nearcap::cli {
namespace {

// One light's share of a lit frame's CPU work (--bench): what the GL's
// clock does not see.
struct LightCpu {
  std::size_t light = 0;   // scene light index
  double decision_ms = 0;  // the policy's decision (FrameSource::decision_ms), 0 for a fixed method
  gl::FrameCpuTimes work;  // silhouettes, the clipped-sides caps, the light frustum
  // Each occluder's method (ShadowFrame::object_methods).
  std::vector<std::pair<std::size_t, gl::ShadowMethod>> methods;
  // The device profile's price of the policy's frame for this light
  // (price_decision's predicted_ms; NaN for a fixed method or a policy
  // without a profile).
  double profile_ms = std::numeric_limits<double>::quiet_NaN();
  // The policy's: 0 where its choice was priced on this frame, k > 0 where
  // it was kept from the frame priced k frames before (kept_choices.hpp).
  std::optional<int> frames_since_priced;
  double total() const { return decision_ms + work.total(); }
};

// One method's lit frame of a scene: its PNG, each light's stencil (with
// --stencil), the GL's times, and the CPU work that built its draw calls.
struct MethodFrame {
  std::string png;
  std::vector<std::string> stencil_pgm;  // per light
  double ms = 0;                         // the GL's frame (render::LitFrame::ms)
  double upload_ms = 0;                  // of `ms`
  render::LitFramePasses passes;         // with --bench
  std::vector<LightCpu> cpu;             // per light drawn
  // The frame's CPU work: every light's, and the uploads.
  double cpu_ms() const {
    double t = upload_ms;
    for (const LightCpu& l : cpu) t += l.total();
    return t;
  }
  // The CPU work and the GL's passes up to glFinish (the uploads are in both).
  double end_to_end_ms() const { return cpu_ms() - upload_ms + ms; }
};

// One lit frame per method of `scene` (every light, or --light K alone),
// "refused" where the driver or the float pipeline cannot draw it.  With
// --bench the first method is drawn a second time after the others, from
// frame sources of its own (its silhouettes computed again): `again`, the
// noise floor of the comparison.
// With --bench and both zpass and atomiczp among the methods, Z-pass's
// frame is drawn once more with GL_DEPTH_CLAMP on its sides (near and far,
// as AtomicZP draws them): `clamped`, so that AtomicZP's cost over Z-pass
// splits into the clamp's and the eye-count pass's.
struct LitFrames {
  std::vector<MethodFrame> methods;
  std::vector<std::string> refused;      // per method, "" where drawn
  std::optional<MethodFrame> again;      // with --bench
  std::optional<MethodFrame> clamped;    // with --bench, zpass and atomiczp
  std::vector<std::size_t> light_index;  // the scene lights drawn
  std::size_t lights = 0;
};

// Method m's lit frame from `sources` (one per light drawn); with
// `clamp_volumes` its volume draws with GL_DEPTH_CLAMP, near and far.
MethodFrame method_frame(render::LitFrameRenderer& renderer, const Scene& scene, const RenderOptions& o,
                         const RenderMethods& methods, const std::vector<std::unique_ptr<FrameSource>>& sources,
                         std::size_t m, bool keep_images, bool clamp_volumes = false) {
  MethodFrame out;
  std::vector<gl::ShadowFrame> frames;
  for (const auto& source : sources) {
    frames.push_back(source->frame(m));
    if (clamp_volumes)
      for (gl::DrawCall& d : frames.back().draws)
        if (d.pass == gl::DrawPass::Volume) d.state.depth_clamp_near = d.state.depth_clamp_far = true;
    const gl::ShadowFrame& f = frames.back();
    const bool policy = m >= methods.methods.size();
    LightCpu light;
    light.light = f.light;
    light.decision_ms = policy ? source->decision_ms() : 0.0;
    light.work = f.cpu;
    light.methods = f.object_methods;
    out.cpu.push_back(std::move(light));
    if (policy) {
      out.cpu.back().profile_ms = source->decision().predicted_ms;
      out.cpu.back().frames_since_priced = source->decision().frames_since_priced;
    }
  }
  render::LitFrameOptions options;
  options.read_stencils = o.stencil && keep_images;
  options.pass_times = o.bench;
  options.one_sided_stencil = o.one_sided_stencil;
  options.vertex_stage = o.vertex_stage;
  options.side_strips = o.side_strips;
  // --bench: the emulation's worker threads released before the timed draws
  // (worker_threads.hpp), so that none spins beside them.
  if (o.bench) release_worker_threads();
  const render::LitFrame lit = renderer.render(scene, frames, sources.front()->depth(m), options);
  out.passes = lit.passes;
  out.ms = lit.ms;
  out.upload_ms = lit.upload_ms;
  if (keep_images) {
    out.png = encode_png_rgb(lit.width, lit.height, lit.rgb);
    for (const std::vector<std::uint8_t>& st : lit.stencils)
      out.stencil_pgm.push_back(stencil_pgm(lit.width, lit.height, st));
  }
  return out;
}

// Z-pass's index among the methods where --bench times its sides with depth
// clamp (zpass and atomiczp both drawn), else the methods' count.
std::size_t depth_clamp_bench_method(const RenderOptions& o, const RenderMethods& methods) {
  const auto& ms = methods.methods;
  const auto zpass = std::find(ms.begin(), ms.end(), gl::ShadowMethod::ZPass);
  if (!o.bench || zpass == ms.end() || std::find(ms.begin(), ms.end(), gl::ShadowMethod::AtomicZP) == ms.end())
    return ms.size();
  return static_cast<std::size_t>(zpass - ms.begin());
}

LitFrames lit_frames(render::LitFrameRenderer& renderer, const Scene& scene, const RenderOptions& o,
                     const RenderMethods& methods, const gl::EmulationSettings& settings) {
  LitFrames out;
  for (std::size_t k = 0; k < scene.lights.size(); ++k)
    if (!o.light_given || k == o.light) out.light_index.push_back(k);
  out.lights = out.light_index.size();
  auto make_sources = [&](const RenderMethods& m) {
    std::vector<std::unique_ptr<FrameSource>> sources;  // one per light, shared by the methods
    for (std::size_t k : out.light_index) sources.push_back(std::make_unique<FrameSource>(scene, k, m, settings));
    return sources;
  };
  // --bench's second draw of method 0 decides as the first did: from the
  // policy's kept choices as this frame found them, in a copy of its own.
  RenderMethods again_methods = methods;
  if (o.bench && methods.kept) again_methods.kept = std::make_shared<analysis::KeptChoices>(*methods.kept);
  const std::vector<std::unique_ptr<FrameSource>> sources = make_sources(methods);
  for (std::size_t m = 0; m < methods.count(); ++m) {
    try {
      out.methods.push_back(method_frame(renderer, scene, o, methods, sources, m, true));
      out.refused.emplace_back();
    } catch (const Error& e) {
      if ((e.kind() != ErrorKind::Range && e.kind() != ErrorKind::Gl) || methods.count() == 1) throw;
      out.methods.emplace_back();
      out.refused.push_back(e.what());
    }
  }
  if (o.bench && out.refused[0].empty())
    out.again = method_frame(renderer, scene, o, again_methods, make_sources(again_methods), 0, false);
  const std::size_t zpass = depth_clamp_bench_method(o, methods);
  if (zpass < methods.methods.size() && out.refused[zpass].empty())
    out.clamped = method_frame(renderer, scene, o, methods, sources, zpass, false, true);
  return out;
}

// The scenes the lit frames are drawn from: the scene file, or each frame of
// the camera path, parsed when it is asked for, its meshes read once.  A
// path's frames are never all in memory: a frame's scene holds only its own
// camera and the shared meshes, and lives while its frame is drawn.
class LitScenes {
 public:
  explicit LitScenes(const RenderOptions& o) {
    if (o.path.empty())
      scene_ = load_scene(o.scene);
    else
      path_ = load_camera_path_file(o.path);
  }
  std::size_t count() const { return path_ ? static_cast<std::size_t>(path_->frames) : 1; }
  // The files the frames are read from: the scene or the camera path, its
  // base scene, and their meshes.
  std::vector<CommandInput> inputs() { return path_ ? camera_path_inputs(*path_) : scene_inputs(*scene_); }
  Scene at(std::size_t f) {
    if (!path_) return *scene_;
    const int frame = static_cast<int>(f);
    return parse_scene(analysis::path_frame_json(*path_, frame), path_->source + " frame " + std::to_string(f), ".",
                       &meshes_);
  }

 private:
  std::optional<analysis::CameraPath> path_;
  std::optional<Scene> scene_;
  MeshCache meshes_;
};

// Every frame's per-light CPU work of one method (--bench), in flat arrays
// that grow by doubling.  A frame's record holding vectors of its own would
// leave a few small blocks per frame among the blocks the frame's drawing
// freed, and glibc's heap would grow by about those blocks every frame
// (docs/findings/path-memory.md).
struct CpuLog {
  struct Occluder {
    std::size_t object = 0;
    std::optional<gl::ShadowMethod> method;  // the occluder's method (ShadowFrame::object_methods)
    double silhouette_ms = 0, cap_build_ms = 0;
  };
  struct Light {
    std::size_t light = 0;
    double decision_ms = 0, near_plane_ms = 0, light_frustum_ms = 0;
    double profile_ms = std::numeric_limits<double>::quiet_NaN();
    std::optional<int> frames_since_priced;
    std::size_t occluders_begin = 0, occluders_end = 0;  // in `occluders`
  };
  std::vector<Light> lights;
  std::vector<Occluder> occluders;

  // Appends a frame's lights; returns their range in `lights`.
  std::pair<std::size_t, std::size_t> add(const std::vector<LightCpu>& cpu) {
    const std::size_t begin = lights.size();
    for (const LightCpu& l : cpu) {
      Light row{l.light,      l.decision_ms,         l.work.near_plane_ms, l.work.light_frustum_ms,
                l.profile_ms, l.frames_since_priced, occluders.size(),     0};
      for (const gl::OccluderCpuTimes& t : l.work.occluders) {
        const auto chosen =
            std::find_if(l.methods.begin(), l.methods.end(), [&](const auto& om) { return om.first == t.object; });
        occluders.push_back({t.object,
                             chosen == l.methods.end() ? std::nullopt : std::optional<gl::ShadowMethod>(chosen->second),
                             t.silhouette_ms, t.cap_build_ms});
      }
      row.occluders_end = occluders.size();
      lights.push_back(row);
    }
    return {begin, lights.size()};
  }
};

// What render.json and the summary keep of one method's frame: a few
// numbers, the files named again from the frame's index.
struct LitFrameRecord {
  std::size_t frame = 0;
  double ms = 0;
  render::LitFramePasses passes;  // with --bench
  double cpu_ms = 0, end_to_end_ms = 0, upload_ms = 0;
  std::size_t lights_begin = 0, lights_end = 0;  // its lights in the method's CpuLog, with --bench
  // The policy's, with --bench and a device profile: its lights' prices
  // summed, and the end-to-end time predicted from them before drawing
  // (FramePrediction).
  double profile_ms = std::numeric_limits<double>::quiet_NaN();
  double predicted_ms = std::numeric_limits<double>::quiet_NaN();
};

// The policy's predicted end-to-end time of each frame of a path, as a
// renderer predicts it: its lights' prices (the device profile's) times the
// measured/priced ratio of the frame drawn before it
// (analysis::FrameTimeDrift, a path's window), plus its decisions' time,
// spent by then.
class FramePrediction {
 public:
  void predict(LitFrameRecord& fr, const CpuLog& log) {
    double priced = 0, decision = 0;
    bool any = false;
    for (std::size_t k = fr.lights_begin; k < fr.lights_end; ++k) {
      const CpuLog::Light& l = log.lights[k];
      decision += l.decision_ms;
      if (std::isfinite(l.profile_ms)) {
        priced += l.profile_ms;
        any = true;
      }
    }
    if (!any) return;
    fr.profile_ms = priced;
    fr.predicted_ms = priced * drift_.scale() + decision;
    drift_.observe(priced, fr.end_to_end_ms - decision);
    profile_error_.push_back(std::fabs(fr.profile_ms - fr.end_to_end_ms) / fr.end_to_end_ms);
    predicted_error_.push_back(std::fabs(fr.predicted_ms - fr.end_to_end_ms) / fr.end_to_end_ms);
  }
  const std::vector<double>& predicted_error() const { return predicted_error_; }
  const std::vector<double>& profile_error() const { return profile_error_; }

 private:
  analysis::FrameTimeDrift drift_{analysis::FrameTimeDrift::kPathWindow};
  std::vector<double> predicted_error_, profile_error_;
};

// --bench: render.json's breakdown of a frame's CPU work, per light and occluder.
nlohmann::json cpu_json(const LitFrameRecord& fr, const CpuLog& log) {
  nlohmann::json lights = nlohmann::json::array();
  for (std::size_t k = fr.lights_begin; k < fr.lights_end; ++k) {
    const CpuLog::Light& l = log.lights[k];
    nlohmann::json occluders = nlohmann::json::array();
    for (std::size_t i = l.occluders_begin; i < l.occluders_end; ++i) {
      const CpuLog::Occluder& t = log.occluders[i];
      occluders.push_back({{"object", t.object},
                           {"method", t.method ? std::string(gl::to_string(*t.method)) : ""},
                           {"silhouette_ms", t.silhouette_ms},
                           {"cap_build_ms", t.cap_build_ms}});
    }
    lights.push_back({{"light", l.light},
                      {"decision_ms", l.decision_ms},
                      {"near_plane_ms", l.near_plane_ms},
                      {"light_frustum_ms", l.light_frustum_ms},
                      {"occluders", std::move(occluders)}});
    if (std::isfinite(l.profile_ms)) lights.back()["profile_ms"] = l.profile_ms;
    if (l.frames_since_priced) lights.back()["frames_since_priced"] = *l.frames_since_priced;
  }
  return {{"upload_ms", fr.upload_ms}, {"lights", std::move(lights)}};
}

// The p-th quantile (0..1) of `v`, linear between order statistics.
double quantile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const double x = p * static_cast<double>(v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(x);
  return i + 1 < v.size() ? v[i] + (x - static_cast<double>(i)) * (v[i + 1] - v[i]) : v[i];
}

// The lit frame's file and each light's stencil file of method `name`'s frame `f`.
std::string lit_frame_file(const RenderOptions& o, const std::string& name, std::size_t f) {
  const std::filesystem::path dir(o.out);
  char frame_name[32];
  std::snprintf(frame_name, sizeof frame_name, "frame-%04zu.png", f);
  return o.path.empty() ? (dir / ("frame-" + name + ".png")).string() : (dir / name / frame_name).string();
}
std::string lit_stencil_file(const RenderOptions& o, const std::string& name, std::size_t f, std::size_t light_index) {
  const std::filesystem::path dir(o.out);
  const std::string light = "light-" + std::to_string(light_index);
  char frame_name[32];
  std::snprintf(frame_name, sizeof frame_name, "stencil-%04zu-", f);
  return o.path.empty() ? (dir / ("stencil-" + name + "-" + light + ".pgm")).string()
                        : (dir / name / (frame_name + light + ".pgm")).string();
}

}  // namespace

// Without --compare: the lit frame of each method as DIR/frame-METHOD.png,
// or with --path every frame of the camera path as DIR/METHOD/frame-NNNN.png,
// with each frame's GL time in DIR/render.json.  Along a path each frame's
// images go to disk as soon as it is drawn (staged, all or nothing) and only
// its times are kept, so memory stays flat however long the path.
void run_lit(const RenderOptions& o) {
  if (o.out.empty()) throw Error(ErrorKind::Usage, "nearcap render writes the lit frames into --out DIR");
  refuse_non_directory(o.out, "--out");
  const RenderMethods methods = render_methods(o.method, o.policy, o.policy_given, "render");
  gl::EmulationSettings settings = settings_from(o.emulation);
  settings.record_draws = true;
  LitScenes scenes(o);
  // No output replaces what the command reads: the fixed names before the
  // work, each frame's images as they are staged.
  std::vector<CommandInput> inputs = scenes.inputs();
  if (methods.policy) inputs.push_back({o.policy, "policy file"});
  for (const char* name : {"render.json", "bench.csv", "bench.png"})
    refuse_replacing_inputs((std::filesystem::path(o.out) / name).string(), inputs);
  // Every frame checked before the first is drawn (each parsed, then dropped).
  for (std::size_t f = 0; f < scenes.count(); ++f) {
    const Scene scene = scenes.at(f);
    if (o.light_given) check_light_index(scene, o.light);
    check_memory_estimate(scene, "render", 40, o.max_memory_gb);
  }
  // The bench plot's Python, before the frames that precede it.
  const std::string plot_script = shipped_scripts_dir() + "/report/render_bench.py";
  const std::string plot_what = "the bench plot's script";
  const bool plot =
      o.bench && !o.path.empty() &&
      std::find(methods.methods.begin(), methods.methods.end(), gl::ShadowMethod::ZPass) != methods.methods.end();
  std::optional<SettingsFile> plot_table;  // the plot's settings table, made before the frames too
  if (plot) {
    check_output_script(plot_script, plot_what);
    plot_table.emplace();
  }
  const render::EglContext context;
  std::fputs(policy_profile_note(methods, context.renderer()).c_str(), stderr);
  const std::filesystem::path dir(o.out);
  io::StagedOutputFiles files;
  std::vector<std::vector<LitFrameRecord>> per_method(methods.count());
  std::vector<CpuLog> cpu_log(methods.count());  // with --bench
  for (std::vector<LitFrameRecord>& records : per_method) records.reserve(scenes.count());
  std::vector<double> total_ms(methods.count(), 0);
  std::vector<double> cpu_total_ms(methods.count(), 0), end_to_end_total_ms(methods.count(), 0);  // with --bench
  std::vector<double> decision_total_ms(methods.count(), 0);  // the policy's decisions, with --bench
  std::vector<FramePrediction> prediction(methods.count());   // the policy's, with --bench
  std::vector<std::string> refused(methods.count());
  std::size_t lights = 0;
  std::vector<std::size_t> light_index;  // the scene lights drawn (the same in every frame)
  // --bench: one row per frame and method, and the passes' totals.
  const std::string stencil_sides = o.one_sided_stencil ? "one-sided" : "two-sided";
  const std::string layout = o.side_strips ? "side-strips" : "triangles";
  const std::string culling(gl::to_string(settings.volume_culling));
  std::string bench_csv =
      "frame,method,stencil,vertex_stage,layout,culling,ms,depth_ms,stencil_ms,lit_ms,gpu_depth_ms,gpu_stencil_ms,"
      "gpu_lit_ms,cpu_ms,end_to_end_ms\n";
  auto bench_row = [&](std::size_t f, const std::string& name, const MethodFrame& mf) {
    const render::LitFramePasses& p = mf.passes;
    char row[320];
    std::snprintf(row, sizeof row, "%zu,%s,%s,%s,%s,%s,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", f, name.c_str(),
                  stencil_sides.c_str(), std::string(name_of(o.vertex_stage)).c_str(), layout.c_str(), culling.c_str(),
                  mf.ms, p.depth_ms, p.stencil_ms, p.lit_ms, p.gpu_depth_ms, p.gpu_stencil_ms, p.gpu_lit_ms,
                  mf.cpu_ms(), mf.end_to_end_ms());
    bench_csv += row;
  };
  // The noise floor: the first method's end-to-end time drawn twice per frame, again over first.
  std::vector<double> again_ratio;
  const std::string again_name = methods.name(0) + "#again";
  // Z-pass's sides with depth clamp (LitFrames::clamped): their totals beside Z-pass's own.
  const std::size_t clamp_method = depth_clamp_bench_method(o, methods);
  const std::string clamped_name = "zpass#depth-clamp";
  struct ClampTotals {
    std::size_t frames = 0;
    double stencil_ms = 0, end_to_end_ms = 0, zpass_stencil_ms = 0, zpass_end_to_end_ms = 0;
  } clamp_totals;
  std::vector<render::LitFramePasses> pass_totals(methods.count());
  // --bench: the first frame once untimed, so that no method's first frame
  // pays for the driver's first use (shader compilation, allocations).
  render::LitFrameRenderer renderer;  // its programs kept from frame to frame
  if (o.bench) (void)lit_frames(renderer, scenes.at(0), o, methods, settings);
  // A path's frames (ended when a frame fails, so that the error has a line of its own).
  ProgressLine progress(scenes.count());
  for (std::size_t f = 0; f < scenes.count(); ++f) {
    const LitFrames frames = lit_frames(renderer, scenes.at(f), o, methods, settings);
    lights = frames.lights;
    light_index = frames.light_index;
    for (std::size_t m = 0; m < methods.count(); ++m) {
      const std::string name = methods.name(m);
      if (!frames.refused[m].empty()) {
        refused[m] = frames.refused[m];
        continue;
      }
      const MethodFrame& mf = frames.methods[m];
      const std::string frame_file = lit_frame_file(o, name, f);
      refuse_replacing_inputs(frame_file, inputs);
      files.add({frame_file, mf.png});
      for (std::size_t k = 0; k < mf.stencil_pgm.size(); ++k) {
        const std::string stencil_file = lit_stencil_file(o, name, f, frames.light_index[k]);
        refuse_replacing_inputs(stencil_file, inputs);
        files.add({stencil_file, mf.stencil_pgm[k]});
      }
      if (o.bench) {
        const render::LitFramePasses& p = mf.passes;
        bench_row(f, name, mf);
        if (m == 0 && frames.again) {
          bench_row(f, again_name, *frames.again);
          if (mf.end_to_end_ms() > 0) again_ratio.push_back(frames.again->end_to_end_ms() / mf.end_to_end_ms());
        }
        if (m == clamp_method && frames.clamped) {
          bench_row(f, clamped_name, *frames.clamped);
          ++clamp_totals.frames;
          clamp_totals.stencil_ms += frames.clamped->passes.stencil_ms;
          clamp_totals.end_to_end_ms += frames.clamped->end_to_end_ms();
          clamp_totals.zpass_stencil_ms += p.stencil_ms;
          clamp_totals.zpass_end_to_end_ms += mf.end_to_end_ms();
        }
        pass_totals[m].depth_ms += p.depth_ms;
        pass_totals[m].stencil_ms += p.stencil_ms;
        pass_totals[m].lit_ms += p.lit_ms;
        pass_totals[m].gpu_depth_ms += p.gpu_depth_ms;
        pass_totals[m].gpu_stencil_ms += p.gpu_stencil_ms;
        pass_totals[m].gpu_lit_ms += p.gpu_lit_ms;
        pass_totals[m].eye_count_ms += p.eye_count_ms;
      }
      constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
      const auto [lights_begin, lights_end] =
          o.bench ? cpu_log[m].add(mf.cpu) : std::pair<std::size_t, std::size_t>{0, 0};
      per_method[m].push_back(
          {f, mf.ms, mf.passes, mf.cpu_ms(), mf.end_to_end_ms(), mf.upload_ms, lights_begin, lights_end, kNone, kNone});
      if (o.bench && mf.end_to_end_ms() > 0) prediction[m].predict(per_method[m].back(), cpu_log[m]);
      total_ms[m] += mf.ms;
      cpu_total_ms[m] += mf.cpu_ms();
      end_to_end_total_ms[m] += mf.end_to_end_ms();
      for (const LightCpu& l : mf.cpu) decision_total_ms[m] += l.decision_ms;
    }
    if (scenes.count() > 1)
      progress.step(f + 1, "render: frame " + std::to_string(f + 1) + "/" + std::to_string(scenes.count()));
  }
  progress.end();
  std::vector<nlohmann::json> records;
  for (std::size_t m = 0; m < methods.count(); ++m) {
    const std::string name = methods.name(m);
    nlohmann::json r{{"method", name}, {"lights", lights}};
    if (!refused[m].empty()) r["refused"] = refused[m];
    if (!per_method[m].empty()) {
      nlohmann::json entries = nlohmann::json::array();
      for (const LitFrameRecord& fr : per_method[m]) {
        nlohmann::json entry{{"frame", fr.frame}, {"file", lit_frame_file(o, name, fr.frame)}, {"ms", fr.ms}};
        if (o.stencil)
          for (std::size_t k : light_index) entry["stencils"].push_back(lit_stencil_file(o, name, fr.frame, k));
        if (o.bench) {
          const render::LitFramePasses& p = fr.passes;
          entry["passes"] = {
              {"depth_ms", p.depth_ms},         {"stencil_ms", p.stencil_ms},         {"lit_ms", p.lit_ms},
              {"gpu_depth_ms", p.gpu_depth_ms}, {"gpu_stencil_ms", p.gpu_stencil_ms}, {"gpu_lit_ms", p.gpu_lit_ms}};
          if (p.eye_count_ms > 0) entry["passes"]["eye_count_ms"] = p.eye_count_ms;
          entry["cpu_ms"] = fr.cpu_ms;
          entry["end_to_end_ms"] = fr.end_to_end_ms;
          entry["cpu"] = cpu_json(fr, cpu_log[m]);
          if (std::isfinite(fr.predicted_ms)) {
            entry["profile_ms"] = fr.profile_ms;
            entry["predicted_ms"] = fr.predicted_ms;
          }
        }
        entries.push_back(std::move(entry));
      }
      r["frames"] = std::move(entries);
      r["mean_ms"] = total_ms[m] / static_cast<double>(per_method[m].size());
      if (o.bench) {
        r["mean_cpu_ms"] = cpu_total_ms[m] / static_cast<double>(per_method[m].size());
        if (decision_total_ms[m] > 0)
          r["mean_decision_ms"] = decision_total_ms[m] / static_cast<double>(per_method[m].size());
        r["mean_end_to_end_ms"] = end_to_end_total_ms[m] / static_cast<double>(per_method[m].size());
        if (!prediction[m].predicted_error().empty()) {
          r["predicted_median_error"] = quantile(prediction[m].predicted_error(), 0.5);
          r["profile_median_error"] = quantile(prediction[m].profile_error(), 0.5);
        }
      }
      if (o.path.empty()) {
        r["file"] = r["frames"][0]["file"];
        r["ms"] = r["frames"][0]["ms"];
      }
    }
    records.push_back(r);
  }
  nlohmann::json root = render_json(context, o.vertex_stage, records);
  if (!o.path.empty()) root["path"] = o.path;
  if (o.bench && !again_ratio.empty())
    root["noise_floor"] = {{"method", methods.name(0)},
                           {"frames", again_ratio.size()},
                           {"end_to_end_again_over_first_p05", quantile(again_ratio, 0.05)},
                           {"end_to_end_again_over_first_p95", quantile(again_ratio, 0.95)}};
  if (clamp_totals.frames > 0) {
    const double n = static_cast<double>(clamp_totals.frames);
    root["depth_clamp"] = {{"method", "zpass"},
                           {"frames", clamp_totals.frames},
                           {"mean_stencil_ms", clamp_totals.zpass_stencil_ms / n},
                           {"mean_stencil_ms_clamped", clamp_totals.stencil_ms / n},
                           {"mean_end_to_end_ms", clamp_totals.zpass_end_to_end_ms / n},
                           {"mean_end_to_end_ms_clamped", clamp_totals.end_to_end_ms / n}};
  }
  files.add({(dir / "render.json").string(), json_file_text(root)});
  if (o.bench) files.add({(dir / "bench.csv").string(), bench_csv});
  files.commit();
  if (o.path.empty()) {
    print_json_line(root);
  } else {
    // The summary a person reads: mean GL time per frame, relative to Z-pass's.
    double zpass_ms = 0;
    for (const nlohmann::json& r : records)
      if (r["method"] == "zpass" && r.contains("mean_ms")) zpass_ms = r["mean_ms"].get<double>();
    std::printf("%s, %zu frames (%s):\n", o.path.c_str(), scenes.count(), context.renderer().c_str());
    for (const nlohmann::json& r : records) {
      if (!r.contains("mean_ms")) {
        print_refused_row(r, "  ");
        continue;
      }
      const double mean = r["mean_ms"].get<double>();
      std::printf("  %-17s %8.2f ms per frame", r["method"].get<std::string>().c_str(), mean);
      if (zpass_ms > 0) std::printf("  (%.2fx Z-pass)", mean / zpass_ms);
      if (o.bench) {
        const std::size_t m = static_cast<std::size_t>(&r - &records[0]);
        const double n = static_cast<double>(per_method[m].size());
        std::printf("  depth %.2f + stencil %.2f + lit %.2f ms (timer queries %.3f + %.3f + %.3f)",
                    pass_totals[m].depth_ms / n, pass_totals[m].stencil_ms / n, pass_totals[m].lit_ms / n,
                    pass_totals[m].gpu_depth_ms / n, pass_totals[m].gpu_stencil_ms / n, pass_totals[m].gpu_lit_ms / n);
        if (pass_totals[m].eye_count_ms > 0)
          std::printf("  eye count %.2f ms (of the stencil)", pass_totals[m].eye_count_ms / n);
        std::printf("  cpu %.2f ms, end to end %.2f ms", cpu_total_ms[m] / n, end_to_end_total_ms[m] / n);
        if (decision_total_ms[m] > 0)
          std::printf("  (the decision %.3f ms, %.2f%% of end to end)", decision_total_ms[m] / n,
                      100 * decision_total_ms[m] / end_to_end_total_ms[m]);
        if (!prediction[m].predicted_error().empty())
          std::printf("  predicted within %.1f%% (median; the profile's price alone %.1f%%)",
                      100 * quantile(prediction[m].predicted_error(), 0.5),
                      100 * quantile(prediction[m].profile_error(), 0.5));
      }
      std::printf("\n");
    }
    std::printf("frames in %s/METHOD/, times in %s/render.json\n", o.out.c_str(), o.out.c_str());
  }
  if (o.bench) {
    std::printf(
        "bench: %s/bench.csv (%s stencil, vertex stage %s, %s, volume culling %s, a glFinish after each "
        "pass)\n",
        o.out.c_str(), stencil_sides.c_str(), std::string(name_of(o.vertex_stage)).c_str(), layout.c_str(),
        culling.c_str());
    if (!again_ratio.empty())
      std::printf(
          "bench: noise floor: %s drawn twice per frame (%s rows): end-to-end time again/first %.3f to %.3f "
          "(5th to 95th percentile, %zu frame%s)\n",
          methods.name(0).c_str(), again_name.c_str(), quantile(again_ratio, 0.05), quantile(again_ratio, 0.95),
          again_ratio.size(), again_ratio.size() == 1 ? "" : "s");
    if (clamp_totals.frames > 0) {
      const double n = static_cast<double>(clamp_totals.frames);
      std::printf(
          "bench: depth clamp: zpass's draws again with GL_DEPTH_CLAMP on its sides (%s rows): stencil %.3f ms per "
          "frame against %.3f without, end to end %.3f against %.3f (%zu frame%s)\n",
          clamped_name.c_str(), clamp_totals.stencil_ms / n, clamp_totals.zpass_stencil_ms / n,
          clamp_totals.end_to_end_ms / n, clamp_totals.zpass_end_to_end_ms / n, clamp_totals.frames,
          clamp_totals.frames == 1 ? "" : "s");
    }
    if (!o.path.empty() && !plot)
      std::printf("bench: no bench.png (its times are relative to Z-pass's: add zpass to --method)\n");
    if (plot) {
      const std::string png = (dir / "bench.png").string();
      run_output_script(plot_script,
                        {(dir / "bench.csv").string(), png,
                         std::filesystem::path(o.path).stem().string() + " (" + context.renderer() + ", " +
                             stencil_sides + " stencil)",
                         "--settings", plot_table->path()},
                        plot_what, png);
      std::printf("bench: %s (frame time relative to Z-pass, per frame)\n", png.c_str());
    }
  }
}

}  // namespace nearcap::cli
