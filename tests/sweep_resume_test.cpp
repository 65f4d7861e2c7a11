// A sweep's CSV as a file that is continued (docs/sweep-files.md): one
// writer at a time, a sidecar that --resume compares the options with, every
// row checked before a resume appends (a damaged one named by its line),
// --repair for a configuration cut off mid-write, and the checks of --out,
// duplicated options and the replay column's quoting.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "nearcap/analysis/sweep.hpp"
#include "nearcap/analysis/sweep_file.hpp"
#include "nearcap/error.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string line;
  while (std::getline(in, line)) out.push_back(line);
  return out;
}

std::string joined(const std::vector<std::string>& lines, std::size_t from, std::size_t to) {
  std::string out;
  for (std::size_t k = from; k < to; ++k) out += lines[k] + "\n";
  return out;
}

// The rows without their timing columns (*_ms); no quoted commas in the rows compared.
std::vector<std::string> untimed_rows(const std::string& csv) {
  const std::vector<std::string> lines = lines_of(csv);
  std::vector<std::string> header, rows;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    std::vector<std::string> cells;
    std::stringstream s(lines[k]);
    std::string cell;
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    if (k == 0) {
      header = cells;
      continue;
    }
    std::string kept;
    for (std::size_t c = 0; c < cells.size() && c < header.size(); ++c)
      if (header[c].size() < 3 || header[c].compare(header[c].size() - 3, 3, "_ms") != 0) kept += cells[c] + ",";
    rows.push_back(kept);
  }
  return rows;
}

std::string first_cell(const std::string& line) { return line.substr(0, line.find(',')); }

void write_file(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

class SweepFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nearcap_sweep_file_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // A tiny sweep: 6 samples at 16 x 12 pixels, two methods.
  static std::string args(const std::string& out, const std::string& more = "") {
    return "sweep --samples 6 --seed 5 --width 16 --height 12 --methods zpass,zfail " + more + " --out '" + out + "'";
  }
  // A whole sweep into `name`, its text returned.
  std::string whole(const std::string& name, const std::string& more = "") {
    const test::CliResult r = test::run_cli(args(path(name), more), "sweep_file_whole");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return test::slurp(path(name));
  }
  // Line indices (0: the header) where each configuration's rows start, and the line count.
  static std::vector<std::size_t> group_starts(const std::vector<std::string>& lines) {
    std::vector<std::size_t> starts;
    for (std::size_t k = 1; k < lines.size(); ++k)
      if (k == 1 || first_cell(lines[k]) != first_cell(lines[k - 1])) starts.push_back(k);
    return starts;
  }
  fs::path dir_;
};

// One line on stderr, "nearcap: error (KIND): ...", exit code 2.
void expect_one_line_error(const test::CliResult& r, const std::string& kind, const std::string& fragment,
                           const std::string& what) {
  EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.err;
  EXPECT_EQ(r.err.rfind("nearcap: error (" + kind + "): ", 0), 0u) << what << "\n" << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << "\n" << r.err;
  EXPECT_NE(r.err.find(fragment), std::string::npos) << what << ": expected '" << fragment << "' in\n" << r.err;
}

// ---- one writer ------------------------------------------------------------

TEST_F(SweepFile, ASecondWriterIsRefusedWhileTheFirstHoldsTheLock) {
  const std::string csv = path("a.csv");
  const std::string full = whole("a.csv");
  const std::vector<std::string> lines = lines_of(full);
  const std::vector<std::size_t> starts = group_starts(lines);
  ASSERT_GE(starts.size(), 3u);
  const std::string text = joined(lines, 0, starts[2]);  // two configurations of six: a resume has work to do
  write_file(csv, text);
  // This process is the first writer.
  const int fd = ::open(csv.c_str(), O_RDWR);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const test::CliResult second = test::run_cli(args(csv, "--resume"), "sweep_file_second");
  expect_one_line_error(second, "io", csv + ": another nearcap sweep is writing it", "a resume beside a writer");
  EXPECT_EQ(test::slurp(csv), text) << "the refused sweep touched the file";
  ::close(fd);  // the lock goes with it
  const test::CliResult after = test::run_cli(args(csv, "--resume"), "sweep_file_after");
  EXPECT_EQ(after.exit_code, 0) << after.err;
  EXPECT_EQ(untimed_rows(test::slurp(csv)), untimed_rows(full));
}

// Polls `ready` every 10 ms while `child` runs, for at most `bound_s`
// seconds: true once it holds.  A child that has ended is reaped (`*ended`
// set, its status in `*status`) and the wait stops there.
template <class Ready>
bool wait_while_running(pid_t child, Ready ready, int bound_s, bool* ended, int* status) {
  for (int k = 0; k < bound_s * 100; ++k) {
    if (ready()) return true;
    if (!*ended && ::waitpid(child, status, WNOHANG) == child) *ended = true;
    if (*ended) return ready();
    ::usleep(10000);
  }
  return ready();
}

// A running sweep holds the lock on its CSV; killed (SIGKILL), it holds it no more.
TEST_F(SweepFile, TheWriterHoldsTheLockUntilItEndsKilledOrNot) {
  const std::string csv = path("running.csv");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    if (::chdir(NEARCAP_SOURCE_DIR) != 0 || null < 0 || ::dup2(null, 1) < 0 || ::dup2(null, 2) < 0) ::_exit(127);
    ::execl(NEARCAP_CLI, NEARCAP_CLI, "sweep", "--samples", "1000000", "--width", "16", "--height", "12", "--methods",
            "zpass", "--out", csv.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // The file appears under its name already locked, and its sidecar after it
  // (create_csv links the CSV first, so that a sweep that loses the race for
  // the name writes no sidecar).  Both are waited for while the sweep runs
  // (it has a million samples to run), with a bound far above a start under
  // AddressSanitizer on a loaded machine; no ASSERT before the child is killed.
  constexpr int kStartBoundS = 300;
  bool ended = false;
  int status = 0;
  int fd = -1;
  const bool appeared = wait_while_running(
      child, [&] { return (fd = ::open(csv.c_str(), O_RDONLY)) >= 0; }, kStartBoundS, &ended, &status);
  EXPECT_TRUE(appeared) << csv << " never appeared"
                        << (ended ? "; the sweep ended with status " + std::to_string(status) : std::string());
  if (fd >= 0) {
    EXPECT_NE(::flock(fd, LOCK_SH | LOCK_NB), 0) << "the running sweep does not hold the lock on " << csv;
    EXPECT_EQ(errno, EWOULDBLOCK);
    ::close(fd);
  }
  const std::string meta = analysis::sweep_meta_path(csv);
  const bool sidecar = wait_while_running(
      child, [&] { return fs::exists(meta); }, kStartBoundS, &ended, &status);
  EXPECT_TRUE(sidecar) << meta << " never appeared";
  EXPECT_FALSE(ended) << "the sweep of a million samples ended, status " << status;
  const test::CliResult fresh = test::run_cli(args(csv), "sweep_file_fresh_beside");
  EXPECT_EQ(fresh.exit_code, 2) << fresh.err;
  // (timeout: where a resume would not be refused, it would run for hours)
  const test::CliResult resume =
      test::run_cli("sweep --samples 1000000 --width 16 --height 12 --methods zpass --resume --out " + csv,
                    "sweep_file_beside", test::kHangBound);
  expect_one_line_error(resume, "io", "another nearcap sweep is writing it", "a resume beside a running sweep");
  if (!ended) {
    ::kill(child, SIGKILL);
    ASSERT_EQ(::waitpid(child, &status, 0), child);
  }
  fd = ::open(csv.c_str(), O_RDONLY);
  ASSERT_GE(fd, 0);
  EXPECT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0) << "the lock outlived the killed sweep";
  ::close(fd);
}

// ---- the sidecar -----------------------------------------------------------

TEST_F(SweepFile, ResumeRefusesOtherOptionsNamingTheFirstThatDiffers) {
  const std::string policy = path("policy.json");
  fs::copy_file(std::string(NEARCAP_SOURCE_DIR) + "/data/policy.json", policy);
  const std::string base = "--policies doom3,policy --policy " + policy;
  const std::string csv = path("a.csv");
  const std::vector<std::string> lines = lines_of(whole("a.csv", base));
  const std::string cut = joined(lines, 0, group_starts(lines)[2]);
  write_file(csv, cut);
  const std::string other_policy = path("other_policy.json");
  write_file(other_policy, test::slurp(policy) + " \n");  // the same policy, other bytes
  // Each case: a word of the command replaced (or, where `from` is empty, one added).
  const std::string command = "sweep --samples 6 --seed 5 --width 16 --height 12 --methods zpass,zfail " + base;
  struct Case {
    std::string from, to, message;
  };
  const Case cases[] = {
      {"--width 16", "--width 20", "--width: 20 here, 16 in the sweep being resumed"},
      {"--seed 5", "--seed 6", "--seed: 6 here, 5 in the sweep being resumed"},
      {"", "--kinds grazing", "--kinds: grazing here, all in the sweep being resumed"},
      {"", "--allow-bunny", "--allow-bunny: yes here, no in the sweep being resumed"},
      {"", "--subpixel-bits 4", "--subpixel-bits: 4 here, 8 in the sweep being resumed"},
      {"", "--depth float32", "--depth: float32 here, fixed24 in the sweep being resumed"},
      {"", "--variant fma=1", "--variant: fma=1 here, (none) in the sweep being resumed"},
      {"--samples 6", "--samples 3", "--samples: 3 here, 6 in the sweep being resumed"},
      {"--methods zpass,zfail", "--methods zpass", "--methods: zpass here, zpass, zfail in the sweep being resumed"},
      {"doom3,policy --policy " + policy, "doom3", "--policies: doom3 here, doom3, policy in the sweep being resumed"},
      {"--policy " + policy, "--policy " + other_policy, "--policy (content digest): "},
  };
  for (const Case& c : cases) {
    std::string changed = command;
    if (c.from.empty())
      changed += " " + c.to;
    else
      changed.replace(changed.find(c.from), c.from.size(), c.to);
    const test::CliResult r = test::run_cli(changed + " --resume --out " + csv, "sweep_file_other");
    expect_one_line_error(r, "usage", csv + ": cannot resume it with these options: " + c.message, changed);
    EXPECT_EQ(test::slurp(csv), cut) << changed;
  }
  // The same options continue it.
  const test::CliResult same = test::run_cli(args(csv, base + " --resume"), "sweep_file_same");
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(untimed_rows(test::slurp(csv)), untimed_rows(joined(lines, 0, lines.size())));
}

// A camera path's rows depend on its base scene and meshes too: a resume
// after either changed is refused, as after the path file itself changed.
TEST_F(SweepFile, ResumeRefusesAPathWhoseSceneOrMeshChanged) {
  for (const char* mesh : {"box.off", "ground.off"})
    fs::copy_file(fs::path(NEARCAP_SOURCE_DIR) / "data/meshes" / mesh, dir_ / mesh);
  const std::string scene = R"({"camera":{"eye":[0,2.5,5],"target":[0,0.7,0],"up":[0,1,0],"fovy_deg":50,
    "near":0.1,"far":100,"width":16,"height":12},"lights":[{"position":[2,5,1.5]}],
    "objects":[{"mesh":"box.off","translate":[0,1,0]},{"mesh":"ground.off","occluder":false}]})";
  write_file(path("base.json"), scene);
  write_file(path("p.json"), R"({"scene":"base.json","frames":4,"keyframes":[{"eye":[0,2.5,5],"target":[0,0.7,0]},
    {"eye":[1,2.5,4],"target":[0,0.7,0]}]})");
  const std::string csv = path("p.csv");
  const std::string command = "sweep --path " + path("p.json") + " --methods zpass --out " + csv;
  ASSERT_EQ(test::run_cli(command, "sweep_file_scene").exit_code, 0);
  const std::vector<std::string> lines = lines_of(test::slurp(csv));
  const std::string cut = joined(lines, 0, group_starts(lines)[2]);
  write_file(csv, cut);
  const std::string box = test::slurp(path("box.off"));
  for (int edit = 0; edit < 2; ++edit) {
    if (edit == 0) {
      std::string moved = scene;
      moved.replace(moved.find("[2,5,1.5]"), 9, "[2,6,1.5]");
      write_file(path("base.json"), moved);
    } else {
      write_file(path("base.json"), scene);
      write_file(path("box.off"), box + "\n");  // the same mesh, other bytes
    }
    const test::CliResult r = test::run_cli(command + " --resume", "sweep_file_scene_resume");
    expect_one_line_error(r, "usage", "--path (scene and meshes digest): ", edit == 0 ? "scene edited" : "mesh edited");
    EXPECT_EQ(test::slurp(csv), cut);
  }
  write_file(path("box.off"), box);
  // The same files in another folder resume it: the digest is of their bytes.
  const fs::path a = dir_ / "a", b = dir_ / "b";
  fs::create_directories(a);
  for (const char* f : {"box.off", "ground.off", "base.json", "p.json"}) fs::copy_file(dir_ / f, a / f);
  const std::string relative = "sweep --path p.json --methods zpass --out p.csv";
  ASSERT_EQ(test::run_cli(relative, "sweep_file_scene_a", "cd '" + a.string() + "' &&").exit_code, 0);
  const std::vector<std::string> a_lines = lines_of(test::slurp(a / "p.csv"));
  write_file((a / "p.csv").string(), joined(a_lines, 0, group_starts(a_lines)[2]));
  fs::copy(a, b, fs::copy_options::recursive);
  const test::CliResult there =
      test::run_cli(relative + " --resume", "sweep_file_scene_b", "cd '" + b.string() + "' &&");
  ASSERT_EQ(there.exit_code, 0) << there.err;
  EXPECT_EQ(untimed_rows(test::slurp(b / "p.csv")), untimed_rows(joined(a_lines, 0, a_lines.size())));
  // The same file named another way is refused, saying how to name it: the
  // rows' replay column holds the path as the sweep was given it.
  const std::string a_cut = test::slurp(a / "p.csv");
  const test::CliResult spelled =
      test::run_cli("sweep --path '" + (a / "p.json").string() + "' --methods zpass --out p.csv --resume",
                    "sweep_file_scene_spelled", "cd '" + a.string() + "' &&");
  expect_one_line_error(spelled, "usage",
                        "--path: " + (a / "p.json").string() +
                            " here, p.json in the sweep being resumed (a path is compared as written, as each row's "
                            "replay column names it: give it as that sweep did, from the folder it ran in)",
                        "the same path file spelled otherwise");
  EXPECT_EQ(test::slurp(a / "p.csv"), a_cut);
  // Another file is not a spelling: no such advice.
  fs::copy_file(a / "p.json", a / "q.json");
  const test::CliResult other_file = test::run_cli("sweep --path q.json --methods zpass --out p.csv --resume",
                                                   "sweep_file_scene_other", "cd '" + a.string() + "' &&");
  expect_one_line_error(other_file, "usage", "--path: q.json here, p.json in the sweep being resumed", "another file");
  EXPECT_EQ(other_file.err.find("compared as written"), std::string::npos) << other_file.err;
  EXPECT_EQ(test::slurp(a / "p.csv"), a_cut);
  // A sidecar without the scene digest (nothing to compare) resumes as before.
  std::string without = test::slurp(path("p.csv.meta.json"));
  const std::size_t key = without.find("\"--path (scene and meshes digest)\"");
  ASSERT_NE(key, std::string::npos) << without;
  without.erase(key, without.find('\n', key) + 1 - key);
  write_file(path("p.csv.meta.json"), without);
  const test::CliResult same = test::run_cli(command + " --resume", "sweep_file_scene_same");
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(untimed_rows(test::slurp(csv)), untimed_rows(joined(lines, 0, lines.size())));
}

// The sampler's meshes come from NEARCAP_DATA_DIR (or the shipped data):
// a resume with other mesh files is refused, since its rows could differ.
TEST_F(SweepFile, ResumeRefusesSamplerMeshesThatChanged) {
  const fs::path meshes = dir_ / "data" / "meshes";
  fs::create_directories(meshes);
  for (const char* mesh : {"box.off", "torus.off", "eight.off", "knot1.off"})
    fs::copy_file(fs::path(NEARCAP_SOURCE_DIR) / "data/meshes" / mesh, meshes / mesh);
  const std::string env = "NEARCAP_DATA_DIR='" + (dir_ / "data").string() + "'";
  const std::string csv = path("m.csv");
  ASSERT_EQ(test::run_cli(args(csv), "sweep_file_meshes", env).exit_code, 0);
  const std::vector<std::string> lines = lines_of(test::slurp(csv));
  const std::string cut = joined(lines, 0, group_starts(lines)[2]);
  write_file(csv, cut);
  const std::string eight = test::slurp(meshes / "eight.off");
  write_file((meshes / "eight.off").string(), eight + "\n");  // the same mesh, other bytes
  expect_one_line_error(test::run_cli(args(csv, "--resume"), "sweep_file_meshes_edited", env), "usage",
                        "--samples (meshes digest): ", "a sampler mesh edited");
  EXPECT_EQ(test::slurp(csv), cut);
  // A mesh gone from the folder: the folder is refused before the sidecar is read.
  write_file((meshes / "eight.off").string(), eight);
  fs::remove(meshes / "knot1.off");
  expect_one_line_error(test::run_cli(args(csv, "--resume"), "sweep_file_meshes_gone", env), "io",
                        "knot1.off (the sampler reads its meshes from $NEARCAP_DATA_DIR/meshes)",
                        "a sampler mesh removed");
  EXPECT_EQ(test::slurp(csv), cut);
  fs::copy_file(fs::path(NEARCAP_SOURCE_DIR) / "data/meshes/knot1.off", meshes / "knot1.off");
  const test::CliResult same = test::run_cli(args(csv, "--resume"), "sweep_file_meshes_same", env);
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(untimed_rows(test::slurp(csv)), untimed_rows(joined(lines, 0, lines.size())));
  // A sweep of paths alone has no row of the sampler's: its meshes may change.
  const std::string paths = path("p.csv");
  const std::string path_sweep = "sweep --path '" + std::string(NEARCAP_SOURCE_DIR) +
                                 "/data/paths/near_plane_sweep.json' --width 8 --height 6 --methods zpass --out " +
                                 paths;
  ASSERT_EQ(test::run_cli(path_sweep, "sweep_file_meshes_paths", env).exit_code, 0);
  const std::vector<std::string> path_lines = lines_of(test::slurp(paths));
  write_file(paths, joined(path_lines, 0, group_starts(path_lines)[2]));
  write_file((meshes / "eight.off").string(), eight + "\n");
  const test::CliResult path_resume = test::run_cli(path_sweep + " --resume", "sweep_file_meshes_paths_resume", env);
  ASSERT_EQ(path_resume.exit_code, 0) << path_resume.err;
  EXPECT_EQ(untimed_rows(test::slurp(paths)), untimed_rows(joined(path_lines, 0, path_lines.size())));
}

// A configuration's rows are one "rejected" row exactly where its scene does
// not load: either put in the other's place is a damaged file.
TEST_F(SweepFile, ARejectedRowStandsOnlyForASceneThatDoesNotLoad) {
  // Configuration 85 of seed 3 puts a light inside an occluder.
  const std::string csv = path("r.csv");
  const std::string command = "sweep --samples 87 --seed 3 --width 8 --height 6 --methods zpass --out " + csv;
  ASSERT_EQ(test::run_cli(command, "sweep_file_rejected").exit_code, 0);
  const std::string full = test::slurp(csv);
  const std::vector<std::string> lines = lines_of(full);
  std::size_t rejected = 0, loaded = 0;
  for (std::size_t k = 1; k < lines.size(); ++k) {
    if (lines[k].find(",rejected,") != std::string::npos) rejected = k;
    if (first_cell(lines[k]) == "sample:3:1") loaded = loaded ? loaded : k;
  }
  ASSERT_NE(rejected, 0u) << "no rejected configuration in this sweep";
  ASSERT_EQ(first_cell(lines[rejected]), "sample:3:85");
  ASSERT_NE(loaded, 0u);
  const test::CliResult whole_again = test::run_cli(command + " --resume", "sweep_file_rejected_whole");
  ASSERT_EQ(whole_again.exit_code, 0) << "the sweep's own rejected row resumes: " << whole_again.err;
  EXPECT_EQ(test::slurp(csv), full);
  // A row's own columns (configuration, source, kind, detail) with another's
  // method and results.
  const auto in_place_of = [](const std::string& row, const std::string& place) {
    std::string out;
    std::stringstream from(place), with(row);
    for (int c = 0; c < 4; ++c) {
      std::string cell;
      std::getline(from, cell, ',');
      out += cell + ",";
      std::getline(with, cell, ',');
    }
    std::string rest;
    std::getline(with, rest);
    return out + rest;
  };
  for (int swap = 0; swap < 2; ++swap) {
    std::vector<std::string> damaged = lines;
    std::size_t at = swap == 0 ? loaded : rejected;
    damaged[at] = in_place_of(swap == 0 ? lines[rejected] : lines[loaded], lines[at]);
    if (swap == 0)  // the loading configuration's other rows dropped
      while (at + 1 < damaged.size() && first_cell(damaged[at + 1]) == "sample:3:1")
        damaged.erase(damaged.begin() + static_cast<std::ptrdiff_t>(at + 1));
    const std::string text = joined(damaged, 0, damaged.size());
    write_file(csv, text);
    expect_one_line_error(test::run_cli(command + " --resume", "sweep_file_rejected_swap"), "schema",
                          swap == 0 ? "'sample:3:1' is 'rejected' where its scene loads"
                                    : "'sample:3:85' has method zpass where its scene can only be rejected",
                          swap == 0 ? "a rejected row for a scene that loads" : "rows for a scene that does not");
    EXPECT_EQ(test::slurp(csv), text);
  }
}

// A sweep stopped after its CSV got its name and before the sidecar was
// written leaves the header alone: --resume starts it, as nothing can mix.
TEST_F(SweepFile, AHeaderAloneWithoutItsSidecarResumes) {
  const std::string full = whole("h.csv");
  const std::vector<std::string> lines = lines_of(full);
  write_file(path("h.csv"), joined(lines, 0, 1));
  fs::remove(path("h.csv.meta.json"));
  const test::CliResult r = test::run_cli(args(path("h.csv"), "--resume"), "sweep_file_header_alone");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(untimed_rows(test::slurp(path("h.csv"))), untimed_rows(full));
  EXPECT_TRUE(fs::exists(path("h.csv.meta.json")));
  // With one row, no sidecar is still refused: what made the row is unknown.
  write_file(path("h.csv"), joined(lines, 0, 2));
  fs::remove(path("h.csv.meta.json"));
  expect_one_line_error(test::run_cli(args(path("h.csv"), "--resume"), "sweep_file_no_sidecar"), "schema",
                        "has no sidecar", "a row without a sidecar");
}

TEST_F(SweepFile, ACsvWithWindowsLineEndsIsNamedAsSuch) {
  const std::string text = whole("w.csv");
  std::string crlf;
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  write_file(path("w.csv"), crlf);
  expect_one_line_error(test::run_cli(args(path("w.csv"), "--resume"), "sweep_file_crlf"), "schema",
                        "line 1 ends in CR LF", "CR LF");
  EXPECT_EQ(test::slurp(path("w.csv")), crlf);
}

// More --samples extend a sweep: its rows are those of the larger sweep run whole.
TEST_F(SweepFile, ALargerSamplesCountExtendsTheSweep) {
  const std::string csv = path("a.csv");
  whole("a.csv");
  const test::CliResult r =
      test::run_cli("sweep --samples 9 --seed 5 --width 16 --height 12 --methods zpass,zfail --resume --out " + csv,
                    "sweep_file_more");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const test::CliResult nine =
      test::run_cli("sweep --samples 9 --seed 5 --width 16 --height 12 --methods zpass,zfail --out " + path("nine.csv"),
                    "sweep_file_nine");
  ASSERT_EQ(nine.exit_code, 0) << nine.err;
  EXPECT_EQ(untimed_rows(test::slurp(csv)), untimed_rows(test::slurp(path("nine.csv"))));
  // The sidecar says 9 now: 6 would shorten the sweep.
  const test::CliResult fewer = test::run_cli(args(csv, "--resume"), "sweep_file_fewer");
  expect_one_line_error(fewer, "usage", "--samples: 6 here, 9 in the sweep being resumed", "fewer samples");
}

TEST_F(SweepFile, ACsvWithoutItsSidecarIsNotResumed) {
  const std::string csv = path("a.csv");
  const std::string text = whole("a.csv");
  fs::remove(analysis::sweep_meta_path(csv));
  const test::CliResult r = test::run_cli(args(csv, "--resume"), "sweep_file_nometa");
  expect_one_line_error(r, "schema", csv + ": has no sidecar " + csv + ".meta.json", "no sidecar");
  EXPECT_EQ(test::slurp(csv), text);
}

// ---- damaged rows ----------------------------------------------------------

TEST_F(SweepFile, ADamagedRowAnywhereIsAnErrorNamingItsLine) {
  const std::string csv = path("a.csv");
  const std::vector<std::string> lines = lines_of(whole("a.csv"));
  const std::vector<std::size_t> starts = group_starts(lines);
  ASSERT_GE(starts.size(), 4u);
  // A configuration with more than one row, not the first nor the last.
  std::size_t g = 1;
  while (g + 1 < starts.size() && starts[g + 1] - starts[g] < 2) ++g;
  ASSERT_LT(g + 1, starts.size()) << "no configuration with two rows or more";
  const std::size_t a = starts[g], b = starts[g + 1];  // its rows: lines a .. b-1 (line number = index + 1)
  std::vector<std::string> short_row = lines;
  short_row[a] = short_row[a].substr(0, short_row[a].rfind(',', short_row[a].rfind(',') - 1));
  std::vector<std::string> stray_quote = lines, overlong = lines;
  stray_quote[a] = '"' + stray_quote[a];  // a quoted field that the sweep, which writes no line breaks, never opens
  overlong[a] += std::string((std::size_t{1} << 20) + 1, ',');
  std::vector<std::string> other_replay = lines;  // the command that replays the configuration, edited
  const std::size_t replay_at = other_replay[a].find(" --width ");
  ASSERT_NE(replay_at, std::string::npos) << other_replay[a];
  other_replay[a].insert(replay_at, " --allow-bunny");
  std::vector<std::string> missing_first = lines, missing_last = lines, repeated = lines;
  missing_first.erase(missing_first.begin() + static_cast<std::ptrdiff_t>(a));
  missing_last.erase(missing_last.begin() + static_cast<std::ptrdiff_t>(b - 1));
  repeated.insert(repeated.begin() + static_cast<std::ptrdiff_t>(b), lines.begin() + static_cast<std::ptrdiff_t>(a),
                  lines.begin() + static_cast<std::ptrdiff_t>(b));
  struct Case {
    std::string what, text, fragment;
  };
  const Case cases[] = {
      {"garbage last line", joined(lines, 0, lines.size()) + "garbage\n",
       "line " + std::to_string(lines.size() + 1) + ": 1 field(s) where the header has"},
      {"short row mid-file", joined(short_row, 0, lines.size()), "line " + std::to_string(a + 1) + ": "},
      {"missing first row of a configuration", joined(missing_first, 0, missing_first.size()),
       "line " + std::to_string(a + 1) + ": "},
      {"missing last row of a configuration", joined(missing_last, 0, missing_last.size()),
       "line " + std::to_string(b) + ": "},
      {"a configuration repeated", joined(repeated, 0, repeated.size()),
       "line " + std::to_string(b + 1) + ": configuration '" + first_cell(lines[a]) + "'"},
      // Not a write cut off, so not the file's end for --repair to remove.
      {"a stray quote mid-file", joined(stray_quote, 0, lines.size()),
       "line " + std::to_string(a + 1) + ": a quoted field is not closed on its line"},
      {"a line longer than 1 MB mid-file", joined(overlong, 0, lines.size()),
       "line " + std::to_string(a + 1) + ": longer than 1 MB"},
      {"another replay command", joined(other_replay, 0, lines.size()),
       "line " + std::to_string(a + 1) + ": configuration '" + first_cell(lines[a]) +
           "' has other source, kind, detail or replay columns"},
  };
  for (const Case& c : cases) {
    for (const std::string repair : {"", " --repair"}) {
      write_file(csv, c.text);
      const test::CliResult r = test::run_cli(args(csv, "--resume" + repair), "sweep_file_damaged");
      expect_one_line_error(r, "schema", csv + ": " + c.fragment, c.what + repair);
      EXPECT_EQ(test::slurp(csv), c.text) << c.what << repair << ": the file was changed";
    }
  }
}

// A CSV with more configurations than its sidecar's options make (the rows
// of a longer sweep beside a shorter one's sidecar) is refused at the first
// extra configuration, unchanged.
TEST_F(SweepFile, ConfigurationsPastTheOptionsAreRefused) {
  whole("six.csv");
  const std::string seven = path("seven.csv");
  ASSERT_EQ(
      test::run_cli("sweep --samples 7 --seed 5 --width 16 --height 12 --methods zpass,zfail --out '" + seven + "'",
                    "sweep_file_seven")
          .exit_code,
      0);
  fs::copy_file(path("six.csv.meta.json"), seven + ".meta.json", fs::copy_options::overwrite_existing);
  const std::string text = test::slurp(seven);
  const test::CliResult r = test::run_cli(args(seven, "--resume"), "sweep_file_past");
  expect_one_line_error(r, "schema", "is past the 6 configurations these options make", "a seventh configuration");
  EXPECT_EQ(test::slurp(seven), text);
}

// A kill between two writes leaves whole configurations: resumed as it is.
// A kill inside a write leaves the start of one: --repair runs it again.
TEST_F(SweepFile, ACutOffConfigurationNeedsRepairAndAWholeOneDoesNot) {
  const std::string csv = path("a.csv");
  const std::string text = whole("a.csv");
  const std::vector<std::string> lines = lines_of(text);
  const std::vector<std::size_t> starts = group_starts(lines);
  ASSERT_GE(starts.size(), 4u);
  std::size_t g = 1;
  while (g + 1 < starts.size() && starts[g + 1] - starts[g] < 2) ++g;
  ASSERT_LT(g + 1, starts.size());
  // At a configuration boundary: no flag needed.
  write_file(csv, joined(lines, 0, starts[2]));
  const test::CliResult boundary = test::run_cli(args(csv, "--resume"), "sweep_file_boundary");
  ASSERT_EQ(boundary.exit_code, 0) << boundary.err;
  EXPECT_EQ(untimed_rows(test::slurp(csv)), untimed_rows(text));
  // Inside a configuration, at a row's end, and inside a row.
  const std::string at_row = joined(lines, 0, starts[g] + 1);
  const std::string in_row = at_row + lines[starts[g] + 1].substr(0, 30);
  for (const std::string& cut : {at_row, in_row}) {
    write_file(csv, cut);
    const test::CliResult r = test::run_cli(args(csv, "--resume"), "sweep_file_cut");
    expect_one_line_error(r, "schema", "--repair", "a cut-off configuration");
    EXPECT_NE(r.err.find("remove line " + std::to_string(starts[g] + 1) + " onwards"), std::string::npos) << r.err;
    EXPECT_EQ(test::slurp(csv), cut);
    const test::CliResult repaired = test::run_cli(args(csv, "--resume --repair"), "sweep_file_repair");
    ASSERT_EQ(repaired.exit_code, 0) << repaired.err;
    EXPECT_NE(repaired.err.find("removed line " + std::to_string(starts[g] + 1) + " onwards (--repair)"),
              std::string::npos)
        << repaired.err;
    EXPECT_EQ(untimed_rows(test::slurp(csv)), untimed_rows(text));
  }
}

// check_sweep_file reads in blocks: rows across block boundaries, quoted
// fields with commas, quotes and line breaks, and a file of several megabytes.
// A "rejected" row where the scene loads stands only when the configuration,
// computed again, is rejected too.
TEST(SweepFileCheck, ARejectedRowOfASceneThatLoadsIsCheckedByComputingItAgain) {
  const fs::path file = fs::temp_directory_path() / ("nearcap_sweep_rejected_" + std::to_string(::getpid()) + ".csv");
  const analysis::SweepLayout layout{{"default"}, {"zpass"}};
  analysis::SweepRow r;
  r.configuration = "sample:1:0";
  r.source = "sampler";
  r.kind = "grazing";
  r.method = "rejected";
  write_file(file.string(), analysis::csv_header() + analysis::csv_line(r));
  for (int again = 0; again < 3; ++again) {
    const auto expected = [again](std::uint64_t) {
      analysis::ExpectedGroup g;
      g.id = "sample:1:0";
      g.source = "sampler";
      g.kind = "grazing";
      g.lights = 1;
      if (again < 2) g.rejected_after_loading = [again] { return again == 0; };
      return g;
    };
    const int fd = ::open(file.c_str(), O_RDONLY);
    ASSERT_GE(fd, 0);
    if (again == 0) {
      EXPECT_EQ(analysis::check_sweep_file(fd, file.string(), layout, 1, expected).groups, 1u);
    } else {
      try {
        (void)analysis::check_sweep_file(fd, file.string(), layout, 1, expected);
        ADD_FAILURE() << "a rejected row accepted where the configuration is computed whole (" << again << ")";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("is 'rejected' where its scene loads"), std::string::npos) << e.what();
      }
    }
    ::close(fd);
  }
  fs::remove(file);
}

// A row's text fields never hold a line break: an error message in
// `fallback` (which can name a file whose name holds one) has its control
// characters written as escapes, so a line is a row.
TEST(SweepFileCheck, ARowIsOneLineWhateverItsFieldsHold) {
  analysis::SweepRow r;
  r.configuration = "sample:1:0";
  r.fallback = "refused: /tmp/a\nb.off: cannot open the mesh file\r\x01";
  const std::string line = analysis::csv_line(r);
  EXPECT_EQ(line.find('\n'), line.size() - 1) << line;
  EXPECT_EQ(line.find('\r'), std::string::npos) << line;
  EXPECT_NE(line.find("refused: /tmp/a\\nb.off: cannot open the mesh file\\r\\x01"), std::string::npos) << line;
}

TEST(SweepFileCheck, ReadsAFileOfManyBlocksRowByRow) {
  const fs::path file = fs::temp_directory_path() / ("nearcap_sweep_check_" + std::to_string(::getpid()) + ".csv");
  const analysis::SweepLayout layout{{"default", "fma=1"}, {"zpass", "zfail"}};
  const auto expected = [](std::uint64_t k) {
    analysis::ExpectedGroup g;
    g.id = "sample:1:" + std::to_string(k);
    g.source = "sampler";
    g.kind = "grazing";
    g.detail = "a, \"quoted\" line " + std::to_string(k);
    g.replay = "nearcap sample --index " + std::to_string(k);
    g.lights = k % 3 == 0 ? 2u : 1u;
    return g;
  };
  std::string text = analysis::csv_header();
  constexpr std::uint64_t kGroups = 4000;
  for (std::uint64_t k = 0; k < kGroups; ++k) {
    const analysis::ExpectedGroup g = expected(k);
    for (std::size_t light = 0; light < g.lights; ++light)
      for (const std::string& variant : layout.variants)
        for (const std::string& method : layout.entries) {
          analysis::SweepRow r;
          r.configuration = g.id;
          r.source = g.source;
          r.kind = g.kind;
          r.detail = g.detail;
          r.replay = g.replay;
          r.light = light;
          r.method = method;
          r.variant = variant;
          r.fallback = "x,y";
          text += analysis::csv_line(r);
        }
  }
  ASSERT_GT(text.size(), std::size_t{3} << 20);
  write_file(file.string(), text);
  int fd = ::open(file.c_str(), O_RDONLY);
  ASSERT_GE(fd, 0);
  analysis::SweepFileCheck check = analysis::check_sweep_file(fd, file.string(), layout, kGroups, expected);
  ::close(fd);
  EXPECT_EQ(check.groups, kGroups);
  EXPECT_EQ(check.complete_bytes, text.size());
  EXPECT_EQ(check.cut_tail, "");
  EXPECT_EQ(check.lines, static_cast<std::uint64_t>(std::count(text.begin(), text.end(), '\n')));
  // Cut inside the quoted detail of the last configuration's last row.
  const std::size_t cut = text.rfind(" line ");
  ASSERT_NE(cut, std::string::npos);
  write_file(file.string(), text.substr(0, cut));
  fd = ::open(file.c_str(), O_RDONLY);
  check = analysis::check_sweep_file(fd, file.string(), layout, kGroups, expected);
  ::close(fd);
  EXPECT_EQ(check.groups, kGroups - 1);
  EXPECT_NE(check.cut_tail.find("no newline at its end"), std::string::npos) << check.cut_tail;
  fs::remove(file);
}

// ---- the command line ------------------------------------------------------

// A temporary CSV left behind by a killed sweep whose process number this
// one has (in a container, processes start at the same numbers) takes no
// name a new sweep needs.  The sweep runs as process 1 of its own namespace.
TEST_F(SweepFile, ATemporaryFileLeftBehindUnderThisProcessNumberIsSkipped) {
  if (std::system("unshare -pf true > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "unshare -pf (a process namespace) is not allowed here";
  const std::string csv = path("t.csv");
  for (const char* left : {".tmp.1", ".tmp.1.0"}) write_file(csv + left, "left behind\n");
#ifdef NEARCAP_TESTS_UNDER_ASAN
  // LeakSanitizer cannot stop every thread from inside a process namespace
  // ("False leaks are possible"): leak detection off there, every other check on.
  const std::string prefix = "ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" unshare -pf";
#else
  const std::string prefix = "unshare -pf";
#endif
  const test::CliResult r = test::run_cli(args(csv), "sweep_file_tmp", prefix);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(test::slurp(csv + ".tmp.1.0"), "left behind\n");
  EXPECT_EQ(lines_of(test::slurp(csv)).size(), lines_of(whole("w.csv")).size());
}

// A path frame whose keyframes interpolate past double's range has no scene:
// its row is 'rejected' with the reason, as a scene that does not load, and
// the sweep goes on and resumes.
TEST_F(SweepFile, AFrameWithoutASceneIsRejectedAndTheSweepGoesOn) {
  const std::string far = path("far.json");
  write_file(far, "{\"scene\": \"" + std::string(NEARCAP_SOURCE_DIR) +
                      "/data/scenes/room.json\", \"frames\": 3, \"keyframes\": [{\"eye\": [1e308, 2, 3], "
                      "\"target\": [0, 0, 0]}, {\"eye\": [-1e308, 2, 3], \"target\": [0, 0, 0]}]}");
  const std::string sweep =
      "sweep --path '" + far + "' --width 8 --height 6 --methods zpass --out '" + path("f.csv") + "'";
  const test::CliResult r = test::run_cli(sweep, "sweep_file_far");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = lines_of(test::slurp(path("f.csv")));
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_NE(lines[2].find("path:far:1,"), std::string::npos) << lines[2];
  EXPECT_NE(lines[2].find(",rejected,"), std::string::npos) << lines[2];
  EXPECT_NE(lines[2].find("keyframes 0 and 1 interpolate past double's range in eye"), std::string::npos) << lines[2];
  const test::CliResult resumed = test::run_cli(sweep + " --resume", "sweep_file_far_resume");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
}

// A write that fails (a full disk; here the file size limit, its signal
// ignored, so that write() fails with EFBIG) cuts the file back to the last
// whole configuration: one line, and --resume continues to the rows of a
// sweep never stopped.
TEST_F(SweepFile, AFailedWriteLeavesWholeConfigurationsThatResume) {
  const std::string csv = path("full.csv");
  const std::string sweep = "sweep --samples 200 --seed 5 --width 8 --height 6 --methods zpass,zfail --out '";
  const test::CliResult r = test::run_cli(sweep + csv + "'", "sweep_file_full", "trap '' XFSZ; ulimit -f 60;");
  // After the sweep's progress lines, its one error line.
  EXPECT_EQ(r.exit_code, 2) << r.err;
  const std::size_t at = r.err.find("nearcap: error (io): " + csv + ": write failed: ");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\n', at), r.err.size() - 1) << r.err;
  EXPECT_NE(r.err.find("the configuration being written was removed: --resume continues the sweep", at),
            std::string::npos)
      << r.err;
  const std::string cut = test::slurp(csv);
  ASSERT_FALSE(cut.empty());
  EXPECT_EQ(cut.back(), '\n');
  const test::CliResult resumed = test::run_cli(sweep + csv + "' --resume", "sweep_file_full_resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const test::CliResult whole = test::run_cli(sweep + path("whole.csv") + "'", "sweep_file_full_whole");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_EQ(untimed_rows(test::slurp(csv)), untimed_rows(test::slurp(path("whole.csv"))));
}

// The replay column runs nearcap with exactly the path it names, whatever
// the shell makes of its characters.
TEST_F(SweepFile, TheReplayColumnIsQuotedForTheShell) {
  std::string path_text = test::slurp(std::string(NEARCAP_SOURCE_DIR) + "/data/paths/near_plane_sweep.json");
  const auto replace = [&path_text](const std::string& from, const std::string& to) {
    const std::size_t at = path_text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    path_text.replace(at, from.size(), to);
  };
  replace("\"../scenes/", "\"" + std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/");
  replace("\"frames\": 60", "\"frames\": 2");
  const std::string hostile = path("z;echo INJECTED;it's $(echo x).json");
  write_file(hostile, path_text);
  const std::string csv = path("q.csv");
  std::string quoted = "'";
  for (char c : hostile) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  quoted += "'";
  const test::CliResult r =
      test::run_cli("sweep --path " + quoted + " --width 16 --height 12 --methods zpass --out " + csv, "sweep_file_q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = lines_of(test::slurp(csv));
  ASSERT_GE(lines.size(), 2u);
  // The replay column, followed by the reference's two times: a quoted CSV
  // field when it holds a quote or comma.
  std::string replay = lines[1].substr(lines[1].rfind(",nearcap frame ") + 1);
  for (int k = 0; k < 2; ++k) replay.erase(replay.rfind(','));
  ASSERT_EQ(replay.rfind("nearcap frame ", 0), 0u) << replay;
  replay.replace(0, std::string("nearcap").size(), "'" + std::string(NEARCAP_CLI) + "'");
  const std::string run = "cd '" + dir_.string() + "' && " + replay + " > replay.out 2>&1";
  EXPECT_EQ(std::system(run.c_str()), 0) << replay << "\n" << test::slurp(path("replay.out"));
  EXPECT_EQ(test::slurp(path("replay.out")).find("INJECTED"), std::string::npos) << test::slurp(path("replay.out"));
  EXPECT_TRUE(fs::exists(path("c.json"))) << replay;
}

TEST_F(SweepFile, DuplicatedListEntriesAreUsageErrors) {
  const std::string csv = path("d.csv");
  const std::pair<std::string, std::string> cases[] = {
      {"sweep --samples 2 --methods zpass,zfail,zpass --out " + csv, "--methods names zpass twice"},
      {"sweep --samples 2 --policies doom3,ogre,doom3 --out " + csv, "--policies names doom3 twice"},
      {"sweep --samples 2 --policies policy,policy --out " + csv, "--policies names policy twice"},
      {"sweep --path data/paths/zoom.json --path data/paths/zoom.json --out " + csv,
       "--path data/paths/zoom.json is given twice"},
      {"sweep --path data/paths/zoom.json --path ./data/paths/zoom.json --out " + csv,
       "--path ./data/paths/zoom.json is given twice"},
      {"sweep --path data/paths/zoom.json --path " + path("zoom.json") + " --out " + csv, "are both named 'zoom'"},
      {"evaluate --path data/paths/zoom.json --path " + path("zoom.json") + " --out " + path("evaluated"),
       "are both named 'zoom'"},
      {"calibrate --path data/paths/zoom.json --path " + path("zoom.json") + " --out " + csv, "are both named 'zoom'"},
      // A name that a CSV field or a replay command cannot hold as it is.
      {"sweep --path '" + path("z\xff.json") + "' --out " + csv, "is not UTF-8 text, or holds a control character"},
      {"evaluate --path '" + path("z\nline.json") + "' --out " + path("evaluated"),
       "is not UTF-8 text, or holds a control character"},
  };
  fs::copy_file(std::string(NEARCAP_SOURCE_DIR) + "/data/paths/zoom.json", path("zoom.json"));
  for (const char* name : {"z\xff.json", "z\nline.json"}) fs::copy_file(path("zoom.json"), path(name));
  for (const auto& [command, message] : cases) {
    expect_one_line_error(test::run_cli(command, "sweep_file_dup"), "usage", message, command);
    EXPECT_FALSE(fs::exists(csv)) << command;
  }
}

TEST_F(SweepFile, AnOutThatIsNotARegularFileIsNamedAsWhatItIs) {
  const std::string fifo = path("fifo"), dangling = path("dangling.csv");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_symlink(dir_ / "nowhere.csv", dangling);
  const std::pair<std::string, std::string> cases[] = {
      {dangling, dangling + ": a symbolic link to a file that does not exist"},
      {dir_.string(), dir_.string() + ": a directory, not a regular file"},
      {fifo, fifo + ": a FIFO, not a regular file"},
      {"/dev/full", "/dev/full: a character device, not a regular file"},
  };
  for (const auto& [out, message] : cases)
    for (const std::string resume : {"", " --resume"}) {
      const test::CliResult r =
          test::run_cli("sweep --samples 2 --width 16 --height 12" + resume + " --out " + out, "sweep_file_special");
      expect_one_line_error(r, "io", message, out + resume);
      EXPECT_FALSE(fs::exists(analysis::sweep_meta_path(out))) << out;
    }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 2) << "only the FIFO and the link";
}

}  // namespace
}  // namespace nearcap
