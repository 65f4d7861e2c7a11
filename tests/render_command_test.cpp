// `nearcap render` (--compare, --path, --bench, the lit frames) and the lit
// frame renderer, run on Mesa's llvmpipe through a headless EGL context.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "llvmpipe_fixture.hpp"
#include "nearcap/analysis/frame_time_drift.hpp"
#include "nearcap/analysis/kept_choices.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/image_io.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/render/egl_context.hpp"
#include "nearcap/render/gl_frame_replay.hpp"
#include "nearcap/render/lit_frame.hpp"

namespace nearcap {
namespace {

TEST(RenderCommand, CompareGivesOneRecordPerMethod) {
  const test::CliResult r =
      test::run_cli("render data/scenes/near_split.json --light 0 --compare --method zpass,zfail", "render");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j.at("renderer").get<std::string>().empty());
  ASSERT_EQ(j.at("methods").size(), 2u);
  for (const nlohmann::json& m : j["methods"])
    for (const char* key : {"gl_vs_emulation", "objects_differ", "near_cap_differ", "gl_vs_exact", "cracks",
                            "emulation_vs_exact", "ms", "emulation_ms"})
      EXPECT_TRUE(m.at(key).is_number()) << key;
  // Z-pass is wrong where the near plane cuts the shadow, on the real GL too.
  EXPECT_GT(j["methods"][0]["gl_vs_exact"].get<int>(), 100000);
  EXPECT_GT(j["methods"][0]["cracks"].get<int>(), 10000);
  EXPECT_EQ(j["methods"][1]["cracks"], 0);
}

// The llvmpipe model from the command line: exact_camera's ground ties,
// 307 stencil differences with the defaults, none with the model.
TEST(RenderCommand, TheLlvmpipeModelOptions) {
  const std::string base = "render data/scenes/exact_camera.json --light 0 --compare --method zpass,zfail";
  const test::CliResult defaults = test::run_cli(base, "render_model");
  if (defaults.exit_code == 2 && defaults.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << defaults.err;
  ASSERT_EQ(defaults.exit_code, 0) << defaults.err;
  const test::CliResult model =
      test::run_cli(base + " --viewport llvmpipe --depth-interpolation llvmpipe --clipper mesa", "render_model");
  ASSERT_EQ(model.exit_code, 0) << model.err;
  const nlohmann::json a = nlohmann::json::parse(defaults.out), b = nlohmann::json::parse(model.out);
  EXPECT_GT(a["methods"][0]["gl_vs_emulation"].get<int>(), 100);
  for (const nlohmann::json& m : b["methods"]) EXPECT_EQ(m["gl_vs_emulation"], 0) << m;
  const test::CliResult bad = test::run_cli(base + " --clipper gl", "render_model");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--clipper"), std::string::npos) << bad.err;
}

// The shipped switch policy on the real GL, where the paper's corrected ZP+
// switches to Z-fail with depth clamp (case D): as right as Z-fail there,
// the emulation's pixel for pixel, and the record says each occluder's method.
TEST(RenderCommand, ThePolicyOnTheRealGl) {
  const test::CliResult r =
      test::run_cli("render data/scenes/case_d.json --light 0 --compare --method zfail,policy", "render_policy");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.at("methods").size(), 2u);
  const nlohmann::json &zfail = j["methods"][0], &policy = j["methods"][1];
  EXPECT_EQ(policy["method"], "policy");
  EXPECT_LE(policy["gl_vs_exact"].get<int>(), zfail["gl_vs_exact"].get<int>());
  EXPECT_EQ(policy["cracks"], 0);
  EXPECT_EQ(policy["gl_vs_emulation"], 0);
  ASSERT_EQ(policy.at("occluders").size(), 1u);
  EXPECT_FALSE(policy["occluders"][0]["why"].get<std::string>().empty());
}

TEST(RenderCommand, WithoutAnEglDriverItSaysWhatToInstall) {
  const test::CliResult r = test::run_cli("render data/scenes/default.json --light 0 --compare --method zpass",
                                          "render_no_egl", "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("nearcap: error (gl): EGL", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("libgl1-mesa-dri"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

TEST(RenderCommand, APathWritesEveryFrameAndItsTime) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_render_path_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const test::CliResult r = test::run_cli(
      "render --path data/paths/eye_in_shadow.json --method zpass,zfail --out '" + dir.string() + "'", "render_path");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("x Z-pass"), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(test::slurp(dir / "render.json"));
  ASSERT_EQ(j["methods"].size(), 2u);
  for (const nlohmann::json& m : j["methods"]) {
    ASSERT_EQ(m["frames"].size(), 60u);  // the path's frames
    EXPECT_GT(m["mean_ms"].get<double>(), 0.0);
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "zfail" / "frame-0059.png"));
  // Off a terminal the progress comes as lines (no carriage return): one at
  // each tenth of the frames, the last among them.
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("render: frame 60/60, "), std::string::npos) << r.err;
  std::size_t lines = 0;
  for (std::size_t at = r.err.find("render: frame "); at != std::string::npos;
       at = r.err.find("render: frame ", at + 1))
    ++lines;
  EXPECT_EQ(lines, 10u) << r.err;
  std::filesystem::remove_all(dir);
}

// --bench: a row per frame and method with the passes' times, the plot, the
// breakdown on stdout; --one-sided-stencil draws the same frames.
TEST(RenderCommand, BenchWritesEachFramesPassTimesAndThePlot) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_render_bench_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const test::CliResult r =
      test::run_cli("render --path data/paths/eye_in_shadow.json --method zpass,zpplus --bench --out '" +
                        (dir / "two").string() + "'",
                    "render_bench");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("depth "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" + stencil "), std::string::npos) << r.out;
  const std::string csv = test::slurp(dir / "two" / "bench.csv");
  EXPECT_EQ(csv.rfind("frame,method,stencil,vertex_stage,layout,culling,ms,depth_ms,stencil_ms,lit_ms,gpu_depth_ms,"
                      "gpu_stencil_ms,gpu_lit_ms,cpu_ms,end_to_end_ms\n",
                      0),
            0u)
      << csv.substr(0, 80);
  // The header, 60 frames of 2 methods and Z-pass drawn again (the noise floor).
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 3 * 60);
  EXPECT_NE(csv.find("\n59,zpplus,two-sided,"), std::string::npos);
  EXPECT_NE(csv.find("\n59,zpass#again,two-sided,"), std::string::npos);
  EXPECT_GT(std::filesystem::file_size(dir / "two" / "bench.png"), 1000u);
  const nlohmann::json j = nlohmann::json::parse(test::slurp(dir / "two" / "render.json"));
  for (const nlohmann::json& m : j["methods"]) {
    // The timer query ran (what it measures is the driver's: llvmpipe's is
    // the CPU clock around its rasterizer's work, which one short frame's
    // pass could leave unmoved).
    double gpu_stencil_ms = 0;
    for (const nlohmann::json& f : m["frames"]) {
      const nlohmann::json& p = f["passes"];
      const double sum = p["depth_ms"].get<double>() + p["stencil_ms"].get<double>() + p["lit_ms"].get<double>();
      EXPECT_GT(p["stencil_ms"].get<double>(), 0.0);
      EXPECT_GE(p["gpu_stencil_ms"].get<double>(), 0.0);
      gpu_stencil_ms += p["gpu_stencil_ms"].get<double>();
      EXPECT_LE(sum, f["ms"].get<double>() * 1.0001 + 1e-3);  // the passes lie within the frame's time
    }
    EXPECT_GT(gpu_stencil_ms, 0.0) << m["method"];
  }
  const test::CliResult one = test::run_cli(
      "render --path data/paths/eye_in_shadow.json --method zpass --bench "
      "--one-sided-stencil --side-strips --stencil --out '" +
          (dir / "one").string() + "'",
      "render_bench");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_NE(test::slurp(dir / "one" / "bench.csv").find("\n0,zpass,one-sided,glsl,side-strips,"), std::string::npos);
  EXPECT_NE(csv.find("\n0,zpass,two-sided,glsl,triangles,"), std::string::npos);
  const test::CliResult compare =
      test::run_cli("render data/scenes/default.json --light 0 --compare --bench", "render_bench");
  EXPECT_EQ(compare.exit_code, 2);
  EXPECT_NE(compare.err.find("--bench"), std::string::npos) << compare.err;
  std::filesystem::remove_all(dir);
}

// DIR (made anew) holding path.json: the bundled path NAME with `frames`
// frames, its scene data/scenes/SCENE.json by absolute name, and the
// viewport width x height where given.
void write_path_copy(const std::filesystem::path& dir, const std::string& name, const std::string& scene, int frames,
                     int width = 0, int height = 0) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  nlohmann::json path =
      nlohmann::json::parse(test::slurp(std::string(NEARCAP_SOURCE_DIR) + "/data/paths/" + name + ".json"));
  path["scene"] = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + scene + ".json";
  path["frames"] = frames;
  if (width > 0) path["width"] = width;
  if (height > 0) path["height"] = height;
  std::ofstream(dir / "path.json") << path.dump();
}

// --bench along a path with the policy: each of its frames' price (the
// device profile's, its lights summed) and the end-to-end time predicted
// before drawing it: that price times the measured/priced of the frame
// before it (1 for the first: FrameTimeDrift's path window), plus the
// frame's decision; the medians of both errors.
TEST(RenderCommand, BenchPredictsThePolicysFramesFromTheFramesBefore) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_render_predict_" + std::to_string(::getpid()));
  write_path_copy(dir, "eye_in_shadow", "room", 6);
  const test::CliResult r = test::run_cli("render --path '" + (dir / "path.json").string() +
                                              "' --method zfail,policy --bench --out '" + (dir / "out").string() + "'",
                                          "render_predict");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("predicted within "), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(test::slurp(dir / "out" / "render.json"));
  std::size_t checked = 0;
  for (const nlohmann::json& m : j["methods"]) {
    if (m["method"] != "policy") {
      EXPECT_FALSE(m["frames"][0].contains("predicted_ms")) << m["method"];
      continue;
    }
    analysis::FrameTimeDrift drift(analysis::FrameTimeDrift::kPathWindow);  // a path's, as render keeps it
    for (const nlohmann::json& f : m["frames"]) {
      double decision = 0, lights_priced = 0;
      for (const nlohmann::json& light : f["cpu"]["lights"]) {
        decision += light["decision_ms"].get<double>();
        lights_priced += light.at("profile_ms").get<double>();
      }
      const double priced = f.at("profile_ms").get<double>(), measured = f["end_to_end_ms"].get<double>();
      EXPECT_GT(priced, 0);
      EXPECT_DOUBLE_EQ(priced, lights_priced);
      EXPECT_NEAR(f.at("predicted_ms").get<double>(), priced * drift.scale() + decision, 1e-9 * measured);
      drift.observe(priced, measured - decision);
      ++checked;
    }
    EXPECT_GE(m.at("predicted_median_error").get<double>(), 0);
    EXPECT_GE(m.at("profile_median_error").get<double>(), 0);
  }
  EXPECT_EQ(checked, 6u);
  std::filesystem::remove_all(dir);
}

// --bench along a path keeps the policy's choices as a frame loop does
// (kept_choices.hpp): frames priced, a choice kept for at most
// KeptChoices::kMaxKeptFrames frames after, and the same frames kept whether
// the policy is drawn alone (then --bench's second draw of the first method
// is the policy's, which decides again from its own copy of the kept
// choices) or beside Z-fail (drawn first and again).
TEST(RenderCommand, BenchKeepsThePolicysChoicesAsAFrameLoopDoes) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_render_kept_" + std::to_string(::getpid()));
  constexpr int kFrames = 20;
  write_path_copy(dir, "near_plane_sweep", "room_side_light", kFrames, 64, 48);
  std::vector<std::vector<int>> runs;
  for (const char* methods : {"zfail,policy", "policy"}) {
    const std::string out = (dir / methods).string();
    const test::CliResult r = test::run_cli(
        "render --path '" + (dir / "path.json").string() + "' --method " + methods + " --bench --out '" + out + "'",
        "render_kept");
    if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
      GTEST_SKIP() << "no headless OpenGL here: " << r.err;
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(test::slurp(std::filesystem::path(out) / "render.json"));
    std::vector<int> since;
    for (const nlohmann::json& m : j["methods"]) {
      if (m["method"] != "policy") continue;
      for (const nlohmann::json& f : m["frames"]) since.push_back(f["cpu"]["lights"][0].at("frames_since_priced"));
    }
    ASSERT_EQ(since.size(), static_cast<std::size_t>(kFrames)) << methods;
    for (int k : since) EXPECT_LE(k, analysis::KeptChoices::kMaxKeptFrames) << methods;
    // Priced and kept frames both (the warm-up draw before the first frame
    // decides too: the first frame may keep its choice).
    EXPECT_GT(std::count(since.begin(), since.end(), 0), 0) << methods;
    EXPECT_GT(std::count_if(since.begin(), since.end(), [](int k) { return k > 0; }), 0) << methods;
    for (std::size_t f = 1; f < since.size(); ++f) {
      if (since[f] > 0) {
        EXPECT_EQ(since[f], since[f - 1] + 1) << methods << " frame " << f;
      }
    }
    runs.push_back(since);
  }
  EXPECT_EQ(runs[0], runs[1]);
  std::filesystem::remove_all(dir);
}

// --bench with zpass and atomiczp: Z-pass's frame drawn once more with
// GL_DEPTH_CLAMP on its sides (the zpass#depth-clamp rows, render.json's
// depth_clamp and a summary line), so that AtomicZP's cost over Z-pass
// splits into the clamp's and the eye-count pass's; without atomiczp, no
// such rows.
TEST(RenderCommand, BenchTimesZPassSidesWithDepthClampBesideAtomicZP) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_render_clamp_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const test::CliResult r = test::run_cli(
      "render data/scenes/eye_in_shadow.json --light 0 --method zpass,atomiczp "
      "--bench --out '" +
          (dir / "both").string() + "'",
      "render_clamp");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = test::slurp(dir / "both" / "bench.csv");
  EXPECT_NE(csv.find("\n0,zpass,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n0,zpass#depth-clamp,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n0,atomiczp,"), std::string::npos) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 4) << csv;  // zpass, again, clamped, atomiczp
  EXPECT_NE(r.out.find("bench: depth clamp:"), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(test::slurp(dir / "both" / "render.json"));
  ASSERT_TRUE(j.contains("depth_clamp")) << j.dump();
  EXPECT_EQ(j["depth_clamp"]["frames"], 1);
  EXPECT_GT(j["depth_clamp"]["mean_stencil_ms_clamped"].get<double>(), 0.0);
  EXPECT_GT(j["depth_clamp"]["mean_stencil_ms"].get<double>(), 0.0);
  const test::CliResult zpass_only =
      test::run_cli("render data/scenes/eye_in_shadow.json --light 0 --method zpass,zfail --bench --out '" +
                        (dir / "no").string() + "'",
                    "render_clamp");
  ASSERT_EQ(zpass_only.exit_code, 0) << zpass_only.err;
  EXPECT_EQ(test::slurp(dir / "no" / "bench.csv").find("depth-clamp"), std::string::npos);
  EXPECT_EQ(zpass_only.out.find("bench: depth clamp:"), std::string::npos) << zpass_only.out;
  std::filesystem::remove_all(dir);
}

// --bench's CPU work: bench.csv's cpu_ms and end_to_end_ms on every row (the
// noise floor's second Z-pass too), end to end at least the CPU work, and
// render.json's breakdown per light and occluder within the frame's cpu_ms;
// Z-pass builds no cap, ZP+ with the clipped-sides cap does.
TEST(RenderCommand, BenchTimesTheCpuWorkAndTheFrameEndToEnd) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_render_cpu_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const test::CliResult r = test::run_cli(
      "render data/scenes/eye_in_shadow.json --light 0 --method zpass,zpplus-corrected,policy "
      "--light-projection clipped-sides --bench --out '" +
          dir.string() + "'",
      "render_cpu");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("noise floor: zpass drawn twice per frame"), std::string::npos) << r.out;
  // bench.csv, read by its header's names.
  std::istringstream csv(test::slurp(dir / "bench.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  auto split = [](const std::string& text) {
    std::vector<std::string> cells;
    std::istringstream in(text);
    for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
    return cells;
  };
  const std::vector<std::string> header = split(line);
  const auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t method = column("method"), cpu = column("cpu_ms"), end_to_end = column("end_to_end_ms");
  ASSERT_LT(cpu, header.size()) << line;
  ASSERT_LT(end_to_end, header.size()) << line;
  std::vector<std::string> methods;
  while (std::getline(csv, line)) {
    const std::vector<std::string> cells = split(line);
    ASSERT_EQ(cells.size(), header.size()) << line;
    methods.push_back(cells[method]);
    const double c = std::stod(cells[cpu]), e = std::stod(cells[end_to_end]);
    EXPECT_TRUE(std::isfinite(c) && c >= 0) << line;
    EXPECT_TRUE(std::isfinite(e) && e >= 0) << line;
    EXPECT_GE(e * (1 + 1e-5), c) << line;  // the CSV's 6 significant digits
  }
  EXPECT_EQ(methods, (std::vector<std::string>{"zpass", "zpass#again", "zpplus-corrected", "policy"}));
  const nlohmann::json j = nlohmann::json::parse(test::slurp(dir / "render.json"));
  ASSERT_EQ(j["methods"].size(), 3u);
  EXPECT_EQ(j["noise_floor"]["method"], "zpass");
  EXPECT_EQ(j["noise_floor"]["frames"], 1u);
  for (const nlohmann::json& m : j["methods"]) {
    const std::string name = m["method"].get<std::string>();
    ASSERT_EQ(m["frames"].size(), 1u) << name;
    const nlohmann::json& f = m["frames"][0];
    const double cpu_ms = f["cpu_ms"].get<double>(), end_to_end_ms = f["end_to_end_ms"].get<double>();
    EXPECT_GE(end_to_end_ms, cpu_ms) << name;
    const nlohmann::json& work = f["cpu"];
    double sum = work["upload_ms"].get<double>();
    ASSERT_EQ(work["lights"].size(), 1u) << name;
    for (const nlohmann::json& light : work["lights"]) {
      EXPECT_EQ(light["light"], 0u);
      sum += light["decision_ms"].get<double>() + light["near_plane_ms"].get<double>() +
             light["light_frustum_ms"].get<double>();
      if (name != "policy") {
        EXPECT_EQ(light["decision_ms"].get<double>(), 0.0) << name;
      }
      ASSERT_FALSE(light["occluders"].empty()) << name;
      for (const nlohmann::json& oc : light["occluders"]) {
        const double silhouette = oc["silhouette_ms"].get<double>(), cap = oc["cap_build_ms"].get<double>();
        EXPECT_TRUE(std::isfinite(silhouette) && silhouette >= 0) << oc;
        EXPECT_TRUE(std::isfinite(cap) && cap >= 0) << oc;
        const std::string chosen = oc["method"].get<std::string>();
        if (name != "policy") {
          EXPECT_EQ(chosen, name) << oc;
        }
        if (chosen == "zpass" || chosen == "zfail") {
          EXPECT_EQ(cap, 0.0) << name << ": " << oc;
        }
        sum += silhouette + cap;
      }
    }
    EXPECT_LE(sum, cpu_ms * (1 + 1e-12)) << name << ": " << work;
    // The policy's mean decision: its one frame's.
    if (name == "policy") {
      const double decision = work["lights"][0]["decision_ms"].get<double>();
      ASSERT_GT(decision, 0.0);
      EXPECT_DOUBLE_EQ(m.at("mean_decision_ms").get<double>(), decision);
    } else {
      EXPECT_FALSE(m.contains("mean_decision_ms")) << name;
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(RenderCommand, UsageErrorsNameTheMissingOption) {
  const test::CliResult lit = test::run_cli("render data/scenes/default.json --light 0", "render_usage");
  EXPECT_EQ(lit.exit_code, 2);
  EXPECT_NE(lit.err.find("--out"), std::string::npos) << lit.err;
  const test::CliResult compare = test::run_cli("render data/scenes/default.json --compare", "render_usage2");
  EXPECT_EQ(compare.exit_code, 2);
  EXPECT_NE(compare.err.find("--light"), std::string::npos) << compare.err;
  const test::CliResult both =
      test::run_cli("render data/scenes/default.json --path data/paths/zoom.json --out x", "render_usage3");
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(both.err.find("--path"), std::string::npos) << both.err;
}

}  // namespace
}  // namespace nearcap

namespace nearcap {
namespace {

class LitFrameTest : public test::LlvmpipeTest {};

// The lit frame's light is gated by that light's stencil: where the real
// stencil is 0 the pixel is exactly as lit as with no shadow volumes at all,
// where it is not it gets the ambient term only (darker, or as dark where the
// surface faces away from the light).
// One-sided stencil (each two-sided draw as a back-culled and a
// front-culled draw) leaves every light's stencil and the lit frame as
// two-sided stencil does, for every method (the counts per fragment are the
// same operations), but for one pixel of near_cap_bunny_wall with Z-pass's
// sides (Z-pass and both ZP+): llvmpipe culls or counts one side fragment
// there differently with culling on than its two-sided stencil counts it
// (not traced further).  And the pass times are measured when asked.
TEST_F(LitFrameTest, OneSidedStencilDrawsTheSameFrame) {
  for (const char* name : {"near_split.json", "eye_in_shadow.json", "near_cap_bunny_wall.json", "twisted.json"}) {
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    for (gl::ShadowMethod m : gl::kAllShadowMethods) {
      SCOPED_TRACE(std::string(name) + ", " + std::string(gl::to_string(m)));
      gl::EmulationSettings settings;
      settings.record_draws = true;
      const gl::ShadowFrame frame = gl::render_shadow_frame(scene, 0, m, settings);
      render::LitFrameOptions two, one;
      two.read_stencils = one.read_stencils = true;
      one.one_sided_stencil = true;
      one.pass_times = true;
      const render::LitFrame a = render::render_lit_frame(scene, {frame}, settings.depth, two);
      const render::LitFrame b = render::render_lit_frame(scene, {frame}, settings.depth, one);
      ASSERT_EQ(a.stencils.size(), 1u);
      ASSERT_EQ(b.stencils.size(), 1u);
      std::size_t differ = 0;
      for (std::size_t p = 0; p < a.stencils[0].size(); ++p) differ += a.stencils[0][p] != b.stencils[0][p];
      const bool bunny_sides = std::string(name) == "near_cap_bunny_wall.json" && m != gl::ShadowMethod::ZFail &&
                               m != gl::ShadowMethod::Preload;
      EXPECT_LE(differ, bunny_sides ? 1u : 0u);
      if (differ == 0) {
        EXPECT_EQ(a.rgb, b.rgb);
      }
      EXPECT_EQ(a.passes.stencil_ms, 0.0);  // not asked
      EXPECT_GT(b.passes.depth_ms, 0.0);
      EXPECT_GT(b.passes.stencil_ms, 0.0);
      EXPECT_GT(b.passes.lit_ms, 0.0);
    }
  }
}

TEST_F(LitFrameTest, EachLightIsAddedWhereItsStencilIsZero) {
  const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/near_split.json");
  gl::EmulationSettings settings;
  settings.record_draws = true;
  const gl::ShadowFrame frame = gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZFail, settings);
  gl::ShadowFrame unshadowed = frame;  // the depth pre-pass alone: no volume, stencil 0 everywhere
  unshadowed.draws.erase(std::remove_if(unshadowed.draws.begin(), unshadowed.draws.end(),
                                        [](const gl::DrawCall& d) { return d.pass != gl::DrawPass::Depth; }),
                         unshadowed.draws.end());
  const render::LitFrame lit = render::render_lit_frame(scene, {frame}, settings.depth);
  const render::LitFrame bright = render::render_lit_frame(scene, {unshadowed}, settings.depth);
  render::GlFrameReplay replay(frame.width, frame.height, settings.depth);
  const render::ReplayedFrame stencil = replay.replay(frame.draws);
  ASSERT_EQ(lit.rgb.size(), static_cast<std::size_t>(frame.width) * frame.height * 3);
  std::size_t shadowed = 0, darker = 0, lit_equal = 0, lit_pixels = 0;
  for (int j = 0; j < frame.height; ++j)
    for (int i = 0; i < frame.width; ++i) {
      const std::size_t gl_index = static_cast<std::size_t>(j) * frame.width + i;
      const std::size_t png_index = (static_cast<std::size_t>(frame.height - 1 - j) * frame.width + i) * 3;
      if (stencil.object[gl_index] < 0) continue;
      int sum_lit = 0, sum_bright = 0;
      for (int c = 0; c < 3; ++c) {
        sum_lit += lit.rgb[png_index + c];
        sum_bright += bright.rgb[png_index + c];
      }
      if (stencil.stencil[gl_index] == 0) {
        ++lit_pixels;
        lit_equal += sum_lit == sum_bright;
      } else {
        ++shadowed;
        darker += sum_lit < sum_bright;
        EXPECT_LE(sum_lit, sum_bright);
      }
    }
  EXPECT_EQ(lit_equal, lit_pixels);
  EXPECT_GT(shadowed, 10000u);
  EXPECT_GT(darker, shadowed / 2) << "the shadow darkens what the light reaches";
}

TEST(RenderCommand, WritesTheLitFrameOfEachMethod) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_render_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const test::CliResult r =
      test::run_cli("render data/scenes/room.json --method zpass,zfail --out '" + dir.string() + "'", "render_lit");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"frame-zpass.png", "frame-zfail.png"}) {
    const std::string png = test::slurp(dir / name);
    ASSERT_GT(png.size(), 8u) << name;
    EXPECT_EQ(png.substr(1, 3), "PNG") << name;
  }
  EXPECT_EQ(nlohmann::json::parse(test::slurp(dir / "render.json"))["methods"].size(), 2u);
  std::filesystem::remove_all(dir);
}

// --stencil: each light's real stencil beside the lit frame, the emulation's
// but for the depth near-ties the comparison above explains.
TEST(RenderCommand, TheLitFramesStencilsPerLight) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_render_st_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const test::CliResult r = test::run_cli(
      "render data/scenes/near_split.json --method zfail --stencil --out '" + dir.string() + "'", "render_stencil");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int width = 0, height = 0;
  const std::vector<std::uint16_t> real =
      decode_pgm16(test::slurp(dir / "stencil-zfail-light-0.pgm"), "stencil", &width, &height);
  const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/near_split.json");
  ASSERT_EQ(width, scene.camera.width);
  ASSERT_EQ(height, scene.camera.height);
  const gl::ShadowFrame emulated = gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZFail);
  std::size_t differ = 0, shadowed = 0;
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const std::uint16_t v = real[static_cast<std::size_t>(height - 1 - j) * width + i];  // PGM: top row first
      differ += v != emulated.stencil[emulated.index(i, j)];
      shadowed += v != 0;
    }
  EXPECT_GT(shadowed, 10000u);
  EXPECT_LE(differ, 8u);
  const test::CliResult both = test::run_cli(
      "render data/scenes/near_split.json --light 0 --compare --stencil --method zfail", "render_stencil_usage");
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(both.err.find("--stencil goes with the lit frames"), std::string::npos) << both.err;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace nearcap
