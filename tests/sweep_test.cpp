// `nearcap sweep` and `nearcap sample` end to end: the rows a sweep writes,
// a resumed sweep equal to an uninterrupted one, replaying a row alone, and
// the errors of a bad invocation.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <map>
#include <set>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_support.hpp"
#include "nearcap/analysis/sweep.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> split(const std::string& line) {  // no quoted commas in the columns compared
  std::vector<std::string> out;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) out.push_back(cell);
  return out;
}

// A sweep CSV's text read as its header, then row by row.
class SweepCsv {
 public:
  explicit SweepCsv(const std::string& text) : in_(text) {
    std::string line;
    std::getline(in_, line);
    header_ = split(line);
  }
  const std::vector<std::string>& header() const { return header_; }
  // The index of column `name`; a column the header lacks fails the test
  // (and gives header().size()).
  std::size_t column(const std::string& name) const {
    const auto k = static_cast<std::size_t>(std::find(header_.begin(), header_.end(), name) - header_.begin());
    EXPECT_LT(k, header_.size()) << "no column " << name;
    return k;
  }
  // The next row: its line and cells; false after the last.
  bool next(std::string& line, std::vector<std::string>& cells) {
    if (!std::getline(in_, line)) return false;
    cells = split(line);
    return true;
  }

 private:
  std::stringstream in_;
  std::vector<std::string> header_;
};

// The rows without their timing columns (*_ms), which differ run to run.
std::vector<std::string> untimed_rows(const std::string& csv) {
  SweepCsv in(csv);
  const std::vector<std::string>& header = in.header();
  std::vector<std::string> rows;
  std::string line;
  std::vector<std::string> cells;
  while (in.next(line, cells)) {
    std::string kept;
    for (std::size_t k = 0; k < cells.size() && k < header.size(); ++k)
      if (header[k].size() < 3 || header[k].compare(header[k].size() - 3, 3, "_ms") != 0) kept += cells[k] + ",";
    rows.push_back(kept);
  }
  return rows;
}

class Sweep : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nearcap_sweep_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // A small sweep: the 60 frames of a path and 8 samples, 16 x 12 pixels.
  std::string args(const std::string& out) const {
    return "sweep --path data/paths/near_plane_sweep.json --samples 8 --seed 3 --width 16 --height 12 --out " + out;
  }
  fs::path dir_;
};

TEST_F(Sweep, WritesOneRowPerConfigurationLightAndMethod) {
  const test::CliResult r = test::run_cli(args(path("a.csv")), "sweep");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = test::slurp(path("a.csv"));
  EXPECT_EQ(csv.rfind(analysis::csv_header(), 0), 0u);
  SweepCsv in(csv);
  std::string line;
  std::vector<std::string> cells;
  std::map<std::string, int> rows_per_configuration;
  int rejected = 0;
  while (in.next(line, cells)) {
    ++rows_per_configuration[cells[0]];
    rejected += cells[5] == "rejected";
  }
  EXPECT_EQ(rows_per_configuration.size(), 60u + 8u);
  for (const auto& [id, n] : rows_per_configuration)
    EXPECT_TRUE(n == 1 || n % 6 == 0) << id << ": " << n << " rows (6 methods per light, or one 'rejected')";
  EXPECT_EQ(rows_per_configuration["path:near_plane_sweep:31"], 6);
  EXPECT_LT(rejected, 8);
  EXPECT_NE(r.out.find("68 configurations"), std::string::npos) << r.out;
}

// Engine rules add a row each; the per-occluder columns agree with the
// methods' rows of the same configuration, and are empty for the methods
// that draw no occluder with Z-pass or Z-fail (ZP+, AtomicZP).
TEST_F(Sweep, PoliciesAddRowsWithTheirOccluderDecisions) {
  const test::CliResult r = test::run_cli(
      args(path("p.csv")) + " --methods zpass,zfail,zpplus,atomiczp --policies doom3,ogre", "sweep_policies");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  SweepCsv in(test::slurp(path("p.csv")));
  const std::size_t method = in.column("method"), occluders = in.column("occluders"),
                    truth = in.column("zpass_wrong_occluders"), fn = in.column("false_negatives"),
                    fp = in.column("false_positives");
  ASSERT_FALSE(HasFailure());
  std::map<std::string, std::map<std::string, std::vector<std::string>>> rows;  // configuration, method
  std::size_t wrong_somewhere = 0;
  std::string line;
  std::vector<std::string> cells;
  while (in.next(line, cells)) {
    if (cells[method] == "rejected") continue;
    rows[cells[0] + "/" + cells[4]][cells[method]] = cells;
  }
  for (const auto& [key, by_method] : rows) {
    ASSERT_EQ(by_method.size(), 6u) << key;
    for (const char* m : {"zpplus", "atomiczp"}) {
      EXPECT_EQ(by_method.at(m)[fn], "") << key << " " << m;
      EXPECT_EQ(by_method.at(m)[fp], "") << key << " " << m;
    }
    const auto& zpass = by_method.at("zpass");
    const auto& zfail = by_method.at("zfail");
    EXPECT_EQ(zpass[fn], zpass[truth]) << key;  // Z-pass misses every occluder that needs Z-fail
    EXPECT_EQ(zpass[fp], "0") << key;
    EXPECT_EQ(zfail[fn], "0") << key;
    EXPECT_EQ(std::stoi(zfail[fp]), std::stoi(zfail[occluders]) - std::stoi(zfail[truth])) << key;
    for (const char* p : {"doom3", "ogre"}) {
      const auto& row = by_method.at(p);
      EXPECT_EQ(row[truth], zpass[truth]) << key << " " << p;
      EXPECT_LE(std::stoi(row[fn]), std::stoi(row[truth])) << key << " " << p;
    }
    wrong_somewhere += zpass[truth] != "0";
  }
  EXPECT_GT(wrong_somewhere, 10u);
}

TEST_F(Sweep, AResumedSweepEqualsAnUninterruptedOne) {
  ASSERT_EQ(test::run_cli(args(path("whole.csv")), "sweep_whole").exit_code, 0);
  const std::string whole = test::slurp(path("whole.csv"));
  // Interrupted mid-row, 60 % of the way through: --repair runs the cut-off configuration again.
  std::string cut = whole.substr(0, whole.size() * 3 / 5);
  ASSERT_NE(cut.back(), '\n');
  std::ofstream(path("resumed.csv"), std::ios::binary) << cut;
  fs::copy_file(path("whole.csv.meta.json"), path("resumed.csv.meta.json"));
  const test::CliResult r = test::run_cli(args(path("resumed.csv")) + " --resume --repair", "sweep_resume");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(untimed_rows(test::slurp(path("resumed.csv"))), untimed_rows(whole));
  // Resuming a finished sweep runs nothing and changes nothing.
  const std::string finished = test::slurp(path("resumed.csv"));
  const test::CliResult again = test::run_cli(args(path("resumed.csv")) + " --resume", "sweep_resume2");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(test::slurp(path("resumed.csv")), finished);
  EXPECT_EQ(again.out.rfind("sweep: nothing to run: all ", 0), 0u) << again.out;
}

TEST_F(Sweep, CrackDistanceBucketsAddUpToTheWrongPixels) {
  ASSERT_EQ(test::run_cli(args(path("b.csv")), "sweep_buckets").exit_code, 0);
  SweepCsv in(test::slurp(path("b.csv")));
  std::size_t rows = 0, with_cracks = 0;
  std::string line;
  std::vector<std::string> cells;
  while (in.next(line, cells)) {
    if (cells[5] == "rejected") continue;
    ++rows;
    long long buckets = 0;
    for (const char* b : {"lt_1_512", "1_512", "1_64", "1_8", "1_2", "2", "8"})
      buckets += std::stoll(cells[in.column(std::string("wrong_r_") + b)]);
    const long long cracks = std::stoll(cells[in.column("cracks")]);
    EXPECT_EQ(buckets, std::stoll(cells[in.column("wrong")])) << line;
    EXPECT_EQ(cracks, std::stoll(cells[in.column("wrong_r_1_2")]) + std::stoll(cells[in.column("wrong_r_2")]) +
                          std::stoll(cells[in.column("wrong_r_8")]))
        << line;
    with_cracks += cracks > 0;
    EXPECT_FALSE(cells[in.column("light_near_distance")].empty()) << line;
  }
  EXPECT_GT(rows, 300u);
  EXPECT_GT(with_cracks, 0u);
}

// The noise floor's data: Z-pass's frame is timed a second time, on its own
// row (frame_again_ms), under every variant; the other methods' rows leave the
// column empty, and so does a sweep without Z-pass.
TEST_F(Sweep, ZPassRowsHoldASecondTimingOfTheirFrame) {
  const auto read = [&](const std::string& file) {
    SweepCsv in(test::slurp(path(file)));
    const std::size_t method = in.column("method"), variant = in.column("variant"), refused = in.column("refused"),
                      first = in.column("frame_ms"), again = in.column("frame_again_ms");
    std::map<std::string, std::size_t> timed_twice;  // method [variant] -> rows with a second timing
    std::size_t rows = 0;
    std::string line;
    std::vector<std::string> cells;
    while (in.next(line, cells)) {
      if (cells[method] == "rejected" || cells[refused] == "1") continue;
      ++rows;
      if (cells[method] != "zpass") {
        EXPECT_EQ(cells[again], "") << line;
        continue;
      }
      EXPECT_GT(std::stod(cells[first]), 0) << line;
      EXPECT_FALSE(cells[again].empty()) << "Z-pass timed once: " << line;
      if (cells[again].empty()) continue;
      EXPECT_GT(std::stod(cells[again]), 0) << line;
      ++timed_twice[cells[method] + " " + cells[variant]];
    }
    EXPECT_GT(rows, 0u) << file;
    return timed_twice;
  };
  const std::string small = "sweep --path data/paths/near_plane_sweep.json --width 16 --height 12 ";
  ASSERT_EQ(test::run_cli(small + "--methods zfail,zpass --variant light-projection=glfrustum --out " + path("t.csv"),
                          "sweep_twice")
                .exit_code,
            0);
  const std::map<std::string, std::size_t> twice = read("t.csv");
  EXPECT_EQ(twice.size(), 2u);
  EXPECT_EQ(twice.at("zpass default"), 60u);
  EXPECT_EQ(twice.at("zpass light-projection=glfrustum"), 60u);
  ASSERT_EQ(test::run_cli(small + "--methods zfail,zpplus --out " + path("none.csv"), "sweep_once").exit_code, 0);
  EXPECT_TRUE(read("none.csv").empty());
}

// --variant runs every method again under other named choices; each row says
// which; the variants' rows differ only where the choice matters.
TEST_F(Sweep, VariantsAddRowsNamedByTheirChoices) {
  const test::CliResult r = test::run_cli(
      "sweep --path data/paths/near_plane_sweep.json --width 16 --height 12 --variant light-projection=glfrustum "
      "--variant zfail-far=clamp-far --out " +
          path("v.csv"),
      "sweep_variants");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  SweepCsv in(test::slurp(path("v.csv")));
  ASSERT_EQ(in.header()[6], "variant");
  std::map<std::string, int> per_variant;
  std::string line;
  std::vector<std::string> cells;
  while (in.next(line, cells)) ++per_variant[cells[6]];
  EXPECT_EQ(per_variant.size(), 3u);
  EXPECT_EQ(per_variant["default"], 60 * 6);
  EXPECT_EQ(per_variant["light-projection=glfrustum"], 60 * 6);
  EXPECT_EQ(per_variant["zfail-far=clamp-far"], 60 * 6);
  for (const char* bad :
       {"--variant bogus=1", "--variant depth=float16", "--variant subpixel-bits=x", "--variant subpixel-bits=3.9",
        "--variant subpixel-bits=1e1", "--variant zfail-far=clamp-far --variant zfail-far=clamp-far"}) {
    const test::CliResult b =
        test::run_cli("sweep --samples 2 " + std::string(bad) + " --out " + path("bad.csv"), "sweep_bad_variant");
    EXPECT_EQ(b.exit_code, 2) << bad;
    EXPECT_NE(b.err.find("--variant"), std::string::npos) << bad << ": " << b.err;
    EXPECT_FALSE(fs::exists(path("bad.csv"))) << bad;
  }
}

// A variant's label names its values exactly: two values that print alike in
// six digits are two variants, and a value next to the default is not it.
TEST_F(Sweep, VariantLabelsNameTheirValuesExactly) {
  const test::CliResult r = test::run_cli(
      "sweep --samples 1 --width 8 --height 6 --methods zpplus --variant l-near-scale=0.1234567 "
      "--variant l-near-scale=0.1234568 --variant l-near-scale=0.9999999 --variant guard-band=1.0000001 "
      "--variant l-near-scale=0.5 --out " +
          path("labels.csv"),
      "sweep_variant_labels");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  SweepCsv in(test::slurp(path("labels.csv")));
  std::set<std::string> labels;
  std::string line;
  std::vector<std::string> cells;
  while (in.next(line, cells)) labels.insert(cells[6]);
  EXPECT_EQ(labels, (std::set<std::string>{"default", "l-near-scale=0.1234567", "l-near-scale=0.1234568",
                                           "l-near-scale=0.9999999", "guard-band=1.0000001", "l-near-scale=0.5"}));
}

// The sweep sharded over two MPI ranks (mpirun, Open MPI) writes exactly the
// rows of one process, in the same order, timings aside.
TEST_F(Sweep, TwoMpiRanksWriteWhatOneProcessWrites) {
#ifndef NEARCAP_MPIEXEC
  GTEST_SKIP() << "nearcap was built without MPI (README, \"Sweeps on a cluster\")";
#else
  ASSERT_EQ(test::run_cli(args(path("one.csv")), "sweep_one").exit_code, 0);
  // Leak detection off in a sanitizer build: Open MPI keeps allocations past
  // MPI_Finalize by design; every other check stays on.
  const std::string launcher = "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 " + std::string(NEARCAP_MPIEXEC) +
                               " --allow-run-as-root --oversubscribe -n 2";
  const test::CliResult r = test::run_cli(args(path("two.csv")), "sweep_mpi", launcher);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto one = untimed_rows(test::slurp(path("one.csv"))), two = untimed_rows(test::slurp(path("two.csv")));
  EXPECT_EQ(one.size(), two.size());
  EXPECT_EQ(one, two);
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "rank 0 alone reports: " << r.out;
  // An error before the ranks part (the file exists) is reported once, exit code 2.
  const test::CliResult again = test::run_cli(args(path("two.csv")), "sweep_mpi_again", launcher);
  EXPECT_NE(again.exit_code, 0);
  const std::string marker = "nearcap: error (usage)";
  EXPECT_NE(again.err.find(marker), std::string::npos) << again.err;
  EXPECT_EQ(again.err.find(marker), again.err.rfind(marker)) << again.err;
#endif
}

TEST_F(Sweep, ARowReplaysAlone) {
  ASSERT_EQ(test::run_cli(args(path("a.csv")), "sweep_replay").exit_code, 0);
  SweepCsv in(test::slurp(path("a.csv")));
  int replayed = 0;
  std::string line;
  std::vector<std::string> cells;
  while (replayed < 3 && in.next(line, cells)) {
    if (cells[5] != "zpplus-corrected" || cells[0].rfind("sample:", 0) != 0) continue;
    // The replay column: "nearcap sample ... --out c.json"; run it with this build's program.
    std::string replay = cells[in.column("replay")];
    replay.replace(0, std::string("nearcap ").size(), "");
    replay.replace(replay.find("c.json"), 6, path("c.json"));
    ASSERT_EQ(test::run_cli(replay, "replay").exit_code, 0) << replay;
    const test::CliResult c = test::run_cli(
        "cracks " + path("c.json") + " --light " + cells[4] + " --method zpplus-corrected", "replay_cracks");
    ASSERT_EQ(c.exit_code, 0) << c.err;
    EXPECT_NE(c.out.find("\"wrong\":" + cells[in.column("wrong")] + ","), std::string::npos)
        << cells[0] << ": the sweep said " << cells[in.column("wrong")] << " wrong; cracks says " << c.out;
    EXPECT_NE(c.out.find("\"cracks\":" + cells[in.column("cracks")] + ","), std::string::npos)
        << cells[0] << ": the sweep said " << cells[in.column("cracks")] << " cracks; cracks says " << c.out;
    ++replayed;
  }
  EXPECT_GT(replayed, 0);
}

TEST_F(Sweep, BadInvocationsAreOneLineErrors) {
  const std::string out = path("b.csv");
  const std::pair<std::string, std::string> cases[] = {
      {"sweep --out " + out, "nothing to sweep"},
      {"sweep --samples 2 --methods zpass,bogus --out " + out, "'bogus'"},
      {"sweep --samples 2 --kinds grazing,nope --out " + out, "--kinds: 'nope' is not a hard-case kind"},
      {"sweep --samples 2 --policies doom3,doom4 --out " + out, "--policies 'doom4'"},
      {"sweep --path data/paths/missing.json --out " + out, "missing.json"},
  };
  for (const auto& [a, fragment] : cases) {
    const test::CliResult r = test::run_cli(a, "sweep_bad");
    EXPECT_EQ(r.exit_code, 2) << a << "\n" << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << a << "\n" << r.err;
    EXPECT_FALSE(fs::exists(out)) << a;
  }
  // An existing file needs --resume; one from other options cannot be resumed.
  ASSERT_EQ(test::run_cli("sweep --samples 2 --width 8 --height 6 --out " + out, "sweep_b").exit_code, 0);
  EXPECT_NE(test::run_cli("sweep --samples 2 --width 8 --height 6 --out " + out, "sweep_b2").err.find("--resume"),
            std::string::npos);
  std::ofstream(out, std::ios::app) << test::slurp(out).substr(analysis::csv_header().size());  // a second group
  const test::CliResult other =
      test::run_cli("sweep --samples 2 --seed 99 --width 8 --height 6 --out " + out + " --resume", "sweep_b3");
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_NE(other.err.find("cannot resume it with these options: --seed: 99 here, 1 in the sweep being resumed"),
            std::string::npos)
      << other.err;
}

}  // namespace
}  // namespace nearcap
