// Running the nearcap program from tests: exit code, stdout, stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace nearcap::test {

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

// A path in the temp directory that no other test process uses: `name` and
// this process's id (ctest runs tests in parallel processes, and other test
// runs may share the machine's temp directory).
inline std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The `prefix` of runs that end in seconds, also under AddressSanitizer on
// a loaded 2-core machine, but would never end where the program under test
// is wrong (it reads a FIFO or /dev/zero, a resume is not refused): a bound on
// a hang, far above any run's work, so that only a hang reaches it.
inline const std::string kHangBound = "timeout 300";

// Runs `nearcap ARGS` (NEARCAP_CLI) from the source directory; `prefix` goes
// before the program (environment assignments, `timeout 30`).
inline CliResult run_cli(const std::string& args, const std::string& tag, const std::string& prefix = "") {
  // Unique per process and call: ctest runs tests in parallel processes.
  static int calls = 0;
  const std::string stem = "nearcap_test_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(calls++);
  const auto dir = std::filesystem::temp_directory_path();
  const auto out = dir / (stem + ".out"), err = dir / (stem + ".err");
  const std::string command = "cd '" + std::string(NEARCAP_SOURCE_DIR) + "' && " + prefix + " '" +
                              std::string(NEARCAP_CLI) + "' " + args + " > '" + out.string() + "' 2> '" + err.string() +
                              "'";
  const int status = std::system(command.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

}  // namespace nearcap::test
