// nearcap report RESULTS.csv... --out DIR: the sweep report (HTML page,
// matplotlib plots, tables) drawn by analysis/report/sweep_report.py, which
// this command finds and runs with a Python that has matplotlib.
//
// The script: NEARCAP_REPORT_SCRIPT, else the source tree's
// analysis/report/sweep_report.py this program was built from.  The Python:
// NEARCAP_PYTHON, else /usr/bin/python3 (where Debian's python3-matplotlib
// lives), else python3 on the PATH.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"

namespace nearcap::cli {
namespace {

std::string report_script() {
  const char* env = std::getenv("NEARCAP_REPORT_SCRIPT");
  if (env && *env) return env;
  return std::string(NEARCAP_ANALYSIS_DIR) + "/report/sweep_report.py";
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
  std::vector<std::string> args(results.begin(), results.end());
  args.push_back("--out");
  args.push_back(out);
  if (!policy.empty()) {
    args.push_back("--policy");
    args.push_back(policy);
  }
  const int status = run_python_script(script, args, "the report");
  if (status == 0) return;
  // The script printed its own one-line error; exit with its code.
  throw ExitCode{status};
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
