// The inputs of `nearcap tune` and the policy reader, checked like a scene's
// (README "Bad input"): sweep CSVs and policy files are read only from
// regular files within NEARCAP_MAX_INPUT_MB, every line or field at fault is
// named, and every fault is one line on stderr with exit 2, nothing written.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "nearcap/analysis/policy_fit.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;
using gl::ShadowMethod;

constexpr const char* kHeader =
    "configuration,light,method,variant,cracks,wrong,pixels_seen,fallback,refused,light_frustum_defined,light_near_"
    "distance,"
    "l_far_over_width,delta_over_width,skew,cond_light_transform,cap_window_error_px,coordinate_over_size,"
    "l_near_over_l_far,depth_triangles,near_cap_triangles,volume_triangles,depth_fragments,near_cap_fragments,"
    "volume_fragments,frame_ms";

// One row of the policy's variant; `ms` as written in the CSV.
std::string row(const std::string& configuration, const char* method, int cracks, const std::string& ms) {
  return configuration + ",0," + method + ",switch-clamp=clamp-far," + std::to_string(cracks) + "," +
         std::to_string(cracks) + ",19200,,0,1,2.5,4,0.3,0.1,1e3,0.01,2,0.05,1200,40,900,30000,2000,15000," + ms;
}

// A row's fields (the test's rows quote nothing).
std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> fields(1);
  for (char c : line)
    if (c == ',')
      fields.emplace_back();
    else
      fields.back().push_back(c);
  return fields;
}

// `count` configurations, none held out (the split hashes the id), with a
// row of both methods each; times grow with the configuration.
std::vector<std::string> training_configurations(std::size_t count) {
  std::vector<std::string> ids;
  for (int i = 0; ids.size() < count; ++i) {
    const std::string id = "sample:1:" + std::to_string(i);
    if (!analysis::held_out_configuration(id)) ids.push_back(id);
  }
  return ids;
}

// A sweep CSV with rows of both methods for `count` training configurations:
// data line k (from 2) is row k of the file.
std::string sweep_csv(std::size_t count = 8) {
  std::string csv = std::string(kHeader) + "\n";
  int k = 0;
  for (const std::string& id : training_configurations(count)) {
    csv += row(id, "zpplus-corrected", 0, std::to_string(1.0 + 0.1 * k)) + "\n";
    csv += row(id, "zfail", 0, std::to_string(1.5 + 0.1 * k)) + "\n";
    ++k;
  }
  return csv;
}

// `text` with line `line` (1-based) replaced.
std::string with_line(const std::string& text, std::size_t line, const std::string& replacement) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  lines.at(line - 1) = replacement;
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

class PolicyInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nearcap_policy_inputs_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& content) const {
    std::ofstream(dir_ / name, std::ios::binary) << content;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

// One line on stderr, "nearcap: error (KIND): ...", exit 2.
void expect_one_line_error(const test::CliResult& r, const std::string& kind, const std::string& fragment) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("nearcap: error (" + kind + "): ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
}

TEST_F(PolicyInputs, TuneRefusesAnOutputThatIsAnInput) {
  const std::string csv = write("rows.csv", sweep_csv());
  const test::CliResult same = test::run_cli("tune " + csv + " --out " + csv, "tune_same");
  expect_one_line_error(same, "usage", "would replace the sweep CSV the command reads");
  EXPECT_EQ(test::slurp(csv), sweep_csv());
  // Through a symlink, and from a second input.
  fs::create_symlink(csv, dir_ / "link.json");
  const std::string other = write("other.csv", sweep_csv());
  const test::CliResult link =
      test::run_cli("tune " + other + " " + csv + " --out " + (dir_ / "link.json").string(), "tune_link");
  expect_one_line_error(link, "usage", "would replace the sweep CSV the command reads (" + csv + ")");
  EXPECT_EQ(test::slurp(csv), sweep_csv());
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
}

TEST_F(PolicyInputs, TuneRefusesInputsThatAreNotRegularFiles) {
  const std::string out = (dir_ / "p.json").string();
  expect_one_line_error(test::run_cli("tune /dev/zero --out " + out, "tune_zero", test::kHangBound), "io",
                        "/dev/zero: is a character device");
  ASSERT_EQ(::mkfifo((dir_ / "fifo.csv").c_str(), 0600), 0);
  expect_one_line_error(
      test::run_cli("tune " + (dir_ / "fifo.csv").string() + " --out " + out, "tune_fifo", test::kHangBound), "io",
      "is a FIFO");
  expect_one_line_error(test::run_cli("tune " + dir_.string() + " --out " + out, "tune_dir"), "io", "is a directory");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(PolicyInputs, ACsvGivenTwiceIsRefused) {
  const std::string csv = write("t.csv", sweep_csv()), out = (dir_ / "p.json").string();
  expect_one_line_error(test::run_cli("tune " + csv + " " + csv + " --out " + out, "tune_twice"), "parse",
                        csv + ": line 2: configuration '" + training_configurations(8)[0] +
                            "' again, after other configurations (" + csv + ": line 2)");
  EXPECT_FALSE(fs::exists(out));
}

// A line longer than 1 MB is no sweep row: refused naming it, read no
// further (held whole, a line of commas takes tens of bytes of memory per
// byte).
TEST_F(PolicyInputs, TuneRefusesALineLongerThan1Mb) {
  const std::string csv = write("long.csv", with_line(sweep_csv(), 3, std::string((1u << 20) + 1, ',')));
  expect_one_line_error(test::run_cli("tune " + csv + " --out " + (dir_ / "p.json").string(), "tune_long"), "parse",
                        "long.csv: line 3: longer than 1 MB");
  // A line of exactly 1 MB is read (and refused for its field count).
  const std::string fits = write("fits.csv", with_line(sweep_csv(), 3, std::string(1u << 20, ',')));
  expect_one_line_error(test::run_cli("tune " + fits + " --out " + (dir_ / "p.json").string(), "tune_fits"), "parse",
                        "fits.csv: line 3: 1048577 fields, the header has 25");
}

// Lines ended by a carriage return alone read as one line: named as such,
// not as a header with repeated columns; "\r\n" line ends are read.
TEST_F(PolicyInputs, TuneNamesCarriageReturnLineEnds) {
  std::string cr = sweep_csv(), crlf;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  for (const char c : sweep_csv()) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  const std::string out = (dir_ / "p.json").string();
  expect_one_line_error(test::run_cli("tune " + write("cr.csv", cr) + " --out " + out, "tune_cr"), "parse",
                        "cr.csv: line 1: a carriage return inside the line at column 351");
  const test::CliResult r = test::run_cli("tune " + write("crlf.csv", crlf) + " --out " + out, "tune_crlf");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(PolicyInputs, TheInputLimitAppliesToSweepCsvsAndPolicies) {
  // Rows of a method tune does not read, past 1 MB.
  std::string big = sweep_csv();
  for (int k = 0; big.size() < (3u << 19); ++k) big += row("sample:9:" + std::to_string(k), "preload", 0, "1") + "\n";
  const std::string csv = write("big.csv", big);
  const std::string out = (dir_ / "p.json").string();
  expect_one_line_error(test::run_cli("tune " + csv + " --out " + out, "tune_big", "NEARCAP_MAX_INPUT_MB=1"),
                        "resource", "NEARCAP_MAX_INPUT_MB");
  EXPECT_EQ(test::run_cli("tune " + csv + " --out " + out, "tune_big_raised", "NEARCAP_MAX_INPUT_MB=2").exit_code, 0);
  std::string policy = test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data" / "policy.json");
  policy += std::string(3u << 19, ' ');
  const std::string big_policy = write("big.json", policy);
  expect_one_line_error(
      test::run_cli("cracks data/scenes/near_cap_bunny_wall.json --light 0 --method policy --policy " + big_policy,
                    "policy_big", "NEARCAP_MAX_INPUT_MB=1"),
      "resource", "NEARCAP_MAX_INPUT_MB");
  expect_one_line_error(test::run_cli("cracks data/scenes/near_cap_bunny_wall.json --light 0 --method policy --policy "
                                      "/dev/zero",
                                      "policy_zero", test::kHangBound),
                        "io", "/dev/zero: is a character device");
}

TEST_F(PolicyInputs, TuneNamesTheFirstBadLine) {
  const std::string out = (dir_ / "p.json").string();
  const std::string not_utf8 = write("latin1.csv", with_line(sweep_csv(), 3, row("sample:\xe9t\xe9", "zfail", 0, "1")));
  expect_one_line_error(test::run_cli("tune " + not_utf8 + " --out " + out, "tune_utf8"), "parse",
                        not_utf8 + ": line 3: not UTF-8 (byte 0xE9");
  std::string fast = row(training_configurations(8)[1], "zpplus-corrected", 0, "1");
  fast.replace(fast.find(",2.5,"), 5, ",fast,");
  const std::string bad = write("bad.csv", with_line(sweep_csv(), 4, fast));
  expect_one_line_error(test::run_cli("tune " + bad + " --out " + out, "tune_column"), "parse",
                        bad + ": line 4: column 'light_near_distance': 'fast' is not a number");
  EXPECT_FALSE(fs::exists(out));
}

// An infinite or NaN crack count: one line naming the file, line and
// column, and nothing of the solver's on stderr.
TEST_F(PolicyInputs, NonFiniteCountsAreOneLineWithoutSolverLog) {
  const std::string out = (dir_ / "p.json").string();
  for (const char* count : {"inf", "nan"}) {
    std::string line = row(training_configurations(8)[1], "zfail", 0, "1");
    line.replace(line.find(",zfail,switch-clamp=clamp-far,0,"), 32,
                 std::string(",zfail,switch-clamp=clamp-far,") + count + ",");
    const std::string csv = write("t.csv", with_line(sweep_csv(), 5, line));
    expect_one_line_error(test::run_cli("tune " + csv + " --out " + out, "tune_inf"), "non-finite",
                          csv + ": line 5: column 'cracks': '" + count + "' is not a finite number");
  }
  EXPECT_FALSE(fs::exists(out));
}

// Features spanning 600 decades and a crack to fit: the fit fails or not,
// but the solver's own log (glog) stays off stderr unless
// NEARCAP_SOLVER_LOG=1.
TEST_F(PolicyInputs, TheSolverIsSilentUnlessAsked) {
  std::string csv = sweep_csv();
  for (std::size_t line = 2; line <= 17; ++line) {
    const std::string id = training_configurations(8)[(line - 2) / 2];
    std::string r = row(id, line % 2 ? "zfail" : "zpplus-corrected", line == 2 ? 1 : 0, "1");
    r.replace(r.find(",2.5,"), 5, line % 3 ? ",1e300," : ",1e-300,");
    csv = with_line(csv, line, r);
  }
  const std::string rows = write("huge.csv", csv), out = (dir_ / "p.json").string();
  const test::CliResult quiet = test::run_cli("tune " + rows + " --out " + out, "tune_quiet");
  if (quiet.exit_code == 0)
    EXPECT_TRUE(quiet.err.empty()) << quiet.err;
  else
    expect_one_line_error(quiet, "degenerate", "fit failed");
  const test::CliResult loud = test::run_cli("tune " + rows + " --out " + out, "tune_loud", "NEARCAP_SOLVER_LOG=1");
  EXPECT_NE(loud.err.find("Solver Summary"), std::string::npos) << loud.err;
}

// A policy names each feature once (the reader refuses a repeated one), so
// tune refuses one too, before writing.
TEST_F(PolicyInputs, TuneRefusesARepeatedFeature) {
  const std::string csv = write("rows.csv", sweep_csv()), out = (dir_ / "p.json").string();
  expect_one_line_error(
      test::run_cli("tune " + csv + " --features log_skew,l_near_over_l_far,log_skew --out " + out, "tune_features"),
      "usage", "'log_skew' is named twice");
  EXPECT_FALSE(fs::exists(out));
}

// Few configurations, none held out: the held-out side is empty, and the
// policy is written, with no cost model (the decision reads none).
TEST_F(PolicyInputs, TuneWithoutHeldOutPairs) {
  const std::string csv = write("rows.csv", sweep_csv()), out = (dir_ / "p.json").string();
  const test::CliResult r = test::run_cli("tune " + csv + " --out " + out, "tune_no_held_out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_NE(r.out.find("held out: 0 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fits the policy uses:"), std::string::npos) << r.out;
  const analysis::SwitchPolicy p = analysis::load_policy(out);
  EXPECT_TRUE(p.cost_models.empty());
}

// --variant names the rows' variant with its choices in any order: the
// sweep labels it with them in its own order.
TEST_F(PolicyInputs, TuneReadsAVariantNamedInAnyOrder) {
  std::string csv = sweep_csv();
  const std::string label = ",switch-clamp=clamp-far,", sorted = ",\"l-near-scale=0.5,switch-clamp=clamp-far\",";
  for (std::size_t at = csv.find(label); at != std::string::npos; at = csv.find(label, at + sorted.size()))
    csv.replace(at, label.size(), sorted);
  const std::string rows = write("rows.csv", csv), out = (dir_ / "p.json").string();
  for (const char* given : {"switch-clamp=clamp-far,l-near-scale=0.5", "l-near-scale=0.5,switch-clamp=clamp-far"}) {
    const test::CliResult r = test::run_cli("tune " + rows + " --variant " + given + " --out " + out, "tune_order");
    EXPECT_EQ(r.exit_code, 0) << given << "\n" << r.err;
  }
  expect_one_line_error(test::run_cli("tune " + rows + " --variant bogus=1 --out " + out, "tune_bogus"), "usage",
                        "--variant 'bogus=1': unknown choice 'bogus'");
  expect_one_line_error(
      test::run_cli("tune " + rows + " --variant l-near-scale=0.5,l-near-scale=1 --out " + out, "tune_twice"), "usage",
      "l-near-scale is given twice");
  // --features' list words stand alone, as --kinds' do.
  for (const char* features : {"all,all", "skew,none"})
    expect_one_line_error(test::run_cli("tune " + rows + " --features " + features + " --out " + out, "tune_all"),
                          "usage", "stands alone");
}

// A crack in training: tune would fit a crack model; with --no-exact-zpass
// the decision never asks it, so tune fits none unless --features asks for
// one, which it refuses (one line, usage, no file, before reading the rows:
// a missing CSV is not reached), saying how to write the policy without one.
TEST_F(PolicyInputs, TuneRefusesACrackModelItsSwitchesBypass) {
  const std::string id = training_configurations(8).front();
  const std::string csv = write("rows.csv", with_line(sweep_csv(), 2, row(id, "zpplus-corrected", 1, "1.0")));
  const std::string out = (dir_ / "p.json").string();
  const std::string bypass = " --light-projection clipped-sides --no-exact-zpass";
  const test::CliResult implied = test::run_cli("tune " + csv + bypass + " --out " + out, "tune_implied");
  ASSERT_EQ(implied.exit_code, 0) << implied.err;
  EXPECT_NE(implied.out.find("no crack model: none with --no-exact-zpass"), std::string::npos) << implied.out;
  EXPECT_TRUE(analysis::load_policy(out).crack_model.features.empty());
  fs::remove(out);
  expect_one_line_error(test::run_cli("tune " + csv + bypass + " --features all --out " + out, "tune_bypassed"),
                        "usage", "a crack model (--features all) would never be read: with --no-exact-zpass");
  expect_one_line_error(
      test::run_cli("tune " + (dir_ / "missing.csv").string() + bypass + " --features log_skew --out " + out,
                    "tune_bypassed_unread"),
      "usage", "a crack model (--features log_skew) would never be read");
  EXPECT_FALSE(fs::exists(out));
  const test::CliResult none = test::run_cli("tune " + csv + bypass + " --features none --out " + out, "tune_none");
  ASSERT_EQ(none.exit_code, 0) << none.err;
  EXPECT_NE(none.out.find("fits the policy uses: none"), std::string::npos) << none.out;
  EXPECT_TRUE(analysis::load_policy(out).crack_model.features.empty());
  // With the exact Z-pass test the model is asked, and written.
  const test::CliResult read = test::run_cli("tune " + csv + " --features log_skew --out " + out, "tune_read");
  ASSERT_EQ(read.exit_code, 0) << read.err;
  EXPECT_NE(read.out.find("fits the policy uses: the crack model (log_skew)"), std::string::npos) << read.out;
  EXPECT_EQ(analysis::load_policy(out).crack_model.features, std::vector<std::string>{"log_skew"});
}

// A crack model predicts the cracks of the frames its rows drew: a policy
// carrying one that would draw another cap or depth than the rows' variant
// is refused, naming the choice; the rows' variant's choices pass, and a
// policy without a model takes any.  --plain with no model is refused.
TEST_F(PolicyInputs, TuneRefusesACrackModelForFramesItsRowsDidNotDraw) {
  const std::string id = training_configurations(8).front();
  const std::string cracked = with_line(sweep_csv(), 2, row(id, "zpplus-corrected", 1, "1.0"));
  const std::string csv = write("rows.csv", cracked);
  const std::string out = (dir_ / "p.json").string();
  expect_one_line_error(test::run_cli("tune " + csv + " --light-projection glfrustum --out " + out, "tune_projection"),
                        "usage",
                        "--light-projection glfrustum: the rows of variant 'switch-clamp=clamp-far' were drawn with "
                        "light-projection=paper");
  expect_one_line_error(test::run_cli("tune " + csv + " --depth float32 --out " + out, "tune_depth"), "usage",
                        "--depth float32: the rows of variant 'switch-clamp=clamp-far' were drawn with depth=fixed24");
  // Asked for by --features: refused from the options, before the rows are
  // read (a missing CSV is not reached).
  expect_one_line_error(
      test::run_cli("tune " + (dir_ / "missing.csv").string() + " --features log_skew --depth float32 --out " + out,
                    "tune_depth_unread"),
      "usage", "--depth float32: the rows of variant 'switch-clamp=clamp-far'");
  expect_one_line_error(test::run_cli("tune " + csv + " --features none --plain --out " + out, "tune_plain"), "usage",
                        "--plain is read only when a crack model is fitted");
  EXPECT_FALSE(fs::exists(out));
  // The rows' own choices, named or left at their defaults.
  ASSERT_EQ(
      test::run_cli("tune " + csv + " --light-projection paper --depth fixed24 --out " + out, "tune_same").exit_code,
      0);
  std::string glfrustum = cracked;
  const std::string variant = ",switch-clamp=clamp-far,",
                    drawn_variant = ",\"light-projection=glfrustum,switch-clamp=clamp-far\",";
  for (std::size_t at = 0; (at = glfrustum.find(variant, at)) != std::string::npos; at += drawn_variant.size())
    glfrustum.replace(at, variant.size(), drawn_variant);
  const test::CliResult drawn = test::run_cli("tune " + write("glfrustum.csv", glfrustum) +
                                                  " --variant light-projection=glfrustum,switch-clamp=clamp-far "
                                                  "--light-projection glfrustum --out " +
                                                  out,
                                              "tune_drawn");
  EXPECT_EQ(drawn.exit_code, 0) << drawn.err;
  const test::CliResult no_model =
      test::run_cli("tune " + csv + " --light-projection glfrustum --features none --out " + out, "tune_no_model");
  EXPECT_EQ(no_model.exit_code, 0) << no_model.err;
}

TEST_F(PolicyInputs, APolicyNumberBeyondDoubleIsAParseError) {
  std::string policy = test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data" / "policy.json");
  const nlohmann::json j = nlohmann::json::parse(policy);
  const std::string bias = nlohmann::json(j["crack_model"]["bias"]).dump();
  policy.replace(policy.find("\"bias\": " + bias), 8 + bias.size(), "\"bias\": 1e999");
  const std::string file = write("overflow.json", policy);
  expect_one_line_error(
      test::run_cli("cracks data/scenes/near_cap_bunny_wall.json --light 0 --method policy --policy " + file,
                    "policy_overflow"),
      "parse", file + ": crack_model.bias: malformed JSON: number overflow");
}

// The reader, on text: each fault a Schema error naming the field.
std::string valid_policy() {
  return R"({"format": "nearcap-policy", "version": 3, "capped_method": "zpplus-corrected",
  "fallback_method": "zfail", "switch_clamp": "clamp-far", "zpass_far": "infinite",
  "crack_model": {"features": ["log_skew", "l_near_over_l_far"], "mean": [0, 0.2], "scale": [1, 0.1],
                  "weights": [1.5, -0.5], "bias": -3, "threshold": 0.01},
  "cost_models": {"zfail": {"intercept_ms": 0.1, "ms_per_mtriangle": 2, "ms_per_mfragment": 0.5}},
  "provenance": {"command": "test", "train": {"samples": 3}}})";
}

std::string replaced(const std::string& from, const std::string& to) {
  std::string text = valid_policy();
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

void expect_policy_error(const std::string& text, ErrorKind kind, const std::string& fragment) {
  try {
    analysis::parse_policy(text, "p.json");
    ADD_FAILURE() << "accepted: " << fragment;
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.kind(), kind) << what;
    EXPECT_EQ(what.rfind("p.json: ", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
  }
}

TEST(PolicyReader, IsStrict) {
  ASSERT_NO_THROW(analysis::parse_policy(valid_policy(), "p.json"));
  expect_policy_error(replaced("\"version\": 3", "\"version\": 3, \"version\": 3"), ErrorKind::Schema,
                      "p.json: version: duplicate key");
  expect_policy_error(replaced("\"bias\": -3", "\"bias\": -3, \"bias\": 4"), ErrorKind::Schema,
                      "crack_model.bias: duplicate key");
  expect_policy_error(replaced("\"samples\": 3", "\"samples\": 3, \"samples\": 4"), ErrorKind::Schema,
                      "provenance.train.samples: duplicate key");
  expect_policy_error(replaced("\"cost_models\": {\"zfail\": {\"intercept_ms\": 0.1, \"ms_per_mtriangle\": 2, "
                               "\"ms_per_mfragment\": 0.5}},",
                               ""),
                      ErrorKind::Schema, "cost_models: missing");
  expect_policy_error(replaced(",\n  \"provenance\": {\"command\": \"test\", \"train\": {\"samples\": 3}}", ""),
                      ErrorKind::Schema, "provenance: missing");
  expect_policy_error(replaced("\"l_near_over_l_far\"]", "\"log_skew\"]"), ErrorKind::Schema,
                      "crack_model.features[1]: 'log_skew' appears twice");
  expect_policy_error(replaced("\"version\": 3", "\"version\": 99"), ErrorKind::Schema,
                      "version: 99 is not a version this nearcap reads (1 to 6)");
  expect_policy_error(replaced("\"bias\": -3", "\"bias\": 1e999"), ErrorKind::Parse,
                      "p.json: crack_model.bias: malformed JSON: number overflow parsing '1e999'");
  expect_policy_error(replaced("\"mean\": [0, 0.2]", "\"mean\": [0, -1e999]"), ErrorKind::Parse,
                      "crack_model.mean[1]: malformed JSON: number overflow");
  expect_policy_error(replaced("\"command\": \"test\"", "\"command\": \"t\xff\""), ErrorKind::Parse,
                      "ill-formed UTF-8");
}

// unpriced_frames: read and written back; only with a device profile, a
// known method, a count, and tiers ascending; one tier may be the object
// alone.
TEST(PolicyReader, UnpricedFramesNeedAProfileAndAKnownMethodAndAscendingTiers) {
  const std::string shipped = test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data" / "policy.json");
  const analysis::SwitchPolicy p = analysis::parse_policy(shipped, "p.json");
  ASSERT_FALSE(p.unpriced_frames.empty());
  const analysis::SwitchPolicy q = analysis::parse_policy(analysis::policy_to_json(p), "q.json");
  ASSERT_EQ(q.unpriced_frames.size(), p.unpriced_frames.size());
  for (std::size_t k = 0; k < p.unpriced_frames.size(); ++k) {
    EXPECT_EQ(q.unpriced_frames[k].max_occluder_triangles, p.unpriced_frames[k].max_occluder_triangles);
    EXPECT_EQ(q.unpriced_frames[k].method.name(), p.unpriced_frames[k].method.name());
  }
  using Json = nlohmann::json;
  const Json shipped_json = Json::parse(shipped);
  auto with = [&](const Json& tiers) {
    Json j = shipped_json;
    j["unpriced_frames"] = tiers;
    return j.dump(1);
  };
  auto tier = [](const Json& max, const Json& method) {
    return Json{{"max_occluder_triangles", max}, {"method", method}};
  };
  const analysis::SwitchPolicy one = analysis::parse_policy(with(tier(12, "zfail")), "one.json");
  ASSERT_EQ(one.unpriced_frames.size(), 1u);
  EXPECT_EQ(one.unpriced_frames[0].max_occluder_triangles, 12u);
  EXPECT_EQ(one.unpriced_frames[0].method.method, gl::ShadowMethod::ZFail);
  const analysis::SwitchPolicy two =
      analysis::parse_policy(with(Json::array({tier(12, "zfail"), tier(6400, "zpplus-clipped-sides")})), "two.json");
  ASSERT_EQ(two.unpriced_frames.size(), 2u);
  EXPECT_EQ(two.unpriced_frames[1].max_occluder_triangles, 6400u);
  EXPECT_EQ(two.unpriced_frames[1].method.name(), "zpplus-clipped-sides");

  expect_policy_error(with(tier(12, "zpass")), ErrorKind::Schema,
                      "unpriced_frames.method: 'zpass' is not zfail or zpplus-clipped-sides");
  expect_policy_error(with(Json::array({tier(12, "zfail"), tier(100, "zpass")})), ErrorKind::Schema,
                      "unpriced_frames[1].method: 'zpass' is not zfail or zpplus-clipped-sides");
  expect_policy_error(with(Json::array({tier(-1, "zfail")})), ErrorKind::Schema,
                      "unpriced_frames[0].max_occluder_triangles: must not be negative");
  expect_policy_error(with(tier(1.5, "zfail")), ErrorKind::Schema, "unpriced_frames.max_occluder_triangles");
  expect_policy_error(with(Json::array({Json{{"method", "zfail"}}})), ErrorKind::Schema,
                      "unpriced_frames[0].max_occluder_triangles: missing");
  Json extra = tier(12, "zfail");
  extra["x"] = 1;
  expect_policy_error(with(Json::array({extra})), ErrorKind::Schema, "unpriced_frames[0].x");
  expect_policy_error(with(Json::array({tier(12, "zfail"), tier(12, "zpplus-clipped-sides")})), ErrorKind::Schema,
                      "unpriced_frames[1].max_occluder_triangles: must be above the tier before's (12)");
  expect_policy_error(with(Json::array()), ErrorKind::Schema, "unpriced_frames: expected at least one tier");
  expect_policy_error(with("zfail"), ErrorKind::Schema, "unpriced_frames: expected a JSON object");
  std::string v4 = shipped;
  v4.replace(v4.find("\"version\": 6"), 12, "\"version\": 4");
  expect_policy_error(v4, ErrorKind::Schema, "unpriced_frames: is a version 5 field (this file says version 4)");
  // Version 5 holds one tier, the object alone; its tiers are version 6's.
  Json v5 = Json::parse(with(Json::array({tier(12, "zfail")})));
  v5["version"] = 5;
  expect_policy_error(v5.dump(), ErrorKind::Schema, "unpriced_frames: is a version 6 field (this file says version 5)");
  v5["unpriced_frames"] = tier(12, "zfail");
  EXPECT_EQ(analysis::parse_policy(v5.dump(), "v5.json").unpriced_frames.size(), 1u);
  // Without the profile it would name frames that nothing prices.
  Json j = shipped_json;
  j.erase("device_profile");
  expect_policy_error(j.dump(), ErrorKind::Schema, "unpriced_frames: needs a device_profile");
}

// What tune writes it reads back, also without cost models.
TEST(PolicyReader, ReadsWhatItWritesWithoutCostModels) {
  analysis::SwitchPolicy p = analysis::parse_policy(valid_policy(), "p.json");
  p.cost_models.clear();
  const analysis::SwitchPolicy q = analysis::parse_policy(analysis::policy_to_json(p), "q.json");
  EXPECT_TRUE(q.cost_models.empty());
  EXPECT_EQ(analysis::policy_to_json(q), analysis::policy_to_json(p));
}

// The CSV reader on text (what fuzz_csv calls): the first bad line named.
// `both`: the policy samples' reader too (it reads no time columns).
void expect_csv_error(const std::string& csv, ErrorKind kind, const std::string& fragment, bool both = true) {
  for (int reader = both ? 0 : 1; reader < 2; ++reader) {
    try {
      if (reader == 0)
        (void)analysis::policy_samples_from_text(csv, "s.csv", ShadowMethod::ZPPlusCorrected, ShadowMethod::ZFail);
      else
        (void)analysis::cost_samples_from_text(csv, "s.csv", ShadowMethod::ZFail);
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(e.kind(), kind) << what;
      EXPECT_NE(what.find(fragment), std::string::npos) << what;
    }
  }
}

TEST(PolicyCsv, NamesTheFirstBadLineAndColumn) {
  const std::string csv = sweep_csv();
  EXPECT_EQ(analysis::policy_samples_from_text(csv, "s.csv", ShadowMethod::ZPPlusCorrected, ShadowMethod::ZFail).size(),
            8u);
  EXPECT_EQ(analysis::cost_samples_from_text(csv, "s.csv", ShadowMethod::ZFail).size(), 8u);
  expect_csv_error(with_line(csv, 3, "a,b"), ErrorKind::Parse, "s.csv: line 3: 2 fields, the header has 25");
  expect_csv_error(with_line(csv, 1, "x" + std::string(kHeader)), ErrorKind::Schema,
                   "s.csv: line 1: missing column 'configuration'");
  // A byte order mark before the header is read past.
  EXPECT_EQ(analysis::cost_samples_from_text("\xEF\xBB\xBF" + csv, "s.csv", ShadowMethod::ZFail).size(), 8u);
  expect_csv_error(with_line(csv, 4, row("sample:1:1", "zfail", 0, "1.5ms")), ErrorKind::Parse,
                   "s.csv: line 4: column 'frame_ms': '1.5ms' is not a number", false);
  expect_csv_error(with_line(csv, 4, row("\"sample:1:1", "zfail", 0, "1")), ErrorKind::Parse,
                   "s.csv: line 4: a quoted field is not closed");
  expect_csv_error(with_line(csv, 5, row("sample:1:1", "zfail", 0, "-inf")), ErrorKind::NonFinite,
                   "s.csv: line 5: column 'frame_ms': '-inf' is not a finite number", false);
  expect_csv_error(with_line(csv, 6, row("sample:1:1", "zfail", 0, "1e999")), ErrorKind::Parse,
                   "s.csv: line 6: column 'frame_ms': '1e999'", false);
  // Spellings the sweep never writes, as report refuses them.
  for (const char* spelling : {"0x10", "+1", "1e-400", "infinity", " 1", "1 "})
    expect_csv_error(with_line(csv, 6, row("sample:1:1", "zfail", 0, spelling)), ErrorKind::Parse,
                     "s.csv: line 6: column 'frame_ms': '" + std::string(spelling) + "' is not a number", false);
  expect_csv_error(with_line(csv, 1, std::string(kHeader) + ",frame_ms"), ErrorKind::Parse,
                   "s.csv: line 1: column 'frame_ms' appears twice");
  expect_csv_error(with_line(csv, 2, "\xc0\xaf"), ErrorKind::Parse, "s.csv: line 2: not UTF-8 (byte 0xC0 at column 1");
  expect_csv_error("", ErrorKind::Parse, "s.csv: empty");
}

// A length ratio or a condition number the sweep never writes negative
// (every feature but the light's near distance) is refused, not fitted
// through its log's magnitude.
TEST(PolicyCsv, NegativeMagnitudesAreRefused) {
  const std::vector<std::string> header = split_commas(kHeader);
  std::size_t refused = 0;
  for (const char* column : {"l_far_over_width", "delta_over_width", "skew", "cond_light_transform",
                             "cap_window_error_px", "coordinate_over_size", "l_near_over_l_far"}) {
    SCOPED_TRACE(column);
    std::vector<std::string> fields = split_commas(row("sample:1:1", "zpplus-corrected", 0, "1"));
    const std::size_t k = static_cast<std::size_t>(std::find(header.begin(), header.end(), column) - header.begin());
    ASSERT_LT(k, fields.size());
    fields[k] = "-" + fields[k];
    std::string r;
    for (const std::string& f : fields) r += (r.empty() ? "" : ",") + f;
    try {
      (void)analysis::policy_samples_from_text(with_line(sweep_csv(), 3, r), "s.csv", ShadowMethod::ZPPlusCorrected,
                                               ShadowMethod::ZFail);
      ADD_FAILURE() << "a negative " << column << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Parse) << e.what();
      EXPECT_NE(std::string(e.what()).find("s.csv: line 3: column '" + std::string(column) + "': '" + fields[k] +
                                           "' is negative"),
                std::string::npos)
          << e.what();
      ++refused;
    }
  }
  EXPECT_EQ(refused, 7u);
}

// A row repeated, a configuration's rows apart, or one CSV given twice
// would count twice in the fits: refused, naming the line.
TEST(PolicyCsv, EachRowOnceAndEachConfigurationTogether) {
  const std::string csv = sweep_csv();
  const std::vector<std::string> ids = training_configurations(8);
  const std::string repeated = csv + row(ids[7], "zfail", 0, "9") + "\n";
  expect_csv_error(repeated, ErrorKind::Parse,
                   "s.csv: line 18: a second row of configuration '" + ids[7] +
                       "', light 0, method zfail, variant switch-clamp=clamp-far");
  const std::string apart = csv + row(ids[0], "preload", 0, "9") + "\n";
  expect_csv_error(apart, ErrorKind::Parse,
                   "s.csv: line 18: configuration '" + ids[0] + "' again, after other configurations (s.csv: line 2)");
  const std::string empty_id = with_line(csv, 2, row("", "zfail", 0, "1"));
  expect_csv_error(empty_id, ErrorKind::Parse, "s.csv: line 2: column 'configuration': is empty");
}

// Counts in decimal digits, flags 0 or 1, and cracks among the wrong pixels
// among those seen, as the sweep writes them and the report reads them: a
// row that breaks one is refused, not read another way.
TEST(PolicyCsv, CountsFlagsAndCracksAsTheSweepWritesThem) {
  const std::string csv = sweep_csv();
  const std::string id = training_configurations(8)[1];
  auto edited = [&](const std::string& from, const std::string& to) {
    std::string r = row(id, "zpplus-corrected", 0, "1");
    const std::size_t at = r.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return with_line(csv, 4, r.replace(at, from.size(), to));
  };
  auto refused = [](const std::string& text, const std::string& fragment) {
    try {
      (void)analysis::policy_samples_from_text(text, "s.csv", ShadowMethod::ZPPlusCorrected, ShadowMethod::ZFail);
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Parse) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  const std::string cracks = ",switch-clamp=clamp-far,0,0,19200,";
  refused(edited(cracks, ",switch-clamp=clamp-far,1e3,1000,19200,"),
          "line 4: column 'cracks': '1e3' is not a whole number as the sweep writes it");
  refused(edited(cracks, ",switch-clamp=clamp-far,5,0,19200,"), "line 4: column 'cracks': 5 cracks of 0 wrong pixels");
  refused(edited(cracks, ",switch-clamp=clamp-far,0,19201,19200,"),
          "line 4: column 'wrong': 19201 wrong pixels of 19200 seen");
  refused(edited(",19200,,0,1,", ",19200,,0,yes,"), "line 4: column 'light_frustum_defined': 'yes' is not 0 or 1");
  refused(edited(",19200,,0,1,", ",19200,,2,1,"), "line 4: column 'refused': '2' is not 0 or 1");
  refused(edited(cracks, ",switch-clamp=clamp-far,0,99999999999999999,19200,"),
          "line 4: column 'wrong': '99999999999999999' is over 2^53");
  // Rows the fit does not take are read alike.
  std::string other = row("sample:9:0", "preload", 0, "1");
  other.replace(other.find(",19200,,0,1,"), 12, ",19200,,2,1,");
  refused(csv + other + "\n", "line 18: column 'refused': '2' is not 0 or 1");
}

TEST(PolicyCsv, CountsAreWholeNumbers) {
  const std::string csv = sweep_csv();
  std::string r = row("sample:1:1", "zfail", 0, "1");
  r.replace(r.find(",0,zfail,"), 9, ",0.5,zfail,");
  try {
    (void)analysis::policy_samples_from_text(with_line(csv, 3, r), "s.csv", ShadowMethod::ZPPlusCorrected,
                                             ShadowMethod::ZFail);
    ADD_FAILURE() << "a fractional light index was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("s.csv: line 3: column 'light': '0.5' is not a whole number"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace nearcap
