// nearcap cracks SCENE --light K [--method M|all] [...]: the float pipeline's
// methods against the exact reference, one JSON record per method.
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/classification.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/case_comparison.hpp"
#include "nearcap/judge/crack_map.hpp"

namespace nearcap::cli {
namespace {

struct CracksOptions {
  std::string scene;
  std::size_t light = 0;
  std::string method = "all";
  int subpixel_bits = 8;
  std::string depth = "fixed24";
  std::string fill_rule = "bottom-left";
  float guard_band = 1.0f;
  std::string light_projection = "paper";
  double l_near_scale = 1.0;
  std::string zfail_far = "infinite";
  std::string switch_clamp = "clamp";
  bool fma = false;
  std::string out;
  bool table = false;
  double max_memory_gb = 0;
};

// Peak memory per pixel, measured (README "Limits"): the exact reference, one
// emulated frame at a time (depth, stencil, object ids, near-cap copy), and
// one encoded crack image per method.
constexpr double kCracksBytesPerPixel = 30;  // 28.5 (one method) to 30.4 (all five) at 2048x2048
constexpr double kCracksBytesPerPixelPerMethod = 1;

gl::EmulationSettings settings_from(const CracksOptions& o) {
  gl::EmulationSettings s;
  if (o.subpixel_bits < 0 || o.subpixel_bits > 12)
    throw Error(ErrorKind::Usage, "--subpixel-bits " + std::to_string(o.subpixel_bits) + " is not in [0, 12]");
  s.raster.subpixel_bits = o.subpixel_bits;
  s.raster.fill_rule = o.fill_rule == "top-left" ? gl::FillRule::TopLeft : gl::FillRule::BottomLeft;
  if (!(o.guard_band >= 1.0f))
    throw Error(ErrorKind::Usage, "--guard-band must be at least 1 (1 clips x and y at the view volume)");
  s.raster.guard_band = o.guard_band;
  s.depth = o.depth == "fixed24" ? gl::DepthFormat::Fixed24 : gl::DepthFormat::Float32;
  s.arithmetic = o.fma ? gl::Arithmetic::Fused : gl::Arithmetic::Separate;
  s.light_frustum.projection =
      o.light_projection == "paper" ? gl::LightProjection::Paper : gl::LightProjection::GlFrustum;
  if (!(o.l_near_scale > 0 && o.l_near_scale <= 1))
    throw Error(ErrorKind::Usage,
                "--l-near-scale must be in (0, 1] (l_near beyond l_far d / d_max clips the occluder)");
  s.light_frustum.near_scale = o.l_near_scale;
  s.zfail_far = *gl::zfail_far_from_string(o.zfail_far);
  s.switch_clamp = *gl::switch_clamp_from_string(o.switch_clamp);
  return s;
}

nlohmann::json record_json(const gl::ShadowFrame& f, const CrackReport& r, std::size_t case_disagreements) {
  nlohmann::json j;
  j["method"] = std::string(to_string(r.method));
  j["pixels_seen"] = r.pixels_seen;
  j["wrong"] = r.wrong;
  j["wrong_lit"] = r.wrong_lit;
  j["wrong_shadowed"] = r.wrong_shadowed;
  j["count_mismatch"] = r.count_mismatch;
  j["cap_mismatch"] = r.cap_mismatch ? nlohmann::json(*r.cap_mismatch) : nlohmann::json(nullptr);
  j["case_disagreements"] = case_disagreements;
  j["visibility_mismatch"] = r.visibility_mismatch;
  j["ms"] = f.times.total();
  j["pass_ms"] = {{"setup", f.times.setup_ms},
                  {"depth", f.times.depth_ms},
                  {"near_cap", f.times.cap_ms},
                  {"volume", f.times.volume_ms}};
  j["fragments"] = {
      {"depth", f.depth_pass.fragments}, {"near_cap", f.cap_pass.fragments}, {"volume", f.volume_pass.fragments}};
  nlohmann::json cases = nlohmann::json::object();
  for (std::size_t c = 0; c + 1 < kQuadCaseCount; ++c)
    cases[std::string(to_string(static_cast<QuadCase>(c)))] = f.float_cases[c];
  j["float_cases"] = cases;
  j["zfail_objects"] = f.zfail_objects;
  j["fallback"] = f.fallback.empty() ? nlohmann::json(nullptr) : nlohmann::json("zfail: " + f.fallback);
  if (gl::uses_near_cap(f.method) && f.light_frustum.defined)
    j["light_frustum"] = {{"alpha", f.light_frustum.alpha},
                          {"l_near", f.light_frustum.l_near},
                          {"l_far", f.light_frustum.l_far},
                          {"d", f.light_frustum.d},
                          {"d_max", f.light_frustum.d_max}};
  return j;
}

void print_table(const std::vector<nlohmann::json>& records) {
  std::printf("%-17s %9s %7s %9s %9s %8s %8s %7s %9s %9s\n", "method", "seen", "wrong", "wrong-lit", "wrong-shd",
              "count!=", "cap!=", "cases!=", "visib!=", "ms");
  for (const nlohmann::json& r : records) {
    const std::string cap = r["cap_mismatch"].is_null() ? "-" : std::to_string(r["cap_mismatch"].get<std::size_t>());
    std::printf("%-17s %9zu %7zu %9zu %9zu %8zu %8s %7zu %9zu %9.1f%s\n", r["method"].get<std::string>().c_str(),
                r["pixels_seen"].get<std::size_t>(), r["wrong"].get<std::size_t>(), r["wrong_lit"].get<std::size_t>(),
                r["wrong_shadowed"].get<std::size_t>(), r["count_mismatch"].get<std::size_t>(), cap.c_str(),
                r["case_disagreements"].get<std::size_t>(), r["visibility_mismatch"].get<std::size_t>(),
                r["ms"].get<double>(), r["fallback"].is_null() ? "" : "  (fell back to zfail)");
  }
}

void run(const CracksOptions& o) {
  std::vector<gl::ShadowMethod> methods;
  if (o.method == "all") {
    methods.assign(gl::kAllShadowMethods.begin(), gl::kAllShadowMethods.end());
  } else if (const auto m = gl::shadow_method_from_string(o.method)) {
    methods.push_back(*m);
  } else {
    throw Error(ErrorKind::Usage,
                "--method " + o.method + " is not one of zpass, zfail, zpplus, zpplus-corrected, preload, all");
  }
  const gl::EmulationSettings settings = settings_from(o);
  const Scene scene = load_scene(o.scene);
  check_light_index(scene, o.light);
  check_memory_estimate(scene, "cracks",
                        kCracksBytesPerPixel + kCracksBytesPerPixelPerMethod * static_cast<double>(methods.size()),
                        o.max_memory_gb);
  const CameraSpaceScene cs(scene);
  const PixelReference ref = compute_pixel_reference(cs, o.light);
  const SceneClassification classification = classify_scene(cs);
  const std::size_t case_disagreements = compare_engine_cases(cs, classification).total(o.light);

  std::vector<nlohmann::json> records;
  std::vector<io::OutputFile> files;
  const std::filesystem::path dir(o.out);
  for (gl::ShadowMethod m : methods) {
    const gl::ShadowFrame frame = gl::render_shadow_frame(scene, o.light, m, settings);
    const CrackReport report = judge_frame(frame, ref);
    records.push_back(record_json(frame, report, case_disagreements));
    if (!o.out.empty()) {
      const std::string name = methods.size() == 1 ? "cracks.png" : "cracks-" + std::string(to_string(m)) + ".png";
      files.push_back({(dir / name).string(), crack_png(cs, ref, report)});
    }
  }
  nlohmann::json root;
  if (methods.size() == 1) {
    root = records.front();
  } else {
    root["methods"] = records;
  }
  if (!o.out.empty()) {
    nlohmann::json full = root;
    full["scene"] = scene.source;
    full["light"] = o.light;
    full["reference_ms"] = ref.setup_ms + ref.trace_ms;
    files.push_back({(dir / "cracks.json").string(), full.dump(1) + "\n"});
    io::write_output_files(files);
  }
  if (o.table) {
    print_table(records);
    const nlohmann::json& cases = records.front()["float_cases"];
    std::printf("float engine's cases for light %zu:", o.light);
    for (const char* c : {"A", "B", "C1", "C2", "D"}) std::printf(" %s %zu", c, cases[c].get<std::size_t>());
    std::printf("\n");
    std::fflush(stdout);
    print_case_legend(std::cout);
  } else
    std::cout << root.dump() << "\n";
}

}  // namespace

void register_cracks(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "cracks",
      "emulate the float GL pipeline's shadow methods and count the pixels they get wrong against the exact "
      "reference: one JSON record per method (or a table with --table); with --out DIR, DIR/cracks.png "
      "(cracks-METHOD.png for several methods) and DIR/cracks.json");
  auto o = std::make_shared<CracksOptions>();
  cmd->add_option("scene", o->scene, "scene file (JSON)")->required();
  add_light_option(*cmd, o->light);
  cmd->add_option("--method", o->method, "zpass, zfail, zpplus, zpplus-corrected, preload or all")
      ->capture_default_str();
  cmd->add_option("--subpixel-bits", o->subpixel_bits, "fixed-point sub-pixel bits of the rasterizer")
      ->capture_default_str();
  cmd->add_option("--depth", o->depth, "depth buffer: fixed24 or float32")
      ->check(CLI::IsMember({"fixed24", "float32"}))
      ->capture_default_str();
  cmd->add_option("--fill-rule", o->fill_rule,
                  "pixel centres on an edge: bottom-left (llvmpipe's, GL window coordinates) or top-left")
      ->check(CLI::IsMember({"top-left", "bottom-left"}))
      ->capture_default_str();
  cmd->add_option("--guard-band", o->guard_band,
                  "x/y clipping at |x|,|y| <= G w: 1 is llvmpipe's view-volume clip, larger a GPU-style guard band")
      ->capture_default_str();
  cmd->add_option("--light-projection", o->light_projection, "P_l formulation: paper or glfrustum")
      ->check(CLI::IsMember({"paper", "glfrustum"}))
      ->capture_default_str();
  cmd->add_option("--l-near-scale", o->l_near_scale, "l_near = scale * l_far * min(d / d_max, 1/2)")
      ->capture_default_str();
  cmd->add_option("--zfail-far", o->zfail_far,
                  "zfail's far plane: infinite, clamp (GL_DEPTH_CLAMP) or clamp-far (far plane only)")
      ->check(CLI::IsMember({"infinite", "clamp", "clamp-far"}))
      ->capture_default_str();
  cmd->add_option("--switch-clamp", o->switch_clamp,
                  "depth clamp of ZP+'s switch to zfail (case D, no light frustum): clamp or clamp-far")
      ->check(CLI::IsMember({"clamp", "clamp-far"}))
      ->capture_default_str();
  cmd->add_flag("--fma", o->fma, "vertex transforms with fused multiply-add");
  cmd->add_option("--out", o->out, "output directory for the crack images and cracks.json (created if missing)");
  cmd->add_flag("--table", o->table, "print a human-readable table instead of JSON");
  add_max_memory_option(*cmd, o->max_memory_gb);
  cmd->callback([o] { run(*o); });
}

}  // namespace nearcap::cli
