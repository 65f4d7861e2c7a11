// The program end to end on bundled scenes: documented JSON layouts, counts
// that agree with each other, the main job's outputs.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <set>

#include "cli_support.hpp"
#include "nearcap/raytrace/shadow_ray_tracer.hpp"

namespace nearcap {
namespace {

TEST(ClassifyCommand, JsonLayoutOnEveryBundledScene) {
  for (const char* scene :
       {"default", "no_near_clip", "eye_in_shadow", "near_split", "case_d", "twisted", "exact_camera"}) {
    const test::CliResult r = test::run_cli(std::string("classify --json data/scenes/") + scene + ".json", "classify");
    ASSERT_EQ(r.exit_code, 0) << scene << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_FALSE(j.at("lights").empty());
    for (const auto& light : j.at("lights"))
      for (const auto& o : light.at("objects")) {
        const std::size_t n = o.at("silhouette_edges").get<std::size_t>();
        EXPECT_EQ(n, o.at("edges").size()) << scene;
        std::size_t sum = 0;
        for (const char* c : {"A", "B", "C1", "C2", "D", "degenerate"}) sum += o.at("cases").at(c).get<std::size_t>();
        EXPECT_EQ(sum, n) << scene;
        for (const auto& e : o.at("edges")) {
          const auto v = e.at("v");
          EXPECT_LT(v.at(0).get<std::size_t>(), v.at(1).get<std::size_t>()) << "smallest index first";
        }
      }
  }
}

TEST(ClassifyCommand, CaseDSceneHasCaseD) {
  const test::CliResult r = test::run_cli("classify --json data/scenes/case_d.json", "classify_d");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_GT(j["lights"][0]["objects"][0]["cases"]["D"].get<int>(), 0);
}

TEST(CapCommand, AreasAndCountsAgreeWithTheReference) {
  // near_split.json: the near rectangle is partly in shadow (Figure 4).
  const test::CliResult cap = test::run_cli("cap data/scenes/near_split.json --light 0", "cap");
  ASSERT_EQ(cap.exit_code, 0) << cap.err;
  const auto j = nlohmann::json::parse(cap.out);
  double area_shadow = 0, area = 0;
  for (const auto& f : j.at("faces")) {
    area += f.at("area").get<double>();
    if (f.at("count").get<int>() > 0) area_shadow += f.at("area").get<double>();
    for (const auto& p : f.at("outer")) EXPECT_TRUE(p.at("x").is_string());
  }
  ASSERT_GT(area, 0);
  const double fraction = area_shadow / area;
  EXPECT_GT(fraction, 0.0);
  EXPECT_LT(fraction, 1.0);
  // The per-pixel reference: the fraction of pixel centres with cap > 0 is the
  // area fraction up to the pixel grid (640 x 480).  Point sampling can only
  // misjudge the pixels the region's outline crosses: about its length in
  // pixels, under two frame widths (1280 of 640 x 480 pixels, 2/480) here.
  const auto dir = test::temp_path("nearcap_cli_test_ref");
  const test::CliResult ref =
      test::run_cli("reference data/scenes/near_split.json --light 0 --out " + dir.string(), "ref");
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  const auto summary = nlohmann::json::parse(ref.out);
  const double pixel_fraction = summary.at("pixels_cap_nonzero").get<double>() / (640.0 * 480.0);
  EXPECT_NEAR(pixel_fraction, fraction, 2.0 / 480.0);
  std::filesystem::remove_all(dir);
}

TEST(CapCommand, SvgIsWritten) {
  const auto svg = test::temp_path("nearcap_cli_test_cap") += ".svg";
  std::filesystem::remove(svg);
  const test::CliResult r = test::run_cli("cap data/scenes/case_d.json --light 0 --svg " + svg.string(), "svg");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = test::slurp(svg);
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("count 1"), std::string::npos);
  std::filesystem::remove(svg);
}

TEST(CapCommand, AFailingSecondOutputLeavesNoFirstOutput) {
  // The SVG's parent is a regular file: no directory can be made there.
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_cli_test_partial_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "a_file") << "";
  const test::CliResult r = test::run_cli("cap data/scenes/case_d.json --light 0 --out " + (dir / "cap.json").string() +
                                              " --svg " + (dir / "a_file" / "cap.svg").string(),
                                          "partial");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("error (io)"), std::string::npos) << r.err;
  std::size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    ++entries;
    EXPECT_EQ(e.path().filename(), "a_file") << "no partial output, no temporary";
  }
  EXPECT_EQ(entries, 1u);
  std::filesystem::remove_all(dir);
}

TEST(Cli, MissingSceneExitsWithTwo) {
  const test::CliResult r = test::run_cli("classify data/scenes/does_not_exist.json", "missing");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("does_not_exist.json"), std::string::npos) << r.err;
}

// A fuzz seed scene as a file the program can load: its "box.off" meshes point
// at fuzz/meshes/box.off (the fuzzer's mesh directory), not at the seed's folder.
std::string materialise_seed(const std::string& name) {
  auto j = nlohmann::json::parse(test::slurp(std::string(NEARCAP_SOURCE_DIR) + "/fuzz/seeds/scene/" + name));
  for (auto& o : j.at("objects")) o["mesh"] = std::string(NEARCAP_SOURCE_DIR) + "/fuzz/meshes/box.off";
  const auto path =
      std::filesystem::temp_directory_path() / ("nearcap_cli_seed_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(path) << j.dump();
  return path.string();
}

const std::set<std::string> kCaseNames{"A", "B", "C1", "C2", "D", "degenerate"};

// Checks the documented classify --json layout of one object entry; returns
// its edges as (i, j) pairs.
std::vector<std::pair<int, int>> check_object_layout(const nlohmann::json& o) {
  std::set<std::string> keys;
  for (const auto& item : o.items()) keys.insert(item.key());
  EXPECT_EQ(keys, (std::set<std::string>{"object", "silhouette_edges", "cases", "edge_on_triangles",
                                         "engine_disagreements", "edges"}));
  std::set<std::string> case_keys;
  for (const auto& item : o.at("cases").items()) case_keys.insert(item.key());
  EXPECT_EQ(case_keys, kCaseNames);
  const auto& dis = o.at("engine_disagreements");
  EXPECT_EQ(dis.at("total").get<int>(), dis.at("silhouette_missed").get<int>() + dis.at("silhouette_extra").get<int>() +
                                            dis.at("case_mismatch").get<int>());
  EXPECT_TRUE(dis.at("facing_mismatch").is_number_unsigned());
  const std::size_t n = o.at("silhouette_edges").get<std::size_t>();
  EXPECT_EQ(n, o.at("edges").size());
  std::map<std::string, std::size_t> recount;
  std::size_t sum = 0;
  for (const std::string& c : kCaseNames) sum += o.at("cases").at(c).get<std::size_t>();
  EXPECT_EQ(sum, n);
  std::vector<std::pair<int, int>> edges;
  for (const auto& e : o.at("edges")) {
    const auto& v = e.at("v");
    EXPECT_EQ(v.size(), 2u);
    EXPECT_LT(v.at(0).get<int>(), v.at(1).get<int>()) << "smallest index first";
    edges.emplace_back(v.at(0).get<int>(), v.at(1).get<int>());
    const std::string c = e.at("case").get<std::string>();
    EXPECT_TRUE(kCaseNames.count(c)) << c;
    ++recount[c];
    const auto& engine = e.at("engine_case");
    EXPECT_TRUE(engine.is_null() || kCaseNames.count(engine.get<std::string>())) << engine.dump();
  }
  for (const std::string& c : kCaseNames) EXPECT_EQ(recount[c], o.at("cases").at(c).get<std::size_t>()) << c;
  return edges;
}

TEST(ClassifyCommand, BoxSeedHasAHexagonalSilhouette) {
  // fuzz/seeds/scene/box.json: the unit box raised to y in [0, 1], light at
  // (2, 4, 1) sees its +x, +y and +z faces: the silhouette is a hexagon.
  const std::string scene = materialise_seed("box.json");
  const test::CliResult r = test::run_cli("classify " + scene + " --json", "seed_box");
  std::filesystem::remove(scene);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("filter"));
  ASSERT_EQ(j.at("lights").size(), 1u);
  const auto& light = j.at("lights").at(0);
  EXPECT_EQ(light.at("light").get<int>(), 0);
  ASSERT_EQ(light.at("objects").size(), 1u) << "the receiver (object 1) is not listed";
  const auto& o = light.at("objects").at(0);
  EXPECT_EQ(o.at("object").get<int>(), 0);
  const auto edges = check_object_layout(o);
  EXPECT_EQ(edges.size(), 6u);
  const std::set<std::pair<int, int>> distinct(edges.begin(), edges.end());
  EXPECT_EQ(distinct.size(), edges.size()) << "no edge twice";
  std::map<int, int> degree;
  for (const auto& [a, b] : edges) {
    EXPECT_LT(b, 8);
    ++degree[a];
    ++degree[b];
  }
  EXPECT_EQ(degree.size(), 6u);
  for (const auto& [v, d] : degree) EXPECT_EQ(d, 2) << "vertex " << v << ": the silhouette is one closed loop";
}

TEST(ClassifyCommand, LightInTheNearPlaneIsFlagged) {
  // fuzz/seeds/scene/exact_camera.json: light 1 at world (0, 0.25, 4.5) is at
  // camera-space z = 4.5 - 5 = -0.5 = -near.
  const std::string scene = materialise_seed("exact_camera.json");
  const test::CliResult r = test::run_cli("classify --json " + scene, "seed_exact");
  std::filesystem::remove(scene);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.at("lights").size(), 2u);
  EXPECT_FALSE(j["lights"][0].at("light_in_near_plane").get<bool>());
  EXPECT_TRUE(j["lights"][1].at("light_in_near_plane").get<bool>());
  for (const auto& light : j.at("lights"))
    for (const auto& o : light.at("objects")) (void)check_object_layout(o);
  for (const auto& e : j["lights"][1]["objects"][0]["edges"]) {
    const std::string c = e.at("case").get<std::string>();
    EXPECT_TRUE(c == "A" || c == "D" || c == "degenerate") << c;
  }
}

TEST(ClassifyCommand, TextOutputNamesTheScene) {
  const test::CliResult r = test::run_cli("classify data/scenes/default.json", "text");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("default.json"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("silhouette"), std::string::npos) << r.out;
}

TEST(Cli, MissingSceneIsAnIoErrorWithNoOutput) {
  for (const char* args :
       {"classify data/scenes/does_not_exist.json", "classify --json data/scenes/does_not_exist.json"}) {
    const test::CliResult r = test::run_cli(args, "missing_json");
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.err.find("error (io)"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

TEST(Cli, OverflowingFrustumIsAnErrorNotACrash) {
  // A convenient camera whose frustum overflows (fovy 120 at near 1e308, see
  // SceneErrors.LookAtFrustumThatOverflowsIsRejected): every command must end
  // with exit code 2 and a one-line error, never a signal.
  nlohmann::json j;
  j["camera"] = {{"eye", {0, 1, 5}}, {"target", {0, 0, 0}}, {"fovy_deg", 120}, {"near", 1e308},
                 {"far", 1.5e308},   {"width", 64},         {"height", 48}};
  j["lights"] = nlohmann::json::array({{{"position", {2, 4, 1}}}});
  j["objects"] = nlohmann::json::array(
      {{{"mesh", std::string(NEARCAP_SOURCE_DIR) + "/fuzz/meshes/box.off"}, {"translate", {0, 0.5, 0}}}});
  const auto scene =
      std::filesystem::temp_directory_path() / ("nearcap_cli_overflow_" + std::to_string(::getpid()) + ".json");
  std::ofstream(scene) << j.dump();
  const auto out_dir =
      std::filesystem::temp_directory_path() / ("nearcap_cli_overflow_out_" + std::to_string(::getpid()));
  for (const std::string& args : {"classify " + scene.string(), "cap " + scene.string() + " --light 0",
                                  "reference " + scene.string() + " --light 0 --out " + out_dir.string()}) {
    const test::CliResult r = test::run_cli(args, "overflow");
    EXPECT_EQ(r.exit_code, 2) << args << " (128 + signal number when killed by a signal)\n" << r.err;
    EXPECT_NE(r.err.find("error ("), std::string::npos) << args << "\n" << r.err;
  }
  std::filesystem::remove(scene);
  std::filesystem::remove_all(out_dir);
}

TEST(Cli, UnknownSubcommandOrOptionIsNotSuccess) {
  EXPECT_NE(test::run_cli("frobnicate data/scenes/default.json", "usage").exit_code, 0);
  EXPECT_NE(test::run_cli("classify data/scenes/default.json --no-such-option", "usage").exit_code, 0);
}

TEST(CracksCommand, OneRecordPerMethodWithTheDocumentedFields) {
  const test::CliResult r = test::run_cli("cracks data/scenes/near_split.json --light 0 --method all", "cracks_all");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.at("methods").size(), 8u);  // the six methods, the switch policy and raytrace
  std::set<std::string> names;
  for (const auto& m : j["methods"]) {
    names.insert(m.at("method").get<std::string>());
    if (m["method"] == "raytrace" && !raytrace::raytrace_available()) {
      EXPECT_NE(m.at("refused").get<std::string>().find("libembree-dev"), std::string::npos) << m;
      continue;
    }
    for (const char* key : {"pixels_seen", "wrong", "wrong_lit", "wrong_shadowed", "count_mismatch", "ms"})
      EXPECT_TRUE(m.at(key).is_number()) << key;
    // The float engine's case disagreements; the ray tracer has no cases.
    if (m["method"] == "raytrace") {
      EXPECT_TRUE(m.at("case_disagreements").is_null());
    } else {
      EXPECT_TRUE(m.at("case_disagreements").is_number());
    }
    EXPECT_TRUE(m.contains("cap_mismatch"));
    EXPECT_EQ(m["wrong"].get<std::size_t>(),
              m["wrong_lit"].get<std::size_t>() + m["wrong_shadowed"].get<std::size_t>());
  }
  EXPECT_EQ(names, (std::set<std::string>{"zpass", "zfail", "zpplus", "zpplus-corrected", "preload", "atomiczp",
                                          "policy", "raytrace"}));
  // The policy's record says which method each occluder got, and why.
  const auto policy = std::find_if(j["methods"].begin(), j["methods"].end(),
                                   [](const nlohmann::json& m) { return m["method"] == "policy"; });
  ASSERT_NE(policy, j["methods"].end());
  ASSERT_FALSE((*policy)["occluders"].empty());
  for (const auto& o : (*policy)["occluders"]) {
    EXPECT_TRUE(o.at("method").is_string());
    EXPECT_FALSE(o.at("why").get<std::string>().empty());
  }
}

// Where a tiny near plane exhausts the depth buffer, a policy held to the
// scene's near plane says so (depth_limited, with a note naming the fixes);
// the shipped policy draws that frame with the tight near plane and says
// why; a policy with the tight plane of its own is not depth-limited.
TEST(CracksCommand, ThePolicysRecordSaysWhereTheDepthBufferIsTheLimit) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_depth_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string scene = (dir / "tiny.json").string();
  const test::CliResult sampled =
      test::run_cli("sample --seed 5 --index 1 --kinds tiny-near --width 48 --height 36 --out '" + scene + "'", "s");
  ASSERT_EQ(sampled.exit_code, 0) << sampled.err;
  const test::CliResult r = test::run_cli("cracks '" + scene + "' --light 0 --method zfail,policy", "cracks_depth");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.at("methods").size(), 2u);
  EXPECT_GT(j["methods"][0].at("cracks").get<int>(), 0) << "Z-fail itself cracks here";
  const nlohmann::json& policy = j["methods"][1];
  EXPECT_FALSE(policy.at("depth_limited").get<bool>());
  EXPECT_FALSE(policy.contains("depth_note"));
  EXPECT_NE(policy.at("near_plane_note").get<std::string>().find("tight near plane"), std::string::npos);
  EXPECT_EQ(policy.at("cracks").get<int>(), 0);
  nlohmann::json pinned_policy =
      nlohmann::json::parse(test::slurp(std::string(NEARCAP_SOURCE_DIR) + "/data/policy.json"));
  pinned_policy["near_plane"] = "scene";
  const std::string pinned_path = (dir / "pinned.json").string();
  std::ofstream(pinned_path) << pinned_policy.dump();
  const test::CliResult pinned =
      test::run_cli("cracks '" + scene + "' --light 0 --method policy --policy '" + pinned_path + "'", "c");
  ASSERT_EQ(pinned.exit_code, 0) << pinned.err;
  const auto p = nlohmann::json::parse(pinned.out);
  EXPECT_TRUE(p.at("depth_limited").get<bool>());
  EXPECT_NE(p.at("depth_note").get<std::string>().find("--near-plane tight"), std::string::npos);
  EXPECT_FALSE(p.contains("near_plane_note"));
  const test::CliResult fixed =
      test::run_cli("cracks '" + scene + "' --light 0 --method policy --policy data/policy-tight-near.json", "c");
  ASSERT_EQ(fixed.exit_code, 0) << fixed.err;
  const auto k = nlohmann::json::parse(fixed.out);  // one method: its record alone
  EXPECT_FALSE(k.at("depth_limited").get<bool>());
  EXPECT_EQ(k.at("cracks").get<int>(), 0);
  EXPECT_FALSE(k.contains("depth_note"));
  std::filesystem::remove_all(dir);
}

TEST(CracksCommand, OutWritesTheImageAndTheRecord) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_cracks_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const test::CliResult r = test::run_cli(
      "cracks data/scenes/near_split.json --light 0 --method zpplus --out '" + dir.string() + "'", "cracks_out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out).at("method"), "zpplus");
  const std::string png = test::slurp(dir / "cracks.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const auto record = nlohmann::json::parse(test::slurp(dir / "cracks.json"));
  EXPECT_EQ(record.at("light"), 0);
  std::filesystem::remove_all(dir);
}

TEST(CracksCommand, TableNamesEveryMethod) {
  const test::CliResult r = test::run_cli("cracks data/scenes/case_d.json --light 0 --table", "cracks_table");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* m : {"zpass", "zfail", "zpplus", "zpplus-corrected", "preload", "atomiczp"})
    EXPECT_NE(r.out.find(m), std::string::npos) << m;
}

TEST(CracksCommand, BadArgumentsAreUsageErrorsAndWriteNothing) {
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_cracks_bad_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  for (const std::string args : {"--method zpass+", "--subpixel-bits 40", "--l-near-scale 2",
                                 "--depth-mapping reversed --infinite-far epsilon", "--depth-mapping inverted"}) {
    const test::CliResult r = test::run_cli(
        "cracks data/scenes/near_split.json --light 0 " + args + " --out '" + dir.string() + "'", "cracks_bad");
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.err.find("usage"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir)) << args;
  }
  const test::CliResult light = test::run_cli("cracks data/scenes/near_split.json --light 3", "cracks_light");
  EXPECT_EQ(light.exit_code, 2);
  EXPECT_NE(light.err.find("--light 3"), std::string::npos) << light.err;
}

TEST(CracksCommand, LightOnTheNearPlaneSaysZPPlusFellBack) {
  const test::CliResult r =
      test::run_cli("cracks data/scenes/light_on_near_plane.json --light 0 --method zpplus", "cracks_fallback");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NE(j.at("fallback").get<std::string>().find("zfail"), std::string::npos);
  EXPECT_TRUE(j.at("cap_mismatch").is_null());
}

}  // namespace
}  // namespace nearcap
