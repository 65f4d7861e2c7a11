// nearcap view SCENE: the interactive viewer.  A window (GLFW) showing the lit
// frame with its shadows, drawn by the real GL exactly as `nearcap render`
// draws it, from a fly camera; keys switch the method (and the policy), the
// light, and an overlay of the frame's cracks against the exact reference,
// computed in the background.  `--keys` plays a key sequence through the same
// commands, `--screenshot FILE` then writes the window's pixels and exits:
// how CI drives it under Xvfb.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "frame_source.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/image_io.hpp"
#include "nearcap/io/input_files.hpp"
#include "nearcap/io/output_files.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/render/lit_frame.hpp"
#include "nearcap/view/crack_overlay.hpp"
#include "nearcap/view/fly_camera.hpp"
#include "nearcap/view/status_panel.hpp"
#include "nearcap/view/viewer_commands.hpp"
#include "nearcap/view/viewer_window.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

using Json = nlohmann::json;

struct ViewOptions {
  std::string scene;
  std::size_t light = 0;
  bool light_given = false;
  std::string method = "all";
  std::string policy = shipped_data_dir() + "/policy.json";
  bool policy_given = false;  // --policy on the command line
  std::string keys;
  std::string screenshot;
  std::string out = ".";
  double step = 0;
  EmulationOptions emulation;
  double max_memory_gb = 0;
};

// The scene file's JSON with its mesh paths made absolute, so that a saved
// view is a scene file wherever it is written.
Json scene_json_with_absolute_meshes(const std::string& path) {
  return Json::parse(with_absolute_mesh_paths(io::read_input_file(path, "scene file"), path));
}

// The camera in the scene format's exact form: the view matrix and the frustum.
Json camera_json(const Camera& c) {
  Json view = Json::array();
  for (const auto& row : c.view.rows) view.push_back({row[0], row[1], row[2], row[3]});
  view.push_back({0, 0, 0, 1});
  const Frustum& f = c.frustum;
  return {
      {"view", view},
      {"frustum",
       {{"left", f.left}, {"right", f.right}, {"bottom", f.bottom}, {"top", f.top}, {"near", f.near}, {"far", f.far}}},
      {"width", c.width},
      {"height", c.height}};
}

// One step: a fiftieth of the diagonal of the box around every object.
double default_step(const Scene& scene) {
  Vec3d lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max()},
      hi = -1.0 * lo;
  for (const SceneObject& o : scene.objects)
    for (const Vec3d& p : o.mesh->positions) {
      const Vec3d w = o.object_to_world.apply(p);
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], w[k]);
        hi[k] = std::max(hi[k], w[k]);
      }
    }
  const Vec3d d = hi - lo;
  const double diagonal = std::sqrt(dot(d, d));
  return diagonal > 0 && std::isfinite(diagonal) ? diagonal / 50 : 1.0;
}

std::string object_name(const Scene& scene, std::size_t o) {
  return std::filesystem::path(scene.objects[o].mesh_path).stem().string() + "#" + std::to_string(o);
}

std::string fixed(double v, int digits) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

// The viewer draws the policy's methods and reads none of its prices.
RenderMethods unpriced(RenderMethods m) {
  m.priced = false;
  return m;
}

std::deque<view::ViewerInput> keys_of(const std::string& script) {
  const std::vector<view::ViewerInput> keys = view::parse_key_script(script);
  return {keys.begin(), keys.end()};
}

class Viewer {
 public:
  Viewer(const ViewOptions& o)
      : options_(o),
        scene_json_(scene_json_with_absolute_meshes(o.scene)),
        scene_(parse_scene(scene_json_.dump(), o.scene, ".", &meshes_)),
        methods_(unpriced(render_methods(o.method, o.policy, o.policy_given, "view"))),
        settings_(settings_from(o.emulation)),
        camera_(scene_.camera.view, o.step > 0 ? o.step : default_step(scene_)),
        script_(keys_of(o.keys)) {
    if (o.light_given) {
      check_light_index(scene_, o.light);
      light_choice_ = static_cast<int>(o.light);
    }
    check_memory_estimate(scene_, "view", 40, o.max_memory_gb);
    refuse_non_directory(o.out, "--out");
    if (!o.screenshot.empty()) {
      std::vector<CommandInput> inputs = scene_inputs(scene_);
      if (methods_.policy) inputs.push_back({o.policy, "policy file"});
      refuse_replacing_inputs(o.screenshot, inputs, "--screenshot");
      io::check_output_files({o.screenshot});
      screenshot_destination_ = io::output_destination(o.screenshot);
    }
    settings_.record_draws = true;
    // The first method named is shown first (RenderMethods keeps the policy last).
    if (o.method.rfind("policy", 0) == 0 && methods_.policy) method_ = methods_.methods.size();
  }

  int run() {
    view::ViewerWindow window(scene_.camera.width, scene_.camera.height, "nearcap view: " + options_.scene);
    std::fprintf(stderr, "nearcap view: %s on %s\nkeys: %s\n", options_.scene.c_str(), window.renderer().c_str(),
                 view::key_help().c_str());
    std::fputs(policy_profile_note(methods_, window.renderer()).c_str(), stderr);
    window_ = &window;
    render::LitFrameRenderer renderer;  // in the window's context, its programs kept between frames
    renderer_ = &renderer;
    dirty_ = true;
    while (!window.closed()) {
      std::vector<view::ViewerInput> inputs = window.poll(script_.empty() && !dirty_ ? 0.05 : 0);
      if (!script_.empty()) {
        inputs.push_back(script_.front());
        script_.pop_front();
      }
      bool wait = false;
      for (const view::ViewerInput& in : inputs) wait = apply(in) || wait;
      if (window.closed() || (quit_ && options_.screenshot.empty())) break;
      if (dirty_) draw_frame();
      if (auto r = judge_.poll()) take_overlay(std::move(*r));
      if (wait && show_cracks_) {
        if (auto r = judge_.wait()) take_overlay(std::move(*r));
      }
      // The keys played (or escape among them): the screenshot, then the end.
      if ((script_.empty() || quit_) && !options_.screenshot.empty()) {
        if (show_cracks_)
          if (auto r = judge_.wait()) take_overlay(std::move(*r));
        legend::Image shot;
        window.show(composed(), &shot);
        io::write_output_files({{options_.screenshot, encode_png_rgb(shot.width, shot.height, shot.rgb)}});
        std::printf("screenshot %s (%dx%d): %s\n", options_.screenshot.c_str(), shot.width, shot.height,
                    status_line().c_str());
        break;
      }
    }
    window_ = nullptr;
    return 0;
  }

 private:
  // Applies one command; true when it asks to wait for the crack overlay.
  bool apply(const view::ViewerInput& in) {
    using view::ViewerCommand;
    const double a = in.amount;
    switch (in.command) {
      case ViewerCommand::Forward:
        camera_.move(a, 0, 0);
        break;
      case ViewerCommand::Back:
        camera_.move(-a, 0, 0);
        break;
      case ViewerCommand::Left:
        camera_.move(0, -a, 0);
        break;
      case ViewerCommand::Right:
        camera_.move(0, a, 0);
        break;
      case ViewerCommand::Up:
        camera_.move(0, 0, a);
        break;
      case ViewerCommand::Down:
        camera_.move(0, 0, -a);
        break;
      case ViewerCommand::TurnLeft:
        camera_.turn(5 * a, 0);
        break;
      case ViewerCommand::TurnRight:
        camera_.turn(-5 * a, 0);
        break;
      case ViewerCommand::TurnUp:
        camera_.turn(0, 5 * a);
        break;
      case ViewerCommand::TurnDown:
        camera_.turn(0, -5 * a);
        break;
      case ViewerCommand::SlowerSteps:
        camera_.scale_step(0.5);
        return false;
      case ViewerCommand::FasterSteps:
        camera_.scale_step(2.0);
        return false;
      case ViewerCommand::NextMethod:
        method_ = (method_ + 1) % methods_.count();
        break;
      case ViewerCommand::PreviousMethod:
        method_ = (method_ + methods_.count() - 1) % methods_.count();
        break;
      case ViewerCommand::PickMethod:
        if (static_cast<std::size_t>(in.index) >= methods_.count()) return false;
        method_ = static_cast<std::size_t>(in.index);
        break;
      case ViewerCommand::NextLight:
        light_choice_ = light_choice_ + 1 >= static_cast<int>(scene_.lights.size()) ? -1 : light_choice_ + 1;
        break;
      case ViewerCommand::ToggleCracks:
        show_cracks_ = !show_cracks_;
        if (show_cracks_ && !frames_.empty() && !overlay_for_frame()) start_overlay();
        redraw();
        return false;
      case ViewerCommand::ToggleStatusLine:
        show_status_ = !show_status_;
        redraw();
        return false;
      case ViewerCommand::SaveView:
        save_view();
        return false;
      case ViewerCommand::Quit:
        quit_ = true;
        return false;
      case ViewerCommand::WaitForCracks:
        return true;
    }
    dirty_ = true;
    return false;
  }

  Scene current_scene() const {
    Scene s = scene_;
    s.camera.view = camera_.view();
    return s;
  }

  void draw_frame() {
    dirty_ = false;
    ++frame_id_;
    shown_ = current_scene();
    frames_.clear();
    refused_.clear();
    lit_ = {};
    try {
      gl::DepthFormat depth = settings_.depth;
      for (std::size_t k = 0; k < shown_.lights.size(); ++k) {
        if (light_choice_ >= 0 && static_cast<int>(k) != light_choice_) continue;
        FrameSource source(shown_, k, methods_, settings_);
        frames_.push_back(source.frame(method_));
        depth = source.depth(method_);
      }
      render::LitFrameOptions options;
      options.read_stencils = true;
      lit_ = renderer_->render(shown_, frames_, depth, options);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::Range && e.kind() != ErrorKind::Gl) throw;
      refused_ = e.what();
      frames_.clear();
    }
    emulation_ms_ = 0;
    for (const gl::ShadowFrame& f : frames_) emulation_ms_ += f.times.total();
    if (show_cracks_ && !frames_.empty()) start_overlay();
    redraw();
  }

  bool overlay_for_frame() const { return overlay_ && overlay_->frame_id == frame_id_; }

  void start_overlay() {
    view::CrackOverlayJob job;
    job.frame_id = frame_id_;
    job.scene = shown_;
    for (std::size_t k = 0; k < frames_.size(); ++k) {
      gl::ShadowFrame as_drawn = frames_[k];
      as_drawn.draws.clear();
      as_drawn.stencil = lit_.stencils[k];
      job.frames.push_back(std::move(as_drawn));
    }
    judge_.start(std::move(job));
  }

  void take_overlay(view::CrackOverlayResult r) {
    if (r.frame_id != frame_id_) return;  // the camera moved on
    overlay_ = std::move(r);
    redraw();
  }

  // The status line's fields, in the order shown: the window wraps them
  // (view/status_panel.hpp), stdout gets them on one line.
  std::vector<std::string> status_fields() const {
    std::vector<std::string> f = {
        "[m] " + methods_.name(method_),
        "[l] " + (light_choice_ < 0 ? std::string("all lights") : "light " + std::to_string(light_choice_))};
    if (!refused_.empty()) {
      f.push_back("refused: " + refused_);
      return f;
    }
    f.push_back(fixed(emulation_ms_ + lit_.ms, 1) + " ms (emulation " + fixed(emulation_ms_, 1) + ", GL " +
                fixed(lit_.ms, 1) + ")");
    if (!show_cracks_)
      f.push_back("[c] cracks off");
    else if (!overlay_for_frame())
      f.push_back("[c] cracks: computing...");
    else if (!overlay_->error.empty())
      f.push_back("[c] exact reference refused: " + overlay_->error);
    else
      f.push_back("[c] " + std::to_string(overlay_->wrong) + " wrong px, " + std::to_string(overlay_->cracks) +
                  " cracks (" + fixed(overlay_->ms / 1000, 1) + " s)");
    return f;
  }

  std::string status_line() const {
    std::string s;
    for (const std::string& f : status_fields()) s += (s.empty() ? "" : "  ") + f;
    return s;
  }

  // The method per occluder, when the frame chose one per occluder (the
  // policy): a field per light.
  std::vector<std::string> occluder_fields() const {
    std::vector<std::string> out;
    for (const gl::ShadowFrame& f : frames_) {
      if (!f.mixed) continue;
      std::string s = "light " + std::to_string(f.light) + ":";
      for (const auto& [o, m] : f.object_methods)
        if (shown_.objects[o].occluder) s += " " + object_name(shown_, o) + " " + std::string(to_string(m));
      out.push_back(s);
    }
    return out;
  }

  legend::Image composed() const {
    legend::Image image;
    image.width = shown_.camera.width;
    image.height = shown_.camera.height;
    if (lit_.rgb.size() == static_cast<std::size_t>(image.width) * image.height * 3)
      image.rgb = lit_.rgb;
    else
      image.rgb.assign(static_cast<std::size_t>(image.width) * image.height * 3, 0);
    if (show_cracks_ && overlay_for_frame()) view::paint_overlay(image, *overlay_);
    if (show_status_) view::paint_status(image, {status_fields(), occluder_fields()});
    return image;
  }

  void redraw() {
    if (window_ && !shown_.objects.empty()) window_->show(composed());
  }

  void save_view() {
    const std::filesystem::path dir(options_.out);
    std::filesystem::path file;
    for (int n = 0;; ++n) {
      char name[32];
      std::snprintf(name, sizeof name, "view-%03d.json", n);
      file = dir / name;
      // A new name, and not the screenshot's (through links too), which is written at the end.
      const bool screenshot =
          !options_.screenshot.empty() && io::output_destination(file.string()) == screenshot_destination_;
      if (!std::filesystem::exists(file) && !screenshot) break;
    }
    Json root = scene_json_;
    const Scene s = current_scene();
    root["camera"] = camera_json(s.camera);
    root["description"] = "nearcap view of " + options_.scene + ", saved with method " + methods_.name(method_) +
                          (light_choice_ < 0 ? "" : ", light " + std::to_string(light_choice_));
    io::write_output_files({{file.string(), json_file_text(root)}});
    std::printf("saved %s\n", file.string().c_str());
    std::fflush(stdout);
  }

  const ViewOptions& options_;
  std::string screenshot_destination_;  // the file --screenshot writes (links followed)
  Json scene_json_;
  MeshCache meshes_;
  Scene scene_;
  RenderMethods methods_;
  gl::EmulationSettings settings_;
  view::FlyCamera camera_;
  std::deque<view::ViewerInput> script_;
  bool quit_ = false;  // escape, pressed or played by --keys

  view::ViewerWindow* window_ = nullptr;
  render::LitFrameRenderer* renderer_ = nullptr;
  std::size_t method_ = 0;
  int light_choice_ = -1;  // -1: every light
  bool show_cracks_ = false, show_status_ = true, dirty_ = true;
  std::uint64_t frame_id_ = 0;
  Scene shown_;
  std::vector<gl::ShadowFrame> frames_;
  render::LitFrame lit_;
  double emulation_ms_ = 0;
  std::string refused_;
  view::CrackOverlay judge_;
  std::optional<view::CrackOverlayResult> overlay_;
};

}  // namespace

void register_view(CLI::App& app) {
  auto [cmd, o] =
      add_subcommand<ViewOptions>(app, "view", "an interactive window: the real GL's frame, a fly camera, the cracks",
                                  [](const ViewOptions& v) { Viewer(v).run(); });
  cmd.footer(
      "The window (GLFW) shows the lit frame drawn by the real GL like nearcap render, with a fly camera, keys to "
      "switch method, policy and light, and an overlay of the frame's cracks against the exact reference.\nKeys: " +
      view::key_help());
  add_scene_argument(cmd, o.scene)->required();
  add_optional_light_option(cmd, o.light, o.light_given);
  cmd.add_option("--method", o.method,
                 "the methods the m key cycles through: zpass, zfail, zpplus, zpplus-corrected, preload, atomiczp, "
                 "policy, comma-separated, or all (the six and the policy); the first is shown first")
      ->capture_default_str();
  note_given(cmd.add_option("--policy", o.policy, "the switch policy for the policy method"), o.policy_given)
      ->capture_default_str();
  cmd.add_option("--keys", o.keys,
                 "a key sequence played first, through the same commands as the keys (names as in the key list, "
                 "separated by spaces; 'wait' waits for the crack overlay)");
  cmd.add_option("--screenshot", o.screenshot,
                 "after the key sequence, write the window's pixels as PNG to FILE and exit");
  cmd.add_option("--out", o.out, "directory where the p key saves views (view-NNN.json)")->capture_default_str();
  cmd.add_option("--step", o.step, "distance of one move (default: 1/50 of the scene's diagonal)")
      ->check(CLI::Validator(
          [](std::string& v) {
            char* end = nullptr;
            const double d = std::strtod(v.c_str(), &end);
            return end != v.c_str() && *end == '\0' && d > 0 && std::isfinite(d) ? std::string()
                                                                                 : "must be a positive distance";
          },
          "DISTANCE"));
  add_emulation_options(cmd, o.emulation);
  add_max_memory_option(cmd, o.max_memory_gb);
}

}  // namespace nearcap::cli
