// nearcap report RESULTS.csv... --out DIR: the sweep report (HTML page,
// matplotlib plots, tables) drawn by analysis/report/sweep_report.py, which
// this command finds and runs with a Python that has matplotlib.
//
// The script: NEARCAP_REPORT_SCRIPT, else the source tree's
// analysis/report/sweep_report.py this program was built from.  The Python:
// NEARCAP_PYTHON, else /usr/bin/python3 (where Debian's python3-matplotlib
// lives), else python3 on the PATH.
//
// Inputs are checked here before the script runs, like a scene: each CSV and
// the policy a regular file under a size limit (NEARCAP_MAX_INPUT_MB when set;
// unset, the scene limit for the policy and kDefaultMaxCsvBytes for a CSV,
// which the script streams), the policy read and validated as `nearcap
// sweep --policy` reads it.  The script checks each CSV line as it streams
// it (UTF-8, columns, numbers) and refuses an --out whose files would
// replace an input.
//
// The script takes the methods' names, order, descriptions and roles from
// the settings table (`nearcap settings`), which this command writes to a
// temporary file and passes as --settings.
//
// The script runs as output_script.hpp says: its stderr in a log file of
// the temporary directory, one line on stderr whatever happens to it (its
// own "nearcap: error (KIND): ..." line, or one naming the script, its
// status and the log), and an exit 0 that leaves DIR/index.html unwritten
// is an error.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "cli_commands.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/input_files.hpp"
#include "output_script.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

// A sweep CSV's default size limit: the million-configuration sweep's CSV is
// about 3.0 GB (docs/findings/sweep-speed.md); the report streams it
// in bounded memory, so the limit bounds only the time (a few minutes per GB;
// docs/findings/report-scale.md).
constexpr std::uint64_t kDefaultMaxCsvBytes = std::uint64_t{16} << 30;

std::string report_script() {
  const char* env = std::getenv("NEARCAP_REPORT_SCRIPT");
  if (env && *env) return env;
  return shipped_scripts_dir() + "/report/sweep_report.py";
}

std::string megabytes(std::uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MB"; }

void check_csv(const std::string& path, std::uint64_t limit) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error(ErrorKind::Io, path + ": cannot read the sweep results: " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw Error(ErrorKind::Io, path + ": not a regular file (a sweep's CSV was expected)");
  if (static_cast<std::uint64_t>(st.st_size) > limit)
    throw Error(ErrorKind::Resource, path + ": the sweep CSV is " + megabytes(st.st_size) +
                                         ", over the input limit of " + megabytes(limit) +
                                         " (raise it with NEARCAP_MAX_INPUT_MB)");
}

std::uint64_t csv_limit() {
  const char* env = std::getenv("NEARCAP_MAX_INPUT_MB");
  return env && *env ? io::max_input_bytes() : kDefaultMaxCsvBytes;
}

struct ReportOptions {
  std::vector<std::string> results;
  std::string out;
  std::string policy;
};

void run(const std::vector<std::string>& results, const std::string& out, const std::string& policy) {
  const std::uint64_t limit = csv_limit();
  for (const std::string& r : results) check_csv(r, limit);
  if (!policy.empty()) analysis::parse_policy(io::read_input_file(policy, "policy"), policy);
  const std::string script = report_script();
  if (::access(script.c_str(), R_OK) != 0)
    throw Error(ErrorKind::Io, script +
                                   ": the report script is missing (set NEARCAP_REPORT_SCRIPT to "
                                   "analysis/report/sweep_report.py of a nearcap source tree)");
  check_script_file(script, "the report script");
  std::vector<std::string> args(results.begin(), results.end());
  args.push_back("--out");
  args.push_back(out);
  if (!policy.empty()) {
    args.push_back("--policy");
    args.push_back(policy);
  }
  const SettingsFile settings;
  args.push_back("--settings");
  args.push_back(settings.path());
  run_output_script(script, args, "the report script", (std::filesystem::path(out) / "index.html").string());
}

}  // namespace

void register_report(CLI::App& app) {
  auto [cmd, o] = add_subcommand<ReportOptions>(
      app, "report",
      "the sweep report: DIR/index.html with plots (matplotlib) and tables from one or more `nearcap sweep` CSVs",
      [](const ReportOptions& r) { run(r.results, r.out, r.policy); });
  cmd.add_option("results", o.results, "sweep CSV files (rows of several sweeps or MPI runs are merged)")->required();
  cmd.add_option("--out", o.out,
                 "the report's directory (created; the report's own files in it are replaced, other files kept; "
                 "refused when that would replace an input)")
      ->required();
  cmd.add_option("--policy", o.policy, "a switch policy (nearcap tune) whose fitted models the report shows");
}

}  // namespace nearcap::cli
