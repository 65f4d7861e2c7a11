// `nearcap render --path` draws a camera path in memory that does not grow
// with the path's length: the same path at 20 and at 200 frames peaks within
// a few megabytes.  The peak is the child process's
// own maximum resident set (wait4's rusage), so nothing else this test
// process has run counts.  It runs under glibc's allocator, the one users
// get: were a frame to keep small blocks of its own (its times for
// render.json held in vectors per frame), they would land among the blocks
// the GL driver freed that frame, and glibc's heap would grow by about those
// blocks every frame (docs/findings/path-memory.md), which this test sees.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "cli_support.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

struct PeakRun {
  int exit_code = -1;
  long peak_kb = 0;  // ru_maxrss: the largest resident set the process reached
  std::string err;
};

// Runs `nearcap ARGS...` (NEARCAP_CLI) from the source directory, stdout
// discarded, stderr kept, and measures its peak resident set.
PeakRun run_with_peak(const std::vector<std::string>& args, const fs::path& err_file) {
  std::vector<char*> argv;
  std::string program = NEARCAP_CLI;
  argv.push_back(program.data());
  std::vector<std::string> copies = args;
  for (std::string& a : copies) argv.push_back(a.data());
  argv.push_back(nullptr);
  // The environment without a preloaded allocator, made before the fork.
  std::vector<std::string> environment;
  for (char** e = environ; *e != nullptr; ++e)
    if (std::string_view(*e).rfind("LD_PRELOAD=", 0) != 0) environment.emplace_back(*e);
  std::vector<char*> envp;
  for (std::string& e : environment) envp.push_back(e.data());
  envp.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null_fd = ::open("/dev/null", O_WRONLY);
    const int err_fd = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (null_fd < 0 || err_fd < 0 || ::chdir(NEARCAP_SOURCE_DIR) != 0) ::_exit(127);
    ::dup2(null_fd, 1);
    ::dup2(err_fd, 2);
    ::execve(argv[0], argv.data(), envp.data());
    ::_exit(127);
  }
  PeakRun r;
  int status = 0;
  struct rusage usage {};
  if (pid < 0 || ::wait4(pid, &status, 0, &usage) != pid) return r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.peak_kb = usage.ru_maxrss;
  r.err = test::slurp(err_file);
  return r;
}

class RenderPathMemory : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nearcap_path_memory_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // data/paths/eye_in_shadow.json (the room: a 12,000-triangle torus in a
  // box) at `frames` frames and a 64x48 viewport; returns the path file.
  fs::path path_with(int frames) const {
    nlohmann::json p =
        nlohmann::json::parse(test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data" / "paths" / "eye_in_shadow.json"));
    p["scene"] = (fs::path(NEARCAP_SOURCE_DIR) / "data" / "scenes" / "room.json").string();
    p["frames"] = frames;
    p["width"] = 64;
    p["height"] = 48;
    const fs::path file = dir_ / ("path_" + std::to_string(frames) + ".json");
    std::ofstream(file) << p.dump(1);
    return file;
  }

  // `render --path` at `frames` frames, Z-pass alone.
  PeakRun render(int frames) const {
    const std::string tag = std::to_string(frames);
    return run_with_peak({"render", "--path", path_with(frames).string(), "--method", "zpass", "--out",
                          (dir_ / ("out_" + tag)).string()},
                         dir_ / ("err_" + tag));
  }

  fs::path dir_;
};

TEST_F(RenderPathMemory, TenTimesTheFramesPeaksWithinAFewMegabytes) {
#if defined(NEARCAP_TESTS_UNDER_ASAN)
  GTEST_SKIP() << "AddressSanitizer holds freed memory in its quarantine (256 MB by default), so a longer run's "
                  "peak grows with the memory it has freed, not with what it keeps";
#else
  const PeakRun short_path = render(20);
  if (short_path.exit_code == 2 && short_path.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << short_path.err;
  ASSERT_EQ(short_path.exit_code, 0) << short_path.err;
  const PeakRun long_path = render(200);
  ASSERT_EQ(long_path.exit_code, 0) << long_path.err;
  EXPECT_TRUE(fs::exists(dir_ / "out_200" / "zpass" / "frame-0199.png"));
  const nlohmann::json j = nlohmann::json::parse(test::slurp(dir_ / "out_200" / "render.json"));
  EXPECT_EQ(j["methods"][0]["frames"].size(), 200u);
  std::printf("[ peak     ] 20 frames %ld KB, 200 frames %ld KB\n", short_path.peak_kb, long_path.peak_kb);
  // What a frame leaves behind is its times for render.json (under 1 KB a
  // frame) and its staged file's name: 180 more frames add well under 1 MB.
  // The margin is llvmpipe's own variation from run to run (its threads'
  // arenas and the driver's caches: a few MB).  Each frame's scene kept with
  // its own copy of the torus and the room (read again per frame) adds about
  // 0.8 MB a frame, 149 MB over the 180 frames; a 64x48 frame's PNG kept in
  // memory (a few KB) is below what this test can tell.  A frame's record
  // holding its CPU times in small vectors of its own grows glibc's heap by
  // tens of MB over the 180 frames, by an amount that changes from run to
  // run, though the vectors hold a few hundred bytes: the heap fragments
  // around them (path-memory.md).
  constexpr long kMarginKb = 16 * 1024;
  EXPECT_LE(long_path.peak_kb, short_path.peak_kb + kMarginKb)
      << "the 200-frame path peaks " << (long_path.peak_kb - short_path.peak_kb) / 1024
      << " MB above the 20-frame one: something is kept per frame";
#endif
}

// Along a path each frame's image is staged as it is drawn: a frame that
// cannot be written (its name is a directory) ends the run with one error
// line, no frame before it in place, and the render.json already there kept.
// (Suite RenderCommand: under AddressSanitizer it runs with the EGL tests,
// scripts/test.sh's egl_tests, without leak detection.)
TEST(RenderCommand, AFrameThatCannotBeWrittenLeavesNothingBehind) {
  const fs::path dir = fs::temp_directory_path() / ("nearcap_path_staged_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "out" / "zpass" / "frame-0005.png");
  std::ofstream(dir / "out" / "render.json") << "old";
  nlohmann::json p =
      nlohmann::json::parse(test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data" / "paths" / "eye_in_shadow.json"));
  p["scene"] = (fs::path(NEARCAP_SOURCE_DIR) / "data" / "scenes" / "room.json").string();
  p["frames"] = 12;
  p["width"] = 64;
  p["height"] = 48;
  std::ofstream(dir / "path.json") << p.dump(1);
  const test::CliResult r = test::run_cli(
      "render --path '" + (dir / "path.json").string() + "' --method zpass --out '" + (dir / "out").string() + "'",
      "render_staged");
  if (r.exit_code == 2 && r.err.find("error (gl)") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL here: " << r.err;
  EXPECT_EQ(r.exit_code, 2) << r.err;
  const std::string last_line = r.err.substr(r.err.rfind('\n', r.err.size() - 2) + 1);
  EXPECT_EQ(last_line.rfind("nearcap: error (io): ", 0), 0u) << r.err;
  EXPECT_NE(last_line.find("frame-0005.png"), std::string::npos) << r.err;
  std::set<std::string> left;
  for (const auto& e : fs::recursive_directory_iterator(dir / "out"))
    left.insert(fs::relative(e.path(), dir / "out").string());
  EXPECT_EQ(left, (std::set<std::string>{"render.json", "zpass", "zpass/frame-0005.png"}));
  EXPECT_EQ(test::slurp(dir / "out" / "render.json"), "old");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nearcap
