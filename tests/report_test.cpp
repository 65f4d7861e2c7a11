// nearcap report: the page, its plots (each holding data) and tables from a
// sweep's CSV; bad input is a one-line error with nothing written.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <sstream>
#include <vector>

#include "cli_support.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

class Report : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("nearcap_report_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A path (cases C and D along it) and a few samples, small.
    const test::CliResult r = test::run_cli(
        "sweep --path data/paths/near_plane_sweep.json --samples 12 --seed 2 "
        "--width 24 --height 18 --policies all --out " +
            (dir_ / "rows.csv").string(),
        "report_sweep");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path dir_;
};
fs::path Report::dir_;

TEST_F(Report, WritesThePageWithPlotsThatHoldData) {
  const fs::path out = dir_ / "report";
  const test::CliResult r = test::run_cli(
      "report " + (dir_ / "rows.csv").string() + " --out " + out.string() + " --policy data/policy.json", "report");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("index.html"), std::string::npos) << r.out;
  const std::string page = test::slurp(out / "index.html");
  for (const char* section :
       {"Speed against error", "Camera paths", "Cracks against conditioning", "Crack distance", "Does case D flag",
        "engine rules", "fitted models", "The policy&#x27;s cost", "Hard cases by kind"})
    EXPECT_NE(page.find(section), std::string::npos) << section;
  const nlohmann::json manifest = nlohmann::json::parse(test::slurp(out / "report.json"));
  EXPECT_EQ(manifest["configurations"], 60 + 12 - manifest["rejected"].get<int>());
  ASSERT_GE(manifest["plots"].size(), 4u);
  for (const auto& plot : manifest["plots"]) {
    const fs::path png = out / plot["file"].get<std::string>();
    ASSERT_TRUE(fs::exists(png)) << png;
    EXPECT_EQ(test::slurp(png).substr(1, 3), "PNG") << png;
    EXPECT_GT(plot["points"].get<int>(), 0) << png;
    EXPECT_NE(page.find(plot["file"].get<std::string>()), std::string::npos) << "the page shows " << png;
  }
  for (const char* table : {"summary.csv", "crack_distance.csv", "case_d.csv", "baselines.csv", "by_kind.csv",
                            "policy_crack_model.csv", "policy_weights.csv", "policy_costs.csv", "policy_cost.csv"})
    EXPECT_TRUE(fs::exists(out / table)) << table;
  // The policy's cost: the pairs where Z-pass is right against Z-pass, the others against ZP+ corrected.
  const std::string cost = test::slurp(out / "policy_cost.csv");
  EXPECT_NE(cost.find("\nZ-pass right,"), std::string::npos) << cost;
  EXPECT_NE(cost.find(",zpass,"), std::string::npos) << cost;
  // One row per method in the summary: six methods, four engine rules and the switch policy.
  const std::string summary = test::slurp(out / "summary.csv");
  EXPECT_EQ(std::count(summary.begin(), summary.end(), '\n'), 12) << summary;
  // The baselines' confusion table: the same truth for every row, Z-pass
  // missing all of it, the Z-fail rows none; each row's counts add up.
  std::istringstream baselines(test::slurp(out / "baselines.csv"));
  std::string line;
  std::getline(baselines, line);  // header
  std::map<std::string, std::vector<long>> by_method;
  while (std::getline(baselines, line)) {
    std::istringstream fields(line);
    std::string name, field;
    std::getline(fields, name, ',');
    std::vector<long> v;
    for (int k = 0; k < 6 && std::getline(fields, field, ','); ++k) v.push_back(std::stol(field));
    ASSERT_EQ(v.size(), 6u) << line;
    by_method[name] = v;  // decisions, truth, tp, fn, fp, tn
  }
  for (const char* m : {"zpass", "zfail", "preload", "doom3", "doom3-bfg", "ogre", "always-zfail", "policy"})
    ASSERT_TRUE(by_method.count(m)) << m;
  const long truth = by_method["zpass"][1];
  EXPECT_GT(truth, 0);
  for (const auto& [m, v] : by_method) {
    EXPECT_EQ(v[1], truth) << m;
    EXPECT_EQ(v[2] + v[3], v[1]) << m;
    EXPECT_EQ(v[2] + v[3] + v[4] + v[5], v[0]) << m;
  }
  EXPECT_EQ(by_method["zpass"][3], truth);
  EXPECT_EQ(by_method["always-zfail"][3], 0);
  EXPECT_EQ(by_method["always-zfail"][5], 0);
}

TEST_F(Report, BadInputIsOneLineAndWritesNothing) {
  const fs::path bad = dir_ / "bad.csv";
  {
    std::ofstream f(bad);
    f << "configuration,source,kind\nx,y,z\n";
  }
  const std::string text = test::slurp(dir_ / "rows.csv");
  const fs::path garbled = dir_ / "garbled.csv";
  {
    std::ofstream f(garbled);
    const std::size_t second_line = text.find('\n') + 1;
    std::string broken = text;
    broken.replace(broken.find(',', broken.find(",zpass,", second_line) + 7), 1, ",notanumber,");
    f << broken;
  }
  struct Case {
    std::string args, fragment;
  };
  const fs::path out = dir_ / "never";
  for (const Case& c :
       {Case{"report " + bad.string(), "missing column"},
        Case{"report " + (dir_ / "absent.csv").string(), "absent.csv"}, Case{"report " + garbled.string(), "line 2"},
        Case{"report " + dir_.string(), "not a regular file"},
        Case{"report " + (dir_ / "rows.csv").string() + " --policy " + bad.string(), "malformed JSON"},
        Case{"report " + (dir_ / "rows.csv").string() + " --policy " + (dir_ / "nope.json").string(), "nope.json"},
        Case{"report " + (dir_ / "rows.csv").string() + " " + (dir_ / "rows.csv").string(), "a second row"}}) {
    const test::CliResult r = test::run_cli(c.args + " --out " + out.string(), "report_bad");
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("nearcap: error (", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(c.fragment), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
}

TEST(ReportCommand, UnknownSubcommandsAreNamed) {
  const test::CliResult r = test::run_cli("optimize", "optimize");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown subcommand 'optimize'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("report"), std::string::npos) << "the list names the report: " << r.err;
}

}  // namespace
}  // namespace nearcap
