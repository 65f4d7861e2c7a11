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

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

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
