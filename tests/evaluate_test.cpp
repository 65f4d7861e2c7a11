// The policy's evaluation against the oracle: the table from synthetic rows
// (analysis/policy_evaluation.hpp), and `nearcap evaluate` end to end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "nearcap/analysis/frame_time_drift.hpp"
#include "nearcap/analysis/policy_evaluation.hpp"
#include "nearcap/analysis/switch_policy.hpp"

namespace nearcap {
namespace {

using analysis::EvaluationRow;

EvaluationRow row(const std::string& configuration, const std::string& rule, double end_to_end_ms,
                  std::size_t wrong = 0, std::size_t cracks = 0, const std::string& set = "seed-7", int frame = -1) {
  EvaluationRow r;
  r.set = set;
  r.configuration = configuration;
  r.frame = frame;
  r.rule = rule;
  r.end_to_end_ms = end_to_end_ms;
  r.cpu_ms = end_to_end_ms / 10;
  r.wrong = wrong;
  r.cracks = cracks;
  return r;
}

// Every rule of one (configuration, light) at `ms`, Z-fail's wrong pixels
// and cracks given: the rows a test then changes.
std::vector<EvaluationRow> group(const std::string& configuration, double ms, std::size_t zfail_wrong = 0,
                                 std::size_t zfail_cracks = 0, const std::string& set = "seed-7", int frame = -1) {
  std::vector<EvaluationRow> rows;
  for (const analysis::EvaluationRuleInfo& info : analysis::kEvaluationRules)
    rows.push_back(row(configuration, std::string(info.name), ms, zfail_wrong, zfail_cracks, set, frame));
  return rows;
}

EvaluationRow& find(std::vector<EvaluationRow>& rows, const std::string& configuration, const std::string& rule) {
  for (EvaluationRow& r : rows)
    if (r.configuration == configuration && r.rule == rule) return r;
  throw std::runtime_error("no row " + configuration + " " + rule);
}

std::vector<EvaluationRow> joined(std::vector<EvaluationRow> a, const std::vector<EvaluationRow>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Two configurations: in c1 ZP+ clipped is fastest and right; in c2 Z-pass
// is fastest but wrong where Z-fail is right, so the oracle is the next
// fastest right candidate, ZP+ corrected.
TEST(PolicyEvaluation, OracleIsTheFastestCandidateAsRightAsZFail) {
  std::vector<EvaluationRow> rows = joined(group("c1", 10), group("c2", 20));
  find(rows, "c1", "zpplus-clipped").end_to_end_ms = 4;
  find(rows, "c1", "policy").end_to_end_ms = 6;
  find(rows, "c2", "zpass").end_to_end_ms = 1;
  find(rows, "c2", "zpass").wrong = 5;
  find(rows, "c2", "zpplus-corrected").end_to_end_ms = 8;
  find(rows, "c2", "policy").end_to_end_ms = 12;
  find(rows, "c2", "doom3").end_to_end_ms = 30;
  const analysis::EvaluationTable table = analysis::evaluate_rows(rows);
  ASSERT_EQ(table.sets.size(), 1u);
  const analysis::SetTable& t = table.sets[0];
  EXPECT_EQ(t.groups, 2u);
  EXPECT_EQ(t.excluded, 0u);
  ASSERT_EQ(table.oracle_rows.size(), 2u);
  EXPECT_EQ(table.oracle_rows[0].chosen, "zpplus-clipped");
  EXPECT_EQ(table.oracle_rows[1].chosen, "zpplus-corrected");
  const analysis::RuleTotals* oracle = t.find("oracle");
  const analysis::RuleTotals* policy = t.find("policy");
  const analysis::RuleTotals* doom3 = t.find("doom3");
  const analysis::RuleTotals* zpass = t.find("zpass");
  ASSERT_TRUE(oracle && policy && doom3 && zpass);
  EXPECT_DOUBLE_EQ(oracle->end_to_end_ms, 4 + 8);
  EXPECT_DOUBLE_EQ(policy->end_to_end_ms, 6 + 12);
  EXPECT_DOUBLE_EQ(policy->ratio_to_oracle, 18.0 / 12.0);
  EXPECT_DOUBLE_EQ(doom3->end_to_end_ms, 10 + 30);
  EXPECT_DOUBLE_EQ(doom3->cpu_ms, 1 + 2);  // its CPU time as set by group()
  EXPECT_EQ(zpass->violations, 1u);
  EXPECT_EQ(zpass->wrong, 5u);
  EXPECT_EQ(policy->violations, 0u);
  EXPECT_EQ(t.oracle_choices.at("zpplus-clipped"), 1u);
  // The table lists the oracle, the policy, every fixed rule and candidate.
  EXPECT_EQ(t.rules.size(), analysis::kEvaluationRules.size() + 1);
  EXPECT_EQ(t.rules[0].rule, "oracle");
  EXPECT_EQ(t.rules[1].rule, "policy");
}

// A rule with a crack Z-fail lacks is not as right as Z-fail, even with no
// more wrong pixels; nor one with wrong pixels where Z-fail has none.
TEST(PolicyEvaluation, ACrackZFailLacksIsAViolation) {
  std::vector<EvaluationRow> rows = joined(group("c1", 10, 3, 0), group("c2", 10));
  find(rows, "c1", "policy").cracks = 1;               // 3 wrong pixels like Z-fail's, one of them a crack
  find(rows, "c1", "policy").end_to_end_ms = 2;        // fast, but not a candidate
  find(rows, "c1", "zpplus-paper").cracks = 1;         // a candidate with the crack: not the oracle
  find(rows, "c1", "zpplus-paper").end_to_end_ms = 1;  //
  find(rows, "c2", "exact-zpass+clipped").wrong = 1;   // Z-fail has none here
  const analysis::EvaluationTable table = analysis::evaluate_rows(rows);
  const analysis::SetTable& t = table.sets.at(0);
  EXPECT_EQ(t.find("policy")->violations, 1u);
  EXPECT_EQ(t.find("policy")->cracks, 1u);
  EXPECT_EQ(t.find("zpplus-paper")->violations, 1u);
  EXPECT_EQ(t.find("exact-zpass+clipped")->violations, 1u);
  EXPECT_EQ(t.find("always-zfail")->violations, 0u);
  EXPECT_EQ(table.oracle_rows.at(0).chosen, "zpass");  // the first of the candidates at 10 ms, all right
  EXPECT_TRUE(analysis::as_right_as_zfail(find(rows, "c1", "zfail"), find(rows, "c1", "zfail")));
  EXPECT_FALSE(analysis::as_right_as_zfail(find(rows, "c1", "policy"), find(rows, "c1", "zfail")));
}

// Z-pass where the exact test finds a near-cap does not apply: never the
// oracle, and its total counts Z-fail's frame there.
TEST(PolicyEvaluation, ZPassThatDoesNotApplyIsNoCandidate) {
  std::vector<EvaluationRow> rows = group("c1", 10);
  find(rows, "c1", "zpass").end_to_end_ms = 1;
  find(rows, "c1", "zpass").applies = false;
  find(rows, "c1", "zfail").end_to_end_ms = 9;
  const analysis::EvaluationTable table = analysis::evaluate_rows(rows);
  EXPECT_EQ(table.oracle_rows.at(0).chosen, "zfail");
  EXPECT_DOUBLE_EQ(table.sets.at(0).find("zpass")->end_to_end_ms, 9);
}

// The oracle chooses among the exact-zpass mixes too (Z-pass per occluder
// where the exact test allows), never among the engine rules or the policy.
TEST(PolicyEvaluation, OracleChoosesAmongTheExactZPassMixesNotTheEngineRules) {
  std::vector<EvaluationRow> rows = joined(group("c1", 10), group("c2", 10));
  find(rows, "c1", "exact-zpass+clipped").end_to_end_ms = 3;
  find(rows, "c1", "doom3-bfg").end_to_end_ms = 2;
  find(rows, "c1", "policy").end_to_end_ms = 1;
  find(rows, "c2", "exact-zpass+zfail").end_to_end_ms = 4;
  find(rows, "c2", "always-zfail").end_to_end_ms = 2;  // the zfail candidate's alias: not itself a candidate
  const analysis::EvaluationTable table = analysis::evaluate_rows(rows);
  EXPECT_EQ(table.oracle_rows.at(0).chosen, "exact-zpass+clipped");
  EXPECT_EQ(table.oracle_rows.at(1).chosen, "exact-zpass+zfail");
  EXPECT_DOUBLE_EQ(table.sets.at(0).find("oracle")->end_to_end_ms, 3 + 4);
  EXPECT_DOUBLE_EQ(table.sets.at(0).find("doom3-bfg")->ratio_to_oracle, (2.0 + 10) / 7);
}

// The oracle chooses by the choice rounds' times and counts the others':
// a candidate fast by chance in the rounds it was chosen on keeps its time
// of the other rounds.
TEST(PolicyEvaluation, OracleChoosesOnRoundsItDoesNotCount) {
  std::vector<EvaluationRow> rows = group("c1", 10);
  for (EvaluationRow& r : rows) r.choice_ms = 10;
  find(rows, "c1", "zpplus-corrected").choice_ms = 5;  // lucky rounds
  find(rows, "c1", "zpplus-corrected").end_to_end_ms = 11;
  find(rows, "c1", "zpplus-paper").end_to_end_ms = 6;  // fast in the counted rounds only
  const analysis::EvaluationTable table = analysis::evaluate_rows(rows);
  EXPECT_EQ(table.oracle_rows.at(0).chosen, "zpplus-corrected");
  EXPECT_DOUBLE_EQ(table.sets.at(0).find("oracle")->end_to_end_ms, 11);
  EXPECT_EQ(analysis::evaluation_csv_line(table.oracle_rows.at(0)),
            "seed-7,c1,,0,oracle,0,1,0,0,0.0000,1.0000,11.0000,5.0000,zpplus-corrected,,,,0,0\n");
}

// A (configuration, light) where the policy or a fixed rule did not draw is
// left out of every total, and counted.
TEST(PolicyEvaluation, RefusedRuleLeavesTheGroupOut) {
  std::vector<EvaluationRow> rows = joined(group("c1", 10), group("c2", 20));
  find(rows, "c2", "doom3-bfg").refused = true;
  const analysis::EvaluationTable table = analysis::evaluate_rows(rows);
  const analysis::SetTable& t = table.sets.at(0);
  EXPECT_EQ(t.groups, 1u);
  EXPECT_EQ(t.excluded, 1u);
  EXPECT_DOUBLE_EQ(t.find("policy")->end_to_end_ms, 10);
  EXPECT_EQ(table.oracle_rows.size(), 1u);
}

// The noise floor, the decision's share, sets apart, and the near-plane
// sweep's window against min(Z-fail, Z-pass where right).
TEST(PolicyEvaluation, NoiseFloorDecisionShareAndWindow) {
  std::vector<EvaluationRow> rows;
  for (int f = 38; f < 62; ++f) {
    const std::string c = "path:near_plane_sweep:" + std::to_string(f);
    std::vector<EvaluationRow> g = group(c, 10, 0, 0, "near_plane_sweep", f);
    find(g, c, "zfail").end_to_end_ms = 8;
    find(g, c, "zpass").end_to_end_ms = f % 2 == 0 ? 5 : 4;
    find(g, c, "zpass").wrong = f % 2 == 0 ? 0 : 7;  // odd frames: Z-pass wrong, Z-fail's 8 ms counts
    find(g, c, "policy").decision_ms = 0.1;
    g.push_back(row(c, std::string(analysis::kNoiseRule), f % 4 == 0 ? 8.8 : 8, 0, 0, "near_plane_sweep", f));
    rows = joined(rows, g);
  }
  rows = joined(rows, group("sample:1:0", 3));
  const analysis::EvaluationTable table = analysis::evaluate_rows(rows);
  ASSERT_EQ(table.sets.size(), 2u);
  const analysis::SetTable& t = table.sets[0];
  EXPECT_EQ(t.set, "near_plane_sweep");
  EXPECT_EQ(t.noise_pairs, 24u);
  EXPECT_DOUBLE_EQ(t.noise_p05, 1.0);
  EXPECT_NEAR(t.noise_p95, 1.1, 1e-12);
  EXPECT_NEAR(t.decision_share, 0.1 / 10, 1e-12);
  ASSERT_TRUE(t.window.has_value());
  EXPECT_EQ(t.window->groups, 20u);
  EXPECT_DOUBLE_EQ(t.window->policy_ms, 20 * 10);
  EXPECT_DOUBLE_EQ(t.window->best_ms, 10 * 5 + 10 * 8);
  EXPECT_EQ(table.sets[1].set, "seed-7");
  EXPECT_FALSE(table.sets[1].window.has_value());
  EXPECT_EQ(table.sets[1].noise_pairs, 0u);
  const std::string md = analysis::evaluation_table_markdown(table);
  EXPECT_NE(md.find("### near_plane_sweep"), std::string::npos);
  EXPECT_NE(md.find("frames 40-59: policy 200.00 ms against min(Z-fail, Z-pass where right) 130.00 ms"),
            std::string::npos)
      << md;
}

// The decision's share both ways: the first call as timed (cold) and the
// same decision repeated at once (warm), whose frame holds the warm call in
// place of the first.
TEST(PolicyEvaluation, DecisionShareColdAndWarm) {
  std::vector<EvaluationRow> rows;
  for (int k = 0; k < 2; ++k) {
    const std::string c = "sample:7:" + std::to_string(k);
    std::vector<EvaluationRow> g = group(c, 10);
    find(g, c, "policy").decision_ms = 0.5;
    rows = joined(rows, g);
  }
  analysis::EvaluationTable table = analysis::evaluate_rows(rows);
  EXPECT_NEAR(table.sets.at(0).decision_share, 1.0 / 20, 1e-12);
  EXPECT_FALSE(table.sets.at(0).decision_warm_share.has_value()) << "no warm call timed, no warm share";
  EXPECT_EQ(analysis::evaluation_table_markdown(table).find("warm ("), std::string::npos);
  find(rows, "sample:7:0", "policy").decision_warm_ms = 0.1;
  find(rows, "sample:7:1", "policy").decision_warm_ms = 0.3;
  table = analysis::evaluate_rows(rows);
  EXPECT_NEAR(table.sets.at(0).decision_share, 1.0 / 20, 1e-12) << "the measured share is kept as it is";
  ASSERT_TRUE(table.sets.at(0).decision_warm_share.has_value());
  // (0.1 + 0.3) / ((10 - 0.5 + 0.1) + (10 - 0.5 + 0.3))
  EXPECT_NEAR(*table.sets.at(0).decision_warm_share, 0.4 / 19.4, 1e-12);
  const std::string md = analysis::evaluation_table_markdown(table);
  EXPECT_NE(md.find("the policy's decision: 5.00% of its end-to-end time"), std::string::npos) << md;
  EXPECT_NE(md.find("; 2.06% warm (the same decision repeated at once"), std::string::npos) << md;
  EXPECT_NE(md.find("- noise floor: no pair timed"), std::string::npos) << md;
}

// The policy's predicted frame time is judged by its median relative error,
// beside the noise floor's median deviation from 1.
TEST(PolicyEvaluation, PredictedFrameTimeErrorBesideTheNoiseFloor) {
  std::vector<EvaluationRow> rows;
  const double predicted[] = {9, 10, 12, 15, 10};  // errors 10%, 0%, 20%, 50%, 0% of the measured 10 ms
  for (int k = 0; k < 5; ++k) {
    const std::string c = "sample:7:" + std::to_string(k);
    std::vector<EvaluationRow> g = group(c, 10);
    find(g, c, "policy").predicted_ms = predicted[k];
    find(g, c, "policy").profile_ms = 2 * predicted[k];
    find(g, c, "zfail").end_to_end_ms = 10;
    g.push_back(row(c, std::string(analysis::kNoiseRule), k < 3 ? 11 : 9.5));  // |x - 1|: .1 .1 .1 .05 .05
    rows = joined(rows, g);
  }
  const analysis::EvaluationTable table = analysis::evaluate_rows(rows);
  ASSERT_EQ(table.sets.size(), 1u);
  EXPECT_NEAR(table.sets[0].predicted_median_error, 0.10, 1e-12);
  EXPECT_NEAR(table.sets[0].predicted_median_ratio, 1.0, 1e-12);  // ratios .9 1 1.2 1.5 1
  EXPECT_NEAR(table.sets[0].noise_median_deviation, 0.10, 1e-12);
  const std::string md = analysis::evaluation_table_markdown(table);
  EXPECT_NEAR(table.sets[0].profile_median_error, 1.0, 1e-12);  // 2 x predicted: errors .8 1 1.4 2 1
  EXPECT_NEAR(table.sets[0].profile_median_ratio, 2.0, 1e-12);
  EXPECT_NE(md.find("plus the decision's own time): median error 10.0% of the measured end-to-end time; "
                    "predicted/measured median 1.000; the profile's price alone: median error 100.0%, "
                    "priced/measured median 2.000"),
            std::string::npos)
      << md;
  // A profile twice too dear: the ratio says so (1.8 2 2.4 3 2).
  for (EvaluationRow& r : rows)
    if (r.predicted_ms) *r.predicted_ms *= 2;
  EXPECT_NEAR(analysis::evaluate_rows(rows).sets[0].predicted_median_ratio, 2.0, 1e-12);
  // Without a profile there is no prediction to judge.
  for (EvaluationRow& r : rows) r.predicted_ms.reset(), r.profile_ms.reset();
  EXPECT_TRUE(std::isnan(analysis::evaluate_rows(rows).sets[0].predicted_median_error));
  EXPECT_TRUE(std::isnan(analysis::evaluate_rows(rows).sets[0].profile_median_error));
}

TEST(PolicyEvaluation, CsvLineQuotesAndLeavesASamplesFrameEmpty) {
  EvaluationRow r = row("sample:7:3", "doom3", 1.5, 2, 1);
  EXPECT_EQ(analysis::evaluation_csv_line(r), "seed-7,sample:7:3,,0,doom3,0,1,2,1,0.0000,0.1500,1.5000,,,,,,0,0\n");
  EvaluationRow p = row("sample:7:3", "policy", 1.5);
  p.decision_ms = 0.25;
  p.decision_warm_ms = 0.0625;
  p.predicted_ms = 1.25;
  p.profile_ms = 1.125;
  p.frames_since_priced = 2;
  EXPECT_EQ(analysis::evaluation_csv_line(p),
            "seed-7,sample:7:3,,0,policy,0,1,0,0,0.2500,0.1500,1.5000,,,0.0625,1.2500,1.1250,0,2\n");
  r.set = "a,b";
  r.frame = 4;
  EXPECT_EQ(analysis::evaluation_csv_line(r).substr(0, 22), "\"a,b\",sample:7:3,4,0,d");
}

// A path none of whose frames loads (every keyframe's up along the view):
// nothing is measured, and evaluate and calibrate say so in one line
// naming the first configuration and why, writing nothing.
TEST(EvaluateCommand, NothingMeasuredIsAnError) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("nearcap_evaluate_none_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  nlohmann::json path = nlohmann::json::parse(test::slurp(std::string(NEARCAP_SOURCE_DIR) + "/data/paths/zoom.json"));
  path["scene"] = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + path["scene"].get<std::string>().substr(10);
  path["frames"] = 2;
  for (nlohmann::json& k : path["keyframes"]) k["up"] = {0, 0, 0};
  const std::filesystem::path file = dir / "unloadable.json";
  std::ofstream(file) << path.dump();
  for (const std::string& command :
       {"evaluate --path '" + file.string() + "' --repeats 1 --out '" + (dir / "evaluated").string() + "'",
        "calibrate --samples 0 --path '" + file.string() + "' --out '" + (dir / "c.csv").string() + "'"}) {
    SCOPED_TRACE(command);
    const test::CliResult r = test::run_cli(command, "evaluate_none");
    if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
      GTEST_SKIP() << "no headless OpenGL here: " << r.err;
    EXPECT_EQ(r.exit_code, 2) << r.err;
    const std::string last = r.err.substr(r.err.rfind("nearcap: error ("));
    EXPECT_NE(last.find("nothing measured: none of the 2 configurations loads (the first, path:unloadable:0: "),
              std::string::npos)
        << r.err;
    EXPECT_EQ(last.find("path:unloadable:0"), last.rfind("path:unloadable:0")) << "the id twice: " << r.err;
    EXPECT_EQ(std::count(last.begin(), last.end(), '\n'), 1) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "evaluated"));
  EXPECT_FALSE(std::filesystem::exists(dir / "c.csv"));
  std::filesystem::remove_all(dir);
}

// nearcap evaluate on two sampled configurations at 32 x 24: a row per
// (configuration, light, rule), the oracle's, and the table.
TEST(EvaluateCommand, TwoSamplesEndToEnd) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("nearcap_evaluate_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const test::CliResult r =
      test::run_cli("evaluate --samples 2 --seed 4242 --width 32 --height 24 --out '" + dir.string() + "'", "evaluate");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = test::slurp(dir / "evaluation.csv");
  const std::string md = test::slurp(dir / "table.md");
  EXPECT_EQ(csv.substr(0, csv.find('\n') + 1), analysis::evaluation_csv_header());
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);
  std::size_t oracle = 0, policy = 0, again = 0, atomiczp = 0;
  while (std::getline(lines, line)) {
    EXPECT_EQ(line.rfind("seed-4242,sample:4242:", 0), 0u) << line;
    // The rule is the fifth column (the oracle's `chosen` may name a rule too).
    std::istringstream fields(line);
    std::string rule;
    for (int column = 0; column < 5; ++column) std::getline(fields, rule, ',');
    oracle += rule == "oracle" ? 1 : 0;
    policy += rule == "policy" ? 1 : 0;
    again += rule == "zfail#again" ? 1 : 0;
    atomiczp += rule == "atomiczp" ? 1 : 0;
  }
  EXPECT_GE(policy, 2u) << csv;  // two configurations, a light each at least
  EXPECT_EQ(oracle, policy) << csv;
  EXPECT_EQ(again, policy) << csv;
  EXPECT_EQ(atomiczp, policy) << csv << ": AtomicZP is among the oracle's candidates";
  EXPECT_NE(md.find("| atomiczp | "), std::string::npos) << md;
  EXPECT_NE(md.find("### seed-4242"), std::string::npos) << md;
  EXPECT_NE(md.find("| oracle | "), std::string::npos) << md;
  EXPECT_NE(md.find("| doom3-bfg | "), std::string::npos) << md;
  EXPECT_NE(md.find("% warm (the same decision repeated at once"), std::string::npos) << md;
  EXPECT_NE(r.out.find("| policy | "), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("evaluate: 2/2 configurations"), std::string::npos) << r.err;
  // Z-pass applies exactly where the exact test finds every near-cap empty:
  // there it is as right as Z-fail.  Configuration 0 of seed 4242 has a
  // near-cap (Z-pass is wrong there).
  std::map<std::string, std::vector<std::string>> zpass, zfail;  // configuration and light -> fields
  analysis::FrameTimeDrift drift;                                // the policy's frames so far, in the rows' order
  constexpr double kHalfUnit = 5e-5;                             // ms: the CSV's rounding, either way
  double log_ratio_error = 0;  // the largest rounding error of an observed ratio's logarithm
  std::istringstream rows_of(csv);
  std::getline(rows_of, line);
  while (std::getline(rows_of, line)) {
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
    ASSERT_EQ(fields.size(), 19u) << line;
    // The configuration's largest occluder: a box (12) or a sampled mesh.
    EXPECT_GE(std::stoul(fields[17]), 12u) << line;
    // No choice kept between two sampled configurations (other objects).
    EXPECT_EQ(fields[18], "0") << line;
    if (fields[4] == "policy") {
      EXPECT_FALSE(fields[14].empty()) << "the policy's warm decision time: " << line;
      const double decision = std::stod(fields[9]), measured = std::stod(fields[11]);
      const double predicted = std::stod(fields[15]), priced = std::stod(fields[16]);
      EXPECT_GT(priced, 0) << "the shipped profile's price: " << line;
      // The prediction: the price times the last frames' measured / priced
      // (1 before any), plus the decision's own time.  The CSV rounds each
      // time to 0.1 us (half a unit, 5e-5 ms, either way), and a scale is the
      // median of logarithms, so its error is at most the largest of its
      // ratios' (first order, doubled for what that leaves out).
      const double expected = priced * drift.scale() + decision;
      const double scale_error = std::expm1(kHalfUnit / priced + log_ratio_error) + 1e-9;
      EXPECT_NEAR(predicted, expected, priced * drift.scale() * scale_error + 2 * kHalfUnit) << line;
      drift.observe(priced, measured - decision);
      if (measured > decision)  // else not observed
        log_ratio_error = std::max(log_ratio_error, 2 * (kHalfUnit / priced + 2 * kHalfUnit / (measured - decision)));
    }
    if (fields[4] == "zpass") zpass[fields[1] + "/" + fields[3]] = fields;
    if (fields[4] == "zfail") zfail[fields[1] + "/" + fields[3]] = fields;
  }
  std::size_t applies = 0, not_applies = 0;
  for (const auto& [key, z] : zpass) {
    const std::vector<std::string>& f = zfail.at(key);
    if (z[6] == "1") {
      ++applies;
      EXPECT_LE(std::stoul(z[7]), std::stoul(f[7])) << key << ": Z-pass applies but has more wrong pixels";
    } else {
      ++not_applies;
    }
  }
  EXPECT_GE(not_applies, 1u) << csv;
  EXPECT_EQ(zpass.at("sample:4242:0/0")[6], "0") << csv;
  EXPECT_NE(zpass.at("sample:4242:0/0")[7], "0") << csv;
  std::filesystem::remove_all(dir);
}

// Along a path: the set is the path's name, the near_plane_sweep window's
// line, and the plot of the policy against the oracle.  The policy's first
// frame is priced and a later one may keep its choice for at most
// KeptChoices::kMaxKeptFrames frames, which the table counts; with
// --price-every-frame none is kept, and the heading says so.
TEST(EvaluateCommand, PathFramesMakeTheWindowLineAndThePlot) {
  for (const bool price_every_frame : {false, true}) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("nearcap_evaluate_path_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    const test::CliResult r = test::run_cli(
        "evaluate --path data/paths/near_plane_sweep.json --first-frame 40 --last-frame 43 --width 32 "
        "--height 24 --repeats 2 --out '" +
            dir.string() + "'" + (price_every_frame ? " --price-every-frame" : ""),
        "evaluate");
    if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
      GTEST_SKIP() << "no headless OpenGL here: " << r.err;
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("### near_plane_sweep"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("- frames 40-59: policy "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("(4 frame-lights)"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find(" with every frame priced (--price-every-frame).") != std::string::npos, price_every_frame)
        << r.out;
    const std::string csv = test::slurp(dir / "evaluation.csv");
    EXPECT_NE(csv.find("near_plane_sweep,path:near_plane_sweep:41,41,0,oracle,"), std::string::npos) << csv;
    EXPECT_EQ(csv.find(":44,"), std::string::npos) << csv;
    EXPECT_GT(std::filesystem::file_size(dir / "oracle-near_plane_sweep.png"), 1000u);
    std::istringstream lines(csv);
    std::string line;
    std::getline(lines, line);
    std::size_t policy_rows = 0, kept = 0;
    while (std::getline(lines, line)) {
      std::vector<std::string> f;
      std::istringstream cells(line);
      for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell);
      ASSERT_EQ(f.size(), 19u) << line;
      if (f[4] != "policy") {
        EXPECT_EQ(f[18], "0") << line;
        continue;
      }
      ++policy_rows;
      const int since = std::stoi(f[18]);
      EXPECT_GE(since, 0) << line;
      EXPECT_LE(since, price_every_frame || f[2] == "40" ? 0 : analysis::KeptChoices::kMaxKeptFrames) << line;
      kept += since > 0 ? 1 : 0;
    }
    EXPECT_EQ(policy_rows, 4u);
    if (!price_every_frame) {
      EXPECT_GT(kept, 0u) << csv;
    }
    EXPECT_EQ(r.out.find("in " + std::to_string(kept) + " of the 4 its choice was kept") != std::string::npos, kept > 0)
        << r.out;
    std::filesystem::remove_all(dir);
  }
}

// --fit-unpriced: the fit's line, the table's heading saying every frame
// was priced, the priced total the policy's rows' sum, and the policy written
// with the fitted frames and their provenance.
TEST(EvaluateCommand, FitUnpricedWritesThePolicyWithTheFittedFrames) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("nearcap_evaluate_fit_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const std::filesystem::path fitted = dir / "fitted.json";
  const test::CliResult r = test::run_cli("evaluate --samples 3 --seed 100 --width 32 --height 24 --repeats 2 --out '" +
                                              dir.string() + "' --fit-unpriced '" + fitted.string() + "'",
                                          "evaluate_fit");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("evaluate: unpriced frames: "), std::string::npos) << r.out;
  EXPECT_NE(test::slurp(dir / "table.md").find(" with every frame priced (--fit-unpriced)."), std::string::npos);
  const nlohmann::json p = nlohmann::json::parse(test::slurp(fitted));
  const nlohmann::json& fit = p.at("provenance").at("unpriced_frames");
  EXPECT_EQ(fit.at("seed"), 100);
  EXPECT_EQ(fit.at("samples"), 3);
  const std::size_t frames = fit.at("frames");
  EXPECT_GE(frames, 3u);
  // The priced total is the policy's rows' end-to-end times: every frame
  // priced, the shipped policy's unpriced frames dropped.
  double policy_total = 0;
  std::size_t policy_rows = 0;
  std::istringstream lines(test::slurp(dir / "evaluation.csv"));
  std::string line;
  std::getline(lines, line);
  while (std::getline(lines, line)) {
    std::vector<std::string> f;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell);
    if (f.size() < 12 || f[4] != "policy") continue;
    policy_total += std::stod(f[11]);
    ++policy_rows;
  }
  EXPECT_EQ(policy_rows, frames);
  // Each row's time rounded to 0.1 us (5e-5 ms either way) in the CSV.
  EXPECT_NEAR(fit.at("priced_total_ms").get<double>(), policy_total, 5e-5 * static_cast<double>(policy_rows) + 1e-9);
  EXPECT_LE(fit.at("fitted_total_ms").get<double>(), fit.at("priced_total_ms").get<double>());
  const analysis::SwitchPolicy written = analysis::load_policy(fitted.string());
  EXPECT_EQ(!written.unpriced_frames.empty(), fit.at("unpriced_frames").get<std::size_t>() > 0);
  std::filesystem::remove_all(dir);
}

// Bad input: one line, the kind, exit 2, no output directory made.
TEST(EvaluateCommand, BadOptionsAreOneLineErrors) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("nearcap_evaluate_bad_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const std::string out = " --out '" + dir.string() + "'";
  const struct {
    std::string args, kind, says;
  } cases[] = {
      {"evaluate --samples 2", "usage", "--out DIR"},
      {"evaluate" + out, "usage", "needs held-out data"},
      {"evaluate --samples -1" + out, "usage", "--samples"},
      {"evaluate --samples 2 --width 0" + out, "usage", "--width"},
      {"evaluate --path data/paths/fly_around.json --first-frame 5 --last-frame 4" + out, "usage",
       "--last-frame 4 is before --first-frame 5"},
      {"evaluate --path data/paths/fly_around.json --first-frame 900" + out, "usage", "has 90 frames"},
      {"evaluate --path data/paths/fly_around.json --last-frame 90" + out, "usage", "has 90 frames (the last is 89)"},
      {"evaluate --path data/paths/missing.json" + out, "io", "missing.json"},
      {"evaluate --samples 2 --policy data/missing-policy.json" + out, "io", "missing-policy.json"},
      {"evaluate --samples 2 --policy data/scenes/case_d.json" + out, "schema", "case_d.json"},
      {"evaluate --samples 2 --kinds nope" + out, "usage", "nope"},
      {"evaluate --samples 2 --fit-unpriced data/policy.json" + out, "usage",
       "--fit-unpriced would replace the policy it evaluates"},
      {"evaluate --samples 2 --policy data/policy-tight-near.json --fit-unpriced p.json" + out, "usage",
       "has no device profile"},
      {"evaluate --samples 2 --fit-unpriced data" + out, "io", "'data' is a directory"},
      {"evaluate --samples 2 --fit-unpriced '" + (dir / "table.md").string() + "'" + out, "usage",
       "is the table.md --out writes"},
      {"evaluate --samples 2 --fit-unpriced '" + dir.string() + "'" + out, "usage", "is the directory --out writes"},
      {"evaluate --samples 2 --fit-unpriced '" + dir.string() + "/'" + out, "usage", "is the directory --out writes"},
      {"evaluate --samples 2 --fit-unpriced '" + dir.string() + "' --out '" + dir.string() + "/'", "usage",
       "is the directory --out writes"},
  };
  for (const auto& c : cases) {
    const test::CliResult r = test::run_cli(c.args, "evaluate_bad");
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("nearcap: error (" + c.kind + "): ", 0), 0u) << c.args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir)) << c.args;
  }
}

// The shipped policy is as right as Z-fail where the float Z-pass is wrong
// although the occluder's exact near-cap is empty (a box 10^6 from the
// origin): an exact-Z-pass candidate would draw Z-pass there.
TEST(ShippedPolicyRightness, AsRightAsZFailWhereFloatZPassIsWrongOnAnExactlyEmptyNearCap) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("nearcap_shipped_policy_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string scene = (dir / "c.json").string();
  ASSERT_EQ(test::run_cli("sample --seed 7 --index 638 --kinds all --width 48 --height 36 --out '" + scene + "'",
                          "shipped_policy")
                .exit_code,
            0);
  const test::CliResult r =
      test::run_cli("cracks '" + scene + "' --light 0 --method zpass,zfail,policy", "shipped_policy");
  std::filesystem::remove_all(dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::map<std::string, nlohmann::json> by_method;
  const nlohmann::json records = nlohmann::json::parse(r.out);
  for (const nlohmann::json& m : records["methods"]) by_method[m["method"].get<std::string>()] = m;
  ASSERT_EQ(by_method.count("zpass") + by_method.count("zfail") + by_method.count("policy"), 3u) << r.out;
  EXPECT_GT(by_method["zpass"]["wrong"].get<long>(), by_method["zfail"]["wrong"].get<long>());
  EXPECT_LE(by_method["policy"]["wrong"].get<long>(), by_method["zfail"]["wrong"].get<long>());
  EXPECT_LE(by_method["policy"]["cracks"].get<long>(), by_method["zfail"]["cracks"].get<long>());
}

}  // namespace
}  // namespace nearcap
