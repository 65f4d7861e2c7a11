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
// The script's stderr goes to a log file in the temporary directory; the
// command prints one line whatever happens to the script: its own
// "nearcap: error (KIND): ..." line (the log is kept and named only when the
// script wrote more than that line), or, when the script exits non-zero
// without one or dies on a signal, a line naming the script, the status and
// the log.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cli_commands.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/input_files.hpp"
#include "nearcap/io/utf8_text.hpp"
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

// The log's last non-empty line and whether it holds other text besides it;
// reads at most its last 64 kB.
struct LogTail {
  std::string last_line;
  bool more = false;
};

LogTail tail_of(const std::string& log) {
  LogTail t;
  std::ifstream in(log, std::ios::binary | std::ios::ate);
  if (!in) return t;
  const std::streamoff size = in.tellg();
  const std::streamoff from = size > 65536 ? size - 65536 : 0;
  in.seekg(from);
  std::string text(static_cast<std::size_t>(size - from), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.pop_back();
  const std::size_t start = text.rfind('\n');
  t.last_line = start == std::string::npos ? text : text.substr(start + 1);
  t.more = from > 0 || start != std::string::npos;
  return t;
}

void forward(const std::string& log) {
  std::ifstream in(log, std::ios::binary);
  if (in && in.peek() != std::ifstream::traits_type::eof()) std::cerr << in.rdbuf();
  std::cerr.flush();
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
  const std::string log = temporary_file("nearcap-report-", ".log");  // none: the script's stderr stays on the terminal
  if (log.empty()) {
    const int code = run_python_script(script, args, "the report");
    if (code != 0) throw ExitCode{code};
    return;
  }
  int status = 0;
  try {
    status = run_python_script_logged(script, args, "the report", log);
  } catch (...) {
    std::filesystem::remove(log);
    throw;
  }
  std::error_code ec;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    forward(log);  // warnings, if any
    std::filesystem::remove(log, ec);
    return;
  }
  const LogTail tail = tail_of(log);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 2 && tail.last_line.rfind("nearcap: error (", 0) == 0) {
    if (tail.more) {
      std::cerr << io::escaped_control_characters(tail.last_line) << " (the report script's other output: " << log
                << ")\n";
    } else {
      std::cerr << io::escaped_control_characters(tail.last_line) << "\n";
      std::filesystem::remove(log, ec);
    }
    throw ExitCode{2};
  }
  std::string how = WIFEXITED(status) ? "exited with status " + std::to_string(WEXITSTATUS(status))
                                      : "was killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
                                            std::string(::strsignal(WTERMSIG(status))) + ")";
  const char* python = std::getenv("NEARCAP_PYTHON");
  if (python && *python) how += " (NEARCAP_PYTHON=" + std::string(python) + ")";
  if (tail.last_line.empty() && !tail.more) {
    std::filesystem::remove(log, ec);
    throw Error(ErrorKind::Io,
                script + ": the report script " + how + " without a message (it wrote nothing on stderr)");
  }
  throw Error(ErrorKind::Io, script + ": the report script " + how + " without an error line; its output is in " + log);
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
