// The program end to end on bundled scenes: documented JSON layouts, counts
// that agree with each other, the main job's outputs.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

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
  // area fraction up to the pixel grid (640 x 480).
  const auto dir = std::filesystem::temp_directory_path() / "nearcap_cli_test_ref";
  const test::CliResult ref =
      test::run_cli("reference data/scenes/near_split.json --light 0 --out " + dir.string(), "ref");
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  const auto summary = nlohmann::json::parse(ref.out);
  const double pixel_fraction = summary.at("pixels_cap_nonzero").get<double>() / (640.0 * 480.0);
  EXPECT_NEAR(pixel_fraction, fraction, 2.0 / 480.0);
}

TEST(CapCommand, SvgIsWritten) {
  const auto svg = std::filesystem::temp_directory_path() / "nearcap_cli_test_cap.svg";
  std::filesystem::remove(svg);
  const test::CliResult r =
      test::run_cli("cap data/scenes/case_d.json --light 0 --out /dev/null --svg " + svg.string(), "svg");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = test::slurp(svg);
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("count 1"), std::string::npos);
}

TEST(CapCommand, AFailingSecondOutputLeavesNoFirstOutput) {
  const auto json = std::filesystem::temp_directory_path() / "nearcap_cli_test_partial.json";
  std::filesystem::remove(json);
  const test::CliResult r = test::run_cli(
      "cap data/scenes/case_d.json --light 0 --out " + json.string() + " --svg /nonexistent-dir/cap.svg", "partial");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("error (io)"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(json)) << "no partial output";
  EXPECT_FALSE(std::filesystem::exists(json.string() + ".tmp-nearcap"));
}

TEST(Cli, MissingSceneExitsWithTwo) {
  const test::CliResult r = test::run_cli("classify data/scenes/does_not_exist.json", "missing");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("does_not_exist.json"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace nearcap
