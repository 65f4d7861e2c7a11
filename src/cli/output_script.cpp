// The shipped Python scripts that write a file (see output_script.hpp).
#include "output_script.hpp"

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/utf8_text.hpp"

namespace nearcap::cli {
namespace {

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

// Which file a name holds and when it was last written: a file the script
// wrote has another inode or modification time than the one before it ran.
struct FileStamp {
  dev_t device = 0;
  ino_t inode = 0;
  timespec modified{};
  bool operator==(const FileStamp& o) const {
    return device == o.device && inode == o.inode && modified.tv_sec == o.modified.tv_sec &&
           modified.tv_nsec == o.modified.tv_nsec;
  }
};

std::optional<FileStamp> stamp_of(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  return FileStamp{st.st_dev, st.st_ino, st.st_mtim};
}

// Waitpid's raw status as words ("exited with status 1", "was killed by
// signal 9 (Killed)"), naming NEARCAP_PYTHON when it is set.
std::string how_it_ended(int status) {
  std::string how = WIFEXITED(status) ? "exited with status " + std::to_string(WEXITSTATUS(status))
                                      : "was killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
                                            std::string(::strsignal(WTERMSIG(status))) + ")";
  const char* python = std::getenv("NEARCAP_PYTHON");
  if (python && *python) how += " (NEARCAP_PYTHON=" + std::string(python) + ")";
  return how;
}

// Runs the script and ends as output_script.hpp says; `output` empty: no file expected.
void run_script(const std::string& script, const std::vector<std::string>& args, const std::string& what,
                const std::string& output) {
  const std::optional<FileStamp> before = output.empty() ? std::nullopt : stamp_of(output);
  auto check_written = [&] {
    if (output.empty()) return;
    const std::optional<FileStamp> after = stamp_of(output);
    if (!after || (before && *after == *before))
      throw Error(ErrorKind::Io, script + ": " + what + " exited with status 0 without writing " + output);
  };
  const std::string log = temporary_file("nearcap-script-", ".log");  // none: its stderr stays on the terminal
  if (log.empty()) {
    const int code = run_python_script(script, args, what);
    if (code == 2) throw ExitCode{2};  // its own error line is on the terminal
    if (code != 0)
      throw Error(ErrorKind::Io,
                  script + ": " + what + " exited with status " + std::to_string(code) + " (its output is above)");
    check_written();
    return;
  }
  int status = 0;
  try {
    status = run_python_script_logged(script, args, what, log);
  } catch (...) {
    std::filesystem::remove(log);
    throw;
  }
  std::error_code ec;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    forward(log);  // warnings, if any
    std::filesystem::remove(log, ec);
    check_written();
    return;
  }
  const LogTail tail = tail_of(log);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 2 && tail.last_line.rfind("nearcap: error (", 0) == 0) {
    if (tail.more) {
      std::cerr << io::escaped_control_characters(tail.last_line) << " (" << what << "'s other output: " << log
                << ")\n";
    } else {
      std::cerr << io::escaped_control_characters(tail.last_line) << "\n";
      std::filesystem::remove(log, ec);
    }
    throw ExitCode{2};
  }
  if (tail.last_line.empty() && !tail.more) {
    std::filesystem::remove(log, ec);
    throw Error(ErrorKind::Io,
                script + ": " + what + " " + how_it_ended(status) + " without a message (it wrote nothing on stderr)");
  }
  throw Error(ErrorKind::Io,
              script + ": " + what + " " + how_it_ended(status) + " without an error line; its output is in " + log);
}

}  // namespace

void check_script_file(const std::string& script, const std::string& what) {
  struct stat st {};
  if (::stat(script.c_str(), &st) != 0 || ::access(script.c_str(), R_OK) != 0)
    throw Error(ErrorKind::Io, script + ": " + what + " is missing: " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw Error(ErrorKind::Io, script + ": " + what + " is not a regular file");
}

void run_output_script(const std::string& script, const std::vector<std::string>& args, const std::string& what,
                       const std::string& output) {
  run_script(script, args, what, output);
}

void check_output_script(const std::string& script, const std::string& what) {
  check_script_file(script, what);
  run_script(script, {"--check"}, what, "");
}

}  // namespace nearcap::cli
