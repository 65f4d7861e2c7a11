// nearcap report RESULTS.csv... --out DIR: the sweep report (HTML page,
// matplotlib plots, tables) drawn by analysis/report/sweep_report.py, which
// this command finds and runs with a Python that has matplotlib.
//
// The script: NEARCAP_REPORT_SCRIPT, else the source tree's
// analysis/report/sweep_report.py this program was built from.  The Python:
// NEARCAP_PYTHON, else /usr/bin/python3 (where Debian's python3-matplotlib
// lives), else python3 on the PATH.
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"

extern char** environ;

namespace nearcap::cli {
namespace {

std::string report_script() {
  const char* env = std::getenv("NEARCAP_REPORT_SCRIPT");
  if (env && *env) return env;
  return std::string(NEARCAP_ANALYSIS_DIR) + "/report/sweep_report.py";
}

std::string python() {
  const char* env = std::getenv("NEARCAP_PYTHON");
  if (env && *env) return env;
  if (::access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return "python3";
}

void run(const std::vector<std::string>& results, const std::string& out, const std::string& policy) {
  for (const std::string& r : results) {
    struct stat st {};
    if (::stat(r.c_str(), &st) != 0)
      throw Error(ErrorKind::Io, r + ": cannot read the sweep results: " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw Error(ErrorKind::Io, r + ": not a regular file (a sweep's CSV was expected)");
  }
  const std::string script = report_script();
  if (::access(script.c_str(), R_OK) != 0)
    throw Error(ErrorKind::Io, script +
                                   ": the report script is missing (set NEARCAP_REPORT_SCRIPT to "
                                   "analysis/report/sweep_report.py of a nearcap source tree)");
  const std::string py = python();
  std::vector<std::string> args{py, script};
  args.insert(args.end(), results.begin(), results.end());
  args.push_back("--out");
  args.push_back(out);
  if (!policy.empty()) {
    args.push_back("--policy");
    args.push_back(policy);
  }
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = ::posix_spawnp(&pid, py.c_str(), nullptr, nullptr, argv.data(), environ);
  if (spawned != 0)
    throw Error(ErrorKind::Io, py + ": cannot run Python for the report: " + std::strerror(spawned) +
                                   " (scripts/install-deps.sh installs python3 and python3-matplotlib)");
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR)
      throw Error(ErrorKind::Io, "waiting for the report script: " + std::string(std::strerror(errno)));
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  // The script printed its own one-line error; exit with its code.
  throw ExitCode{WIFEXITED(status) ? WEXITSTATUS(status) : 1};
}

}  // namespace

void register_report(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "report",
      "the sweep report: DIR/index.html with plots (matplotlib) and tables from one or more `nearcap sweep` CSVs");
  auto results = std::make_shared<std::vector<std::string>>();
  auto out = std::make_shared<std::string>();
  auto policy = std::make_shared<std::string>();
  cmd->add_option("results", *results, "sweep CSV files (rows of several sweeps or MPI runs are merged)")->required();
  cmd->add_option("--out", *out, "the report's directory (created; its files replaced)")->required();
  cmd->add_option("--policy", *policy, "a switch policy (nearcap tune) whose fitted models the report shows");
  cmd->callback([results, out, policy] { run(*results, *out, *policy); });
}

}  // namespace nearcap::cli
