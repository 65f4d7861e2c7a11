// nearcap render SCENE --light K --compare [--method M|all] [--out DIR]: each
// stencil method's frame drawn by a real OpenGL (headless EGL) from the
// emulation's own draw calls, held against the emulation and the exact
// reference, one JSON record per method; without --compare, the lit frames
// (render_lit.cpp).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "frame_source.hpp"
#include "method_records.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/image_io.hpp"
#include "nearcap/io/output_files.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "nearcap/render/egl_context.hpp"
#include "nearcap/render/eye_count_pass.hpp"
#include "nearcap/render/gl_frame_replay.hpp"
#include "render_command.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {

// The stencil as the reference's 16-bit PGM (top row first).
std::string stencil_pgm(int width, int height, const std::vector<std::uint8_t>& stencil) {
  std::vector<std::uint16_t> top_first(stencil.size());
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      top_first[static_cast<std::size_t>(height - 1 - j) * width + i] =
          stencil[static_cast<std::size_t>(j) * width + i];
  return nearcap::encode_pgm16(width, height, top_first);
}

nlohmann::json render_json(const render::EglContext& context, render::VertexStage stage,
                           const std::vector<nlohmann::json>& methods) {
  return {{"renderer", context.renderer()},
          {"version", context.version()},
          {"vertex_stage", std::string(name_of(stage))},
          {"methods", methods}};
}

namespace {

// `draws` with their volume draws' stencil clear (AtomicZP's count) set to `count` mod 256.
std::vector<gl::DrawCall> with_stencil_clear(std::vector<gl::DrawCall> draws, std::size_t count) {
  for (gl::DrawCall& d : draws)
    if (d.pass == gl::DrawPass::Volume) d.state.stencil_clear = static_cast<std::uint8_t>(count & 0xffu);
  return draws;
}

// --compare --table: one row per method, the JSON record's figures, and the
// policy's choice per occluder below.
void print_compare_table(const nlohmann::json& root, const std::string& scene, std::size_t light) {
  std::printf("%s, light %zu, on %s (%s), vertex stage %s\n", scene.c_str(), light,
              root["renderer"].get<std::string>().c_str(), root["version"].get<std::string>().c_str(),
              root["vertex_stage"].get<std::string>().c_str());
  std::printf("%-17s %10s %8s %8s %9s %7s %10s %9s %9s\n", "method", "gl!=emul", "obj!=", "cap!=", "gl-wrong", "cracks",
              "emul-wrong", "gl ms", "emul ms");
  for (const nlohmann::json& r : root["methods"]) {
    const std::string method = r["method"].get<std::string>();
    if (r.contains("refused")) {
      print_refused_row(r);
      continue;
    }
    std::printf("%-17s %10zu %8zu %8zu %9zu %7zu %10zu %9.2f %9.2f\n", method.c_str(),
                r["gl_vs_emulation"].get<std::size_t>(), r["objects_differ"].get<std::size_t>(),
                r["near_cap_differ"].get<std::size_t>(), r["gl_vs_exact"].get<std::size_t>(),
                r["cracks"].get<std::size_t>(), r["emulation_vs_exact"].get<std::size_t>(), r["ms"].get<double>(),
                r["emulation_ms"].get<double>());
  }
  for (const nlohmann::json& r : root["methods"])
    if (r.contains("occluders")) {
      std::printf("%s:", r["method"].get<std::string>().c_str());
      print_occluder_lines(r["occluders"]);
      if (r.value("depth_limited", false)) std::printf("  %s\n", r["depth_note"].get<std::string>().c_str());
      if (r.contains("near_plane_note")) std::printf("  %s\n", r["near_plane_note"].get<std::string>().c_str());
    }
  for (const nlohmann::json& r : root["methods"])
    if (r.contains("eye_count")) {
      const nlohmann::json& e = r["eye_count"];
      std::printf("%s: eye count gl %zu, emulation %zu, over %zu triangles (pass %.3f ms, read back %.3f ms)\n",
                  r["method"].get<std::string>().c_str(), e["gl"].get<std::size_t>(), e["emulation"].get<std::size_t>(),
                  e["triangles"].get<std::size_t>(), e["pass_ms"].get<double>(), e["read_back_ms"].get<double>());
    }
  std::printf(
      "gl!=emul: stencil pixels where the real GL and the emulation differ; obj!=: pixels where they see "
      "different objects; cap!=: near-cap stencil pixels that differ; gl-wrong, emul-wrong: each one's wrong "
      "pixels against the exact reference; cracks: the real GL's wrong pixels that are cracks\n");
}

void run(const RenderOptions& o) {
  if (o.scene.empty() == o.path.empty())
    throw Error(ErrorKind::Usage, "nearcap render takes a scene file or --path PATH (one of them)");
  if (o.table && !o.compare) throw Error(ErrorKind::Usage, "--table goes with --compare");
  if (!o.compare) return run_lit(o);
  if (o.bench || o.one_sided_stencil || o.side_strips)
    throw Error(ErrorKind::Usage,
                "--bench, --one-sided-stencil and --side-strips go with the lit frames, not --compare");
  if (o.stencil)
    throw Error(ErrorKind::Usage, "--stencil goes with the lit frames; with --compare, --out DIR writes both stencils");
  if (!o.path.empty()) throw Error(ErrorKind::Usage, "--compare takes a scene file, not --path");
  if (!o.light_given) throw Error(ErrorKind::Usage, "--compare needs --light K");
  refuse_non_directory(o.out, "--out");
  const RenderMethods methods = render_methods(o.method, o.policy, o.policy_given, "render");
  gl::EmulationSettings settings = settings_from(o.emulation);
  settings.record_draws = true;
  const Scene scene = load_scene(o.scene);
  check_light_index(scene, o.light);
  check_memory_estimate(scene, "render", 40, o.max_memory_gb);
  const render::EglContext context;  // before the exact work: no GL, no point
  std::fputs(policy_profile_note(methods, context.renderer()).c_str(), stderr);
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, o.light);
  const PixelReference ref = compute_pixel_reference(tracer);
  CrackDistances distances(tracer, ref);

  MethodRecords records(methods.count());
  std::vector<CommandInput> inputs = scene_inputs(scene);
  if (methods.policy) inputs.push_back({o.policy, "policy file"});
  OutputDir out(o.out, std::move(inputs));
  FrameSource source(scene, o.light, methods, settings);
  std::unique_ptr<render::GlFrameReplay> replay;   // made for each depth buffer the methods need
  std::unique_ptr<render::EyeCountPass> eye_pass;  // made for the first AtomicZP frame
  gl::DepthFormat replay_depth = settings.depth;
  for (std::size_t m = 0; m < methods.count(); ++m) {
    const std::string name = methods.name(m);
    gl::ShadowFrame frame;
    render::ReplayedFrame real;
    // AtomicZP: the GL's own eye count, read back so that the replay clears
    // the stencil to it rather than to the emulation's.
    std::optional<render::EyeCountReadBack> eye;
    try {
      frame = source.frame(m);
      if (!replay || replay_depth != source.depth(m)) {
        replay_depth = source.depth(m);
        replay = std::make_unique<render::GlFrameReplay>(scene.camera.width, scene.camera.height, replay_depth);
      }
      const render::VertexStage stage = o.vertex_stage;
      if (frame.eye_count) {
        if (!eye_pass) eye_pass = std::make_unique<render::EyeCountPass>();
        eye = eye_pass->run_and_read_back(render::eye_count_inputs(
            scene, frame.light, render::eye_counted_objects(frame), render::recorded_arithmetic(frame)));
        real = replay->replay(with_stencil_clear(frame.draws, eye->count), 0, stage);
      } else {
        real = replay->replay(frame.draws, 0, stage);
      }
    } catch (const Error& e) {
      // The float pipeline refuses the frame (range), or this GL cannot draw
      // it (a missing extension): the other methods still run.
      records.refuse(name, e, {ErrorKind::Range, ErrorKind::Gl});
      continue;
    }
    const render::ReplayComparison diff = render::compare(real, frame);
    const CrackReport emulated = judge_frame(frame, ref);
    gl::ShadowFrame as_drawn = frame;  // the real GL's buffers, judged the same way
    as_drawn.stencil = real.stencil;
    as_drawn.object = real.object;
    if (!real.near_cap.empty()) as_drawn.near_cap = real.near_cap;
    CrackReport drawn = judge_frame(as_drawn, ref);
    distances.measure(drawn);
    nlohmann::json record{{"method", name},
                          {"gl_vs_emulation", diff.stencil},
                          {"objects_differ", diff.object},
                          {"near_cap_differ", diff.near_cap},
                          {"gl_vs_exact", drawn.wrong},
                          {"cracks", *drawn.cracks},
                          {"emulation_vs_exact", emulated.wrong},
                          {"ms", real.ms},
                          {"emulation_ms", frame.times.total()}};
    if (eye)
      record["eye_count"] = {{"gl", eye->count},
                             {"emulation", *frame.eye_count},
                             {"triangles", eye->triangles},
                             {"pass_ms", eye->pass_ms},
                             {"read_back_ms", eye->read_back_ms}};
    if (m >= methods.methods.size()) {
      record.update(policy_decision_json(scene, source.decision()));
      if (std::isfinite(source.decision().predicted_ms)) record["predicted_ms"] = source.decision().predicted_ms;
    }
    records.add(record);
    out.add("stencil-gl-" + name + ".pgm", [&] { return stencil_pgm(real.width, real.height, real.stencil); });
    out.add("stencil-emulation-" + name + ".pgm",
            [&] { return stencil_pgm(frame.width, frame.height, frame.stencil); });
  }
  const nlohmann::json root = render_json(context, o.vertex_stage, records.records());
  out.write("render.json", root);
  if (o.table)
    print_compare_table(root, scene.source, o.light);
  else
    print_json_line(root);
}

}  // namespace

void register_render(CLI::App& app) {
  auto [cmd, o] = add_subcommand<RenderOptions>(
      app, "render",
      "draw the stencil methods on a real OpenGL (headless EGL: llvmpipe, or a GPU's driver) from the emulation's "
      "own draw calls, each volume built by the GL's GLSL vertex programs: the lit frame with its shadows, every light "
      "(or --light K), as DIR/frame-METHOD.png; with "
      "--compare --light K, one JSON record per method: stencil pixels where GL and the emulation differ, and wrong "
      "pixels of each against the exact reference (or a table with --table; with --out DIR, both stencils as 16-bit "
      "PGM)",
      run);
  add_scene_argument(cmd, o.scene);
  cmd.add_option("--path", o.path, "a camera path (data/paths/): its frames' lit frames, DIR/METHOD/frame-NNNN.png");
  add_optional_light_option(cmd, o.light, o.light_given);
  cmd.add_option("--method", o.method,
                 "zpass, zfail, zpplus, zpplus-corrected, preload, atomiczp, policy (a method per occluder, from "
                 "--policy), comma-separated, or all (the six and the policy)")
      ->capture_default_str();
  note_given(cmd.add_option("--policy", o.policy, "the switch policy for --method policy (nearcap tune writes one)"),
             o.policy_given)
      ->capture_default_str();
  cmd.add_flag("--compare", o.compare, "compare the real GL's stencil with the emulation's and the exact reference");
  cmd.add_flag("--table", o.table, "with --compare, print a human-readable table instead of JSON");
  cmd.add_flag("--stencil", o.stencil,
               "with the lit frames, each light's real stencil as a 16-bit PGM in the reference's format (the stencil "
               "at every pixel, also where nothing is seen, where the reference writes 65535): "
               "DIR/stencil-METHOD-light-K.pgm (DIR/METHOD/stencil-NNNN-light-K.pgm along a path)");
  cmd.add_flag("--bench", o.bench,
               "time each pass (a glFinish after each: the depth pre-pass, the stencil passes, the lit passes) "
               "and the CPU work that builds the draw calls (silhouettes, the clipped-sides cap, the policy's "
               "decision, uploads), the methods interleaved frame by frame and the first of --method drawn twice (the "
               "first other than policy, which is drawn last; policy when alone; its METHOD#again rows: the noise "
               "floor): the breakdown on stdout, DIR/bench.csv, the CPU work per "
               "light and occluder in DIR/render.json, and along a path DIR/bench.png (each frame's time "
               "relative to Z-pass, as the paper's Figures 9-11)");
  cmd.add_flag("--one-sided-stencil", o.one_sided_stencil,
               "draw each two-sided stencil draw as two one-sided draws (back faces culled, then front), as GL "
               "without two-sided stencil does: the same stencil, twice the vertex work");
  cmd.add_flag("--side-strips", o.side_strips,
               "draw the volumes' sides as triangle strips along the silhouette's chains (the paper's layout for "
               "ZP+'s sides; the same triangles), caps and corrective quads as independent triangles");
  add_choice_option(cmd, "--vertex-stage", o.vertex_stage,
                    "where each draw's clip-space vertices come from: " + values_described<render::VertexStage>());
  cmd.add_option("--out", o.out,
                 "output directory for the lit frames (or, with --compare, the stencils) and render.json (created "
                 "if missing)");
  add_emulation_options(cmd, o.emulation);
  add_max_memory_option(cmd, o.max_memory_gb);
}

}  // namespace nearcap::cli
