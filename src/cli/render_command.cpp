// nearcap render SCENE --light K --compare [--method M|all] [--out DIR]: each
// stencil method's frame drawn by a real OpenGL (headless EGL) from the
// emulation's own draw calls, held against the emulation and the exact
// reference, one JSON record per method.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <memory>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/image_io.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "nearcap/render/egl_context.hpp"
#include "nearcap/render/gl_frame_replay.hpp"
#include "nearcap/render/lit_frame.hpp"

namespace nearcap::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::size_t light = 0;
  bool light_given = false;
  std::string method = "all";
  bool compare = false;
  std::string out;
  EmulationOptions emulation;
  double max_memory_gb = 0;
};

// The stencil as the reference's 16-bit PGM (top row first).
std::string stencil_pgm(int width, int height, const std::vector<std::uint8_t>& stencil) {
  std::vector<std::uint16_t> top_first(stencil.size());
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      top_first[static_cast<std::size_t>(height - 1 - j) * width + i] =
          stencil[static_cast<std::size_t>(j) * width + i];
  return nearcap::encode_pgm16(width, height, top_first);
}

// Without --compare: the lit frame of each method, every light (or --light
// K alone), as DIR/frame-METHOD.png.
void run_lit(const RenderOptions& o) {
  if (o.out.empty()) throw Error(ErrorKind::Usage, "nearcap render writes the lit frames into --out DIR");
  const std::vector<gl::ShadowMethod> methods = methods_from(o.method, "--method");
  gl::EmulationSettings settings = settings_from(o.emulation);
  settings.record_draws = true;
  const Scene scene = load_scene(o.scene);
  if (o.light_given) check_light_index(scene, o.light);
  check_memory_estimate(scene, "render", 40, o.max_memory_gb);
  const render::EglContext context;
  std::vector<std::size_t> lights;
  for (std::size_t k = 0; k < scene.lights.size(); ++k)
    if (!o.light_given || k == o.light) lights.push_back(k);
  std::vector<std::unique_ptr<gl::ShadowFrameBatch>> batches;  // one per light, shared by the methods
  for (std::size_t k : lights) batches.push_back(std::make_unique<gl::ShadowFrameBatch>(scene, k, settings));
  nlohmann::json records = nlohmann::json::array();
  std::vector<io::OutputFile> files;
  for (gl::ShadowMethod m : methods) {
    const std::string name(to_string(m));
    try {
      std::vector<gl::ShadowFrame> frames;
      for (const auto& b : batches) frames.push_back(b->render(m));
      const render::LitFrame lit = render::render_lit_frame(scene, frames, settings.depth);
      const std::string file = (std::filesystem::path(o.out) / ("frame-" + name + ".png")).string();
      files.push_back({file, encode_png_rgb(lit.width, lit.height, lit.rgb)});
      records.push_back({{"method", name}, {"file", file}, {"lights", lights.size()}, {"ms", lit.ms}});
    } catch (const Error& e) {
      if ((e.kind() != ErrorKind::Range && e.kind() != ErrorKind::Gl) || methods.size() == 1) throw;
      records.push_back({{"method", name}, {"refused", e.what()}});
    }
  }
  nlohmann::json root{{"renderer", context.renderer()}, {"version", context.version()}, {"methods", records}};
  files.push_back({(std::filesystem::path(o.out) / "render.json").string(), root.dump(1) + "\n"});
  io::write_output_files(files);
  std::cout << root.dump() << "\n";
}

void run(const RenderOptions& o) {
  if (!o.compare) return run_lit(o);
  if (!o.light_given) throw Error(ErrorKind::Usage, "--compare needs --light K");
  const std::vector<gl::ShadowMethod> methods = methods_from(o.method, "--method");
  gl::EmulationSettings settings = settings_from(o.emulation);
  settings.record_draws = true;
  const Scene scene = load_scene(o.scene);
  check_light_index(scene, o.light);
  check_memory_estimate(scene, "render", 40, o.max_memory_gb);
  const render::EglContext context;  // before the exact work: no GL, no point
  const CameraSpaceScene cs(scene);
  const PixelReference ref = compute_pixel_reference(cs, o.light);

  nlohmann::json records = nlohmann::json::array();
  std::vector<io::OutputFile> files;
  gl::ShadowFrameBatch batch(scene, o.light, settings);
  render::GlFrameReplay replay(scene.camera.width, scene.camera.height, settings.depth);
  for (gl::ShadowMethod m : methods) {
    const std::string name(to_string(m));
    gl::ShadowFrame frame;
    render::ReplayedFrame real;
    try {
      frame = batch.render(m);
      real = replay.replay(frame.draws);
    } catch (const Error& e) {
      // The float pipeline refuses the frame (range), or this GL cannot draw
      // it (a missing extension): the other methods still run.
      if ((e.kind() != ErrorKind::Range && e.kind() != ErrorKind::Gl) || methods.size() == 1) throw;
      records.push_back({{"method", name}, {"refused", e.what()}});
      continue;
    }
    const render::ReplayComparison diff = render::compare(real, frame);
    const CrackReport emulated = judge_frame(frame, ref);
    gl::ShadowFrame as_drawn = frame;  // the real GL's buffers, judged the same way
    as_drawn.stencil = real.stencil;
    as_drawn.object = real.object;
    if (!real.near_cap.empty()) as_drawn.near_cap = real.near_cap;
    const CrackReport drawn = judge_frame(as_drawn, ref);
    records.push_back({{"method", name},
                       {"gl_vs_emulation", diff.stencil},
                       {"objects_differ", diff.object},
                       {"near_cap_differ", diff.near_cap},
                       {"gl_vs_exact", drawn.wrong},
                       {"emulation_vs_exact", emulated.wrong},
                       {"ms", real.ms},
                       {"emulation_ms", frame.times.total()}});
    if (!o.out.empty()) {
      const std::filesystem::path dir(o.out);
      files.push_back(
          {(dir / ("stencil-gl-" + name + ".pgm")).string(), stencil_pgm(real.width, real.height, real.stencil)});
      files.push_back({(dir / ("stencil-emulation-" + name + ".pgm")).string(),
                       stencil_pgm(frame.width, frame.height, frame.stencil)});
    }
  }
  nlohmann::json root{{"renderer", context.renderer()}, {"version", context.version()}, {"methods", records}};
  if (!o.out.empty()) {
    files.push_back({(std::filesystem::path(o.out) / "render.json").string(), root.dump(1) + "\n"});
    io::write_output_files(files);
  }
  std::cout << root.dump() << "\n";
}

}  // namespace

void register_render(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "render",
      "draw the stencil methods on a real OpenGL (headless EGL: llvmpipe, or a GPU's driver) from the emulation's "
      "own draw calls: the lit frame with its shadows, every light (or --light K), as DIR/frame-METHOD.png; with "
      "--compare --light K, one JSON record per method: stencil pixels where GL and the emulation differ, and wrong "
      "pixels of each against the exact reference (with --out DIR, both stencils as 16-bit PGM)");
  auto o = std::make_shared<RenderOptions>();
  cmd->add_option("scene", o->scene, "scene file (JSON)")->required();
  auto* light = add_light_option(*cmd, o->light, false);
  cmd->add_option("--method", o->method, "zpass, zfail, zpplus, zpplus-corrected, preload, comma-separated, or all")
      ->capture_default_str();
  cmd->add_flag("--compare", o->compare, "compare the real GL's stencil with the emulation's and the exact reference");
  cmd->add_option("--out", o->out,
                  "output directory for the lit frames (or, with --compare, the stencils) and render.json (created "
                  "if missing)");
  add_emulation_options(*cmd, o->emulation);
  add_max_memory_option(*cmd, o->max_memory_gb);
  cmd->callback([o, light] {
    o->light_given = light->count() > 0;
    run(*o);
  });
}

}  // namespace nearcap::cli
