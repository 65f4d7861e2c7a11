// nearcap report: the page, its plots (each holding data) and tables from a
// sweep's CSV; bad input is a one-line error with nothing written.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "cli_support.hpp"
#include "nearcap/analysis/engine_policies.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/gl/light_frustum.hpp"
#include "nearcap/gl/shadow_methods.hpp"

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
  // The shipped policy's unpriced tiers, each named with its method.
  const nlohmann::json shipped =
      nlohmann::json::parse(test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data" / "policy.json"));
  ASSERT_TRUE(shipped.at("unpriced_frames").is_array());
  for (const nlohmann::json& tier : shipped.at("unpriced_frames")) {
    const std::string text = "at most " + std::to_string(tier.at("max_occluder_triangles").get<int>()) +
                             " triangles: <code>" + tier.at("method").get<std::string>() + "</code>";
    EXPECT_NE(page.find(text), std::string::npos) << text;
  }
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

// The fields of a line of a nearcap CSV (no field is quoted).
std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1)
    fields.push_back(line.substr(start, comma - start));
  fields.push_back(line.substr(start));
  return fields;
}

std::string joined(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t k = 0; k < fields.size(); ++k) line += (k ? "," : "") + fields[k];
  return line;
}

// A count the program never writes (negative, or more wrong pixels than
// seen), or a time that is not finite or is negative, is refused naming its
// line and column, not summed; a column a row may leave empty (cap_mismatch,
// the per-occluder decisions, frame_again_ms) is checked where it has a value;
// a number is read as the sweep writes it (decimal, no sign +, no spaces).
TEST_F(Report, ACountNoSweepWritesIsRefused) {
  std::istringstream in(test::slurp(dir_ / "rows.csv"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_GE(lines.size(), 2u);
  const std::vector<std::string> header = fields_of(lines[0]);
  const auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::tuple<std::string, std::string, std::string> cases[] = {
      {"wrong", "-5", "line 2: column 'wrong': '-5' is not a count or an index"},
      {"light", "-1", "line 2: column 'light': '-1' is not a count or an index"},
      {"pixels_seen", "0", "line 2: column 'wrong':"},
      {"cracks", "4", "line 2: column 'cracks': 4 cracks of 3 wrong pixels"},
      {"cracks", "99999999999999999999999", "'99999999999999999999999' is not a count a sweep writes"},
      {"frame_ms", "-3", "line 2: column 'frame_ms': '-3' is not a time"},
      {"frame_ms", "inf", "line 2: column 'frame_ms': 'inf' is not a time"},
      {"configuration", "", "line 2: column 'configuration': '' is not a configuration id"},
      {"frame_again_ms", "-0.5", "line 2: column 'frame_again_ms': '-0.5' is not a time"},
      {"frame_again_ms", "nan", "line 2: column 'frame_again_ms': 'nan' is not a time"},
      {"frame_again_ms", "inf", "line 2: column 'frame_again_ms': 'inf' is not a time"},
      {"reference_ms", "-inf", "line 2: column 'reference_ms': '-inf' is not a time"},
      {"cap_mismatch", "-1", "line 2: column 'cap_mismatch': '-1' is not a count (it is negative)"},
      {"cap_mismatch", "9007199254740993", "'9007199254740993' is not a count a sweep writes"},
      {"false_negatives", "-2", "line 2: column 'false_negatives': '-2' is not a count (it is negative)"},
      {"occluders", "1.5", "line 2: column 'occluders': '1.5' is not an integer"},
      {"refused", "2", "line 2: column 'refused': '2' is not 0 or 1"},
      {"wrong", "-0", "line 2: column 'wrong': '-0' is not a count or an index"},
      {"skew", "-1", "line 2: column 'skew': '-1' is not a magnitude (the sweep writes no negative skew)"},
      // Spellings the sweep never writes, refused as `nearcap tune` refuses them.
      {"occluders", "+1", "line 2: column 'occluders': '+1' is not an integer"},
      {"cap_mismatch", "1_0", "line 2: column 'cap_mismatch': '1_0' is not an integer"},
      {"frame_ms", "+1", "line 2: column 'frame_ms': '+1' is not a number"},
      {"frame_ms", "infinity", "line 2: column 'frame_ms': 'infinity' is not a number"},
      {"frame_ms", "1e-400", "line 2: column 'frame_ms': '1e-400' is not a number the sweep writes"},
      {"frame_again_ms", "1e999", "line 2: column 'frame_again_ms': '1e999' is not a number the sweep writes"},
  };
  const fs::path out = dir_ / "never";
  for (const auto& [name, value, fragment] : cases) {
    std::vector<std::string> fields = fields_of(lines[1]);
    ASSERT_LT(column(name), fields.size()) << name;
    if (name == "pixels_seen") fields[column("wrong")] = "5";
    if (value == "4") fields[column("wrong")] = "3";
    fields[column(name)] = value;
    std::string text = lines[0] + "\n" + joined(fields) + "\n";
    for (std::size_t k = 2; k < lines.size(); ++k) text += lines[k] + "\n";
    std::ofstream(dir_ / "edited.csv") << text;
    const test::CliResult r =
        test::run_cli("report " + (dir_ / "edited.csv").string() + " --out " + out.string(), "report_count");
    EXPECT_EQ(r.exit_code, 2) << name << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("nearcap: error (parse): ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

// A control character of the CSV in the report's error line is written as
// an escape: the line reaches a terminal, which would act on it.
TEST_F(Report, AControlCharacterInItsErrorLineIsEscaped) {
  std::istringstream in(test::slurp(dir_ / "rows.csv"));
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  std::ofstream(dir_ / "escape.csv") << header << "\n"
                                     << row.substr(0, row.find(',')) << "\x1b[2J" << row.substr(row.find(',')) << "\n";
  const test::CliResult r = test::run_cli(
      "report " + (dir_ / "escape.csv").string() + " --out " + (dir_ / "never").string(), "report_escape");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.find('\x1b'), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("\\x1b[2J"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// A column named twice: which of the two would be summed is a guess.
TEST_F(Report, AColumnNamedTwiceIsRefused) {
  std::istringstream in(test::slurp(dir_ / "rows.csv"));
  std::string text;
  bool header = true;
  for (std::string line; std::getline(in, line); header = false) text += line + (header ? ",wrong" : ",0") + "\n";
  std::ofstream(dir_ / "twice.csv") << text;
  const fs::path out = dir_ / "never";
  const test::CliResult r =
      test::run_cli("report " + (dir_ / "twice.csv").string() + " --out " + out.string(), "report_twice");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("nearcap: error (parse): " + (dir_ / "twice.csv").string() +
                       ": line 1: column 'wrong' appears twice in the header"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// nearcap stopped (SIGTERM) while its report script runs: the script is
// stopped too, through its cleanup, and nothing of the run is left behind
// (the settings table and the log are temporary files); nearcap ends by the
// signal.  The script here stands in for the report: it says where its
// settings and its stderr (the log) are, then waits.
TEST_F(Report, StoppedWhileItsScriptRunsItStopsTheScriptAndLeavesNothing) {
  const fs::path run = dir_ / "stopped";
  fs::create_directories(run);
  std::ofstream(run / "waiting.py") << "import os, signal, sys, time\n"
                                       "def stop(signum, frame):\n"
                                       "    open(sys.argv[0] + '.stopped', 'w').write('stopped')\n"
                                       "    sys.exit(128 + signum)\n"
                                       "signal.signal(signal.SIGTERM, stop)\n"
                                       "settings = sys.argv[sys.argv.index('--settings') + 1]\n"
                                       "with open(sys.argv[0] + '.tmp', 'w') as f:\n"
                                       "    f.write(settings + '\\n' + os.readlink('/proc/self/fd/2') + '\\n')\n"
                                       "os.rename(sys.argv[0] + '.tmp', sys.argv[0] + '.started')\n"
                                       "time.sleep(120)\n";
  const std::string script = (run / "waiting.py").string();
  // A SIGHUP the shell ignores (as nohup does) stays ignored: nearcap is
  // still running half a second later; then SIGTERM stops it.
  const std::string command = "cd '" + run.string() + "' && (trap '' HUP; NEARCAP_REPORT_SCRIPT='" + script + "' '" +
                              std::string(NEARCAP_CLI) + "' report '" + (dir_ / "rows.csv").string() +
                              "' --out R 2> err & pid=$!; for i in $(seq 600); do [ -e '" + script +
                              ".started' ] && break; sleep 0.1; done; kill -HUP $pid; sleep 0.5; "
                              "kill -0 $pid && echo alive > hup; kill -TERM $pid; wait $pid; echo $? > rc)";
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(test::slurp(run / "hup"), "alive\n") << "an ignored SIGHUP stopped it";
  EXPECT_EQ(test::slurp(run / "rc"), "143\n") << test::slurp(run / "err");
  EXPECT_EQ(test::slurp(run / "waiting.py.stopped"), "stopped") << "the script got SIGTERM and ran its cleanup";
  std::istringstream started(test::slurp(run / "waiting.py.started"));
  std::string settings, log;
  std::getline(started, settings);
  std::getline(started, log);
  EXPECT_FALSE(settings.empty());
  EXPECT_FALSE(fs::exists(settings)) << "the settings table, a temporary file: " << settings;
  EXPECT_FALSE(log.empty());
  EXPECT_FALSE(fs::exists(log)) << "the script's log, a temporary file: " << log;
  EXPECT_FALSE(fs::exists(run / "R"));
}

// The first column of a report table's CSV, header left out.
std::vector<std::string> first_column(const fs::path& csv) {
  std::istringstream in(test::slurp(csv));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  while (std::getline(in, line)) names.push_back(fields_of(line)[0]);
  return names;
}

nlohmann::json settings_table() {
  const test::CliResult r = test::run_cli("settings", "settings");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

// Runs the report script itself on `rows` with the settings table `table`.
test::CliResult run_report_script(const fs::path& rows, const fs::path& table, const fs::path& out) {
  const std::string err = (out.string() + ".err");
  const char* env = std::getenv("NEARCAP_PYTHON");
  const std::string python = env && *env ? env : "/usr/bin/python3";
  const std::string command = "cd '" + std::string(NEARCAP_SOURCE_DIR) + "' && '" + python +
                              "' analysis/report/sweep_report.py '" + rows.string() + "' --out '" + out.string() +
                              "' --settings '" + table.string() + "' > /dev/null 2> '" + err + "'";
  const int status = std::system(command.c_str());
  test::CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = test::slurp(err);
  fs::remove(err);
  return r;
}

TEST(SettingsTable, HoldsEveryMethodAndRuleOfTheSweepInTheReportsOrder) {
  const nlohmann::json table = settings_table();
  EXPECT_EQ(table["format"], "nearcap-settings");
  EXPECT_EQ(table["version"], 1);
  std::vector<std::string> expected;
  std::vector<std::string> labels;
  for (const auto& m : gl::kShadowMethodTable) {
    expected.emplace_back(m.name);
    labels.emplace_back(m.help);
  }
  expected.emplace_back("policy");
  labels.emplace_back("");
  for (const auto& p : analysis::kEnginePolicyTable) {
    expected.emplace_back(p.name);
    labels.emplace_back(p.help);
  }
  ASSERT_EQ(table["methods"].size(), expected.size()) << table["methods"].dump();
  std::map<std::string, std::string> holder;
  for (std::size_t k = 0; k < expected.size(); ++k) {
    const nlohmann::json& m = table["methods"][k];
    EXPECT_EQ(m["name"], expected[k]) << k;
    if (!labels[k].empty()) {
      EXPECT_EQ(m["label"], labels[k]) << expected[k];
    }
    EXPECT_FALSE(m["label"].get<std::string>().empty()) << expected[k];
    for (const auto& role : m["roles"]) {
      EXPECT_TRUE(holder.emplace(role.get<std::string>(), expected[k]).second) << "role " << role << " held twice";
    }
  }
  EXPECT_EQ(table["methods"][0]["kind"], "shadow-method");
  EXPECT_EQ(table["methods"][gl::kAllShadowMethods.size()]["kind"], "switch-policy");
  EXPECT_EQ(table["methods"][expected.size() - 1]["kind"], "engine-rule");
  // Each role of the report held by the method that plays it.
  const std::map<std::string, std::string> roles{{"timing-baseline", "zpass"},
                                                 {"zfail-baseline", "zfail"},
                                                 {"published-zpplus", "zpplus"},
                                                 {"corrected-zpplus", "zpplus-corrected"},
                                                 {"switch-policy", "policy"}};
  EXPECT_EQ(holder, roles);
  // The emulation choices: each option with its table's values.
  bool found = false;
  for (const auto& c : table["choices"])
    if (c["option"] == "light-projection") {
      found = true;
      ASSERT_EQ(c["values"].size(), std::size(gl::kLightProjectionTable));
      for (std::size_t k = 0; k < c["values"].size(); ++k)
        EXPECT_EQ(c["values"][k]["name"], gl::kLightProjectionTable[k].name);
    }
  EXPECT_TRUE(found) << table["choices"].dump();
  EXPECT_EQ(table["kinds"].size(), static_cast<std::size_t>(analysis::kHardCaseKindCount));
}

// A method added to the settings table, one renamed and one moved: the
// report lists them as the table says, with no Python edited; a role the
// table takes away takes its section with it.
TEST_F(Report, TheMethodsTheirOrderAndRolesComeFromTheSettingsTable) {
  nlohmann::json table = settings_table();
  nlohmann::json methods = nlohmann::json::array();
  methods.push_back({{"name", "brand-new"},
                     {"label", "a method only this test has"},
                     {"kind", "shadow-method"},
                     {"roles", nlohmann::json::array()}});
  nlohmann::json zfail;
  for (nlohmann::json m : table["methods"]) {
    if (m["name"] == "atomiczp") m["name"] = "atomic-zp";
    if (m["name"] == "zfail")
      zfail = m;
    else
      methods.push_back(m);
  }
  methods.push_back(zfail);
  table["methods"] = methods;
  const fs::path fake = dir_ / "fake_settings.json";
  std::ofstream(fake) << table.dump(1);
  // The rows: atomiczp's renamed, and each Z-pass row again as brand-new's,
  // and as brand-new's under a variant.
  const fs::path rows = dir_ / "renamed_rows.csv";
  {
    std::istringstream in(test::slurp(dir_ / "rows.csv"));
    std::ofstream out(rows);
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> header = fields_of(line);
    const std::size_t method = std::find(header.begin(), header.end(), "method") - header.begin();
    const std::size_t variant = std::find(header.begin(), header.end(), "variant") - header.begin();
    ASSERT_LT(method, header.size());
    ASSERT_LT(variant, header.size());
    out << line << "\n";
    while (std::getline(in, line)) {
      std::vector<std::string> f = fields_of(line);
      if (f[method] == "atomiczp") f[method] = "atomic-zp";
      out << joined(f) << "\n";
      if (f[method] == "zpass") {
        f[method] = "brand-new";
        out << joined(f) << "\n";
        f[variant] = "light-projection=glfrustum";
        out << joined(f) << "\n";
      }
    }
  }
  const fs::path out = dir_ / "renamed_report";
  test::CliResult r = run_report_script(rows, fake, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> order{"brand-new",
                                       "brand-new [light-projection=glfrustum]",
                                       "zpass",
                                       "zpplus",
                                       "zpplus-corrected",
                                       "preload",
                                       "atomic-zp",
                                       "policy",
                                       "doom3",
                                       "doom3-bfg",
                                       "ogre",
                                       "always-zfail",
                                       "zfail"};
  EXPECT_EQ(first_column(out / "summary.csv"), order);
  EXPECT_EQ(first_column(out / "crack_distance.csv"), order);
  const std::string key = test::slurp(out / "methods.csv");
  EXPECT_NE(key.find("brand-new,shadow-method,a method only this test has\r\n"), std::string::npos) << key;
  // A variant's choices in words, from the table's emulation choices.
  EXPECT_NE(key.find("brand-new [light-projection=glfrustum],shadow-method,a method only this test has; under "
                     "light-projection=glfrustum (P_l formulation)\r\n"),
            std::string::npos)
      << key;
  EXPECT_NE(test::slurp(out / "index.html").find("Does case D flag"), std::string::npos);

  // Without the corrected ZP+'s role the case-D section has no subject.
  for (nlohmann::json& m : table["methods"])
    if (m["name"] == "zpplus-corrected") m["roles"] = nlohmann::json::array();
  std::ofstream(fake) << table.dump(1);
  const fs::path no_role = dir_ / "no_role_report";
  r = run_report_script(rows, fake, no_role);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(test::slurp(no_role / "index.html").find("Does case D flag"), std::string::npos);
  EXPECT_EQ(first_column(no_role / "summary.csv"), order);

  // A table that is not one: one line, nothing written.
  std::ofstream(fake) << R"({"format": "nearcap-policy", "methods": []})";
  const fs::path never = dir_ / "never_settings";
  r = run_report_script(rows, fake, never);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err, "nearcap: error (parse): " + fake.string() +
                       ": format: not a nearcap settings table (nearcap settings prints one)\n");
  EXPECT_FALSE(fs::exists(never));
}

// render --bench's plot: its times are relative to the table's timing
// baseline, whichever method holds that role.
TEST(RenderBenchScript, TimesAreRelativeToTheTablesTimingBaseline) {
  const fs::path dir = test::temp_path("nearcap_render_bench_script");
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    std::ofstream csv(dir / "bench.csv");
    csv << "frame,method,ms\n";
    for (int f = 0; f < 4; ++f)
      csv << f << ",zpass," << 1 + f << "\n"
          << f << ",zpass#again," << 1.1 + f << "\n"
          << f << ",zfail," << 2 + f << "\n";
  }
  nlohmann::json table = settings_table();
  const auto run_script = [&](const std::string& name) {
    std::ofstream(dir / (name + ".json")) << table.dump(1);
    const char* env = std::getenv("NEARCAP_PYTHON");
    const std::string python = env && *env ? env : "/usr/bin/python3";
    const std::string command = "cd '" + std::string(NEARCAP_SOURCE_DIR) + "' && '" + python +
                                "' analysis/report/render_bench.py '" + (dir / "bench.csv").string() + "' '" +
                                (dir / (name + ".png")).string() + "' --settings '" +
                                (dir / (name + ".json")).string() + "' 2> '" + (dir / (name + ".err")).string() + "'";
    const int status = std::system(command.c_str());
    return std::make_pair(WIFEXITED(status) ? WEXITSTATUS(status) : -1, test::slurp(dir / (name + ".err")));
  };
  auto [code, err] = run_script("real");
  EXPECT_EQ(code, 0) << err;
  EXPECT_GT(fs::file_size(dir / "real.png"), 1000u);
  // The role given to a method the bench did not draw: the script says that it needs that method's rows.
  for (nlohmann::json& m : table["methods"])
    m["roles"] = m["name"] == "zpplus" ? nlohmann::json::array({"timing-baseline"}) : nlohmann::json::array();
  std::tie(code, err) = run_script("moved");
  EXPECT_EQ(code, 2);
  EXPECT_NE(err.find("no zpplus rows (the times are relative to zpplus's"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir / "moved.png"));
  // ... and to one it drew: a plot.
  for (nlohmann::json& m : table["methods"])
    m["roles"] = m["name"] == "zfail" ? nlohmann::json::array({"timing-baseline"}) : nlohmann::json::array();
  std::tie(code, err) = run_script("zfail");
  EXPECT_EQ(code, 0) << err;
  EXPECT_TRUE(fs::exists(dir / "zfail.png"));
  fs::remove_all(dir);
}

// The plotting and scale scripts beside the report: bad input is one line
// on stderr, exit 2, never a traceback or a hang.
TEST(ReportScripts, BadInputIsOneLineNeverATraceback) {
  const fs::path dir = test::temp_path("nearcap_report_scripts");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto d = [&](const std::string& name) { return "'" + (dir / name).string() + "'"; };
  std::ofstream(dir / "short.csv") << "set,configuration,frame,light,rule,refused,applies\np,path:p:0,0,0,policy,0,1\n";
  std::ofstream(dir / "bench.csv") << "method,frame\n0,zpass\n";
  std::ofstream(dir / "header.csv") << "configuration,source\n";
  std::ofstream(dir / "binary.csv") << "\xff\xfe\n";
  std::ofstream(dir / "settings.json") << settings_table().dump(1);
  const char* env = std::getenv("NEARCAP_PYTHON");
  const std::string python = env && *env ? env : "/usr/bin/python3";
  std::ofstream(dir / "settings.txt") << "not json\n";
  // Each with nearcap's error kind: usage, io, parse (not the format), schema
  // (a column missing).
  const std::array<std::string, 3> cases[] = {
      {"policy_oracle.py " + d("short.csv") + " p " + d("o.png"), "schema", "not an evaluation CSV (no column"},
      {"policy_oracle.py " + d("binary.csv") + " p " + d("o.png"), "parse", "not an evaluation CSV"},
      {"policy_oracle.py " + d("missing.csv") + " p " + d("o.png"), "io", "cannot read it"},
      {"policy_oracle.py " + d("short.csv") + " p " + d("o.txt"), "usage", "name it NAME.png"},
      {"policy_oracle.py " + d("short.csv"), "usage", "usage: policy_oracle.py"},
      {"render_bench.py " + d("bench.csv") + " " + d("o.png") + " --settings " + d("settings.json"), "schema",
       "not a bench CSV (no column"},
      {"render_bench.py " + d("binary.csv") + " " + d("o.png") + " --settings " + d("settings.json"), "parse",
       "not a bench CSV"},
      {"render_bench.py " + d("missing.csv") + " " + d("o.png") + " --settings " + d("settings.json"), "io",
       "cannot read it"},
      {"render_bench.py " + d("bench.csv") + " " + d("o.png") + " --settings " + d("settings.txt"), "parse", ""},
      {"render_bench.py " + d("bench.csv") + " " + d("o.pdf") + " --settings " + d("settings.json"), "usage",
       "name it NAME.png"},
      {"replicate_rows.py " + d("header.csv") + " 10 " + d("x.csv"), "parse", "no rows to copy"},
      {"replicate_rows.py " + d("missing.csv") + " 10 " + d("x.csv"), "io", "cannot read it"},
      {"replicate_rows.py " + d("binary.csv") + " 10 " + d("x.csv"), "parse", "cannot read it"},
      {"replicate_rows.py " + d("header.csv") + " abc " + d("x.csv"), "usage", "not a positive whole number"},
  };
  for (const auto& [args, kind, fragment] : cases) {
    const std::string command = "cd '" + std::string(NEARCAP_SOURCE_DIR) + "' && timeout 60 '" + python +
                                "' analysis/report/" + args + " 2> " + d("err.txt");
    const int status = std::system(command.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << args;
    const std::string err = test::slurp(dir / "err.txt");
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << args << "\n" << err;
    EXPECT_EQ(err.rfind("nearcap: error (" + kind + "): ", 0), 0u) << args << "\n" << err;
    EXPECT_NE(err.find(fragment), std::string::npos) << args << "\n" << err;
    EXPECT_EQ(err.find("Traceback"), std::string::npos) << args << "\n" << err;
  }
  EXPECT_FALSE(fs::exists(dir / "o.png"));
  EXPECT_FALSE(fs::exists(dir / "x.csv"));
  fs::remove_all(dir);
}

TEST(ReportCommand, UnknownSubcommandsAreNamed) {
  const test::CliResult r = test::run_cli("optimize", "optimize");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown subcommand 'optimize'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("report"), std::string::npos) << "the list names the report: " << r.err;
}

}  // namespace
}  // namespace nearcap
