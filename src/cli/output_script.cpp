// The shipped Python scripts that write a file (see output_script.hpp).
#include "output_script.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>

#include "cli_commands.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/utf8_text.hpp"

namespace nearcap::cli {
namespace {

// Where the script's stderr goes: a file of the temporary directory, kept
// and named when the script fails without an error line of its own; an
// anonymous file in memory where the temporary directory takes none.
class ScriptLog {
 public:
  ScriptLog() : path_(temporary_file("nearcap-script-", ".log")) {
    fd_ = path_.empty() ? ::memfd_create("nearcap-script-log", MFD_CLOEXEC)
                        : ::open(path_.c_str(), O_RDWR | O_TRUNC | O_CLOEXEC);
    if (fd_ < 0) {
      const std::string reason = std::strerror(errno);
      remove();
      throw Error(ErrorKind::Io, "cannot make a log for a script's messages: " + reason);
    }
  }
  ScriptLog(const ScriptLog&) = delete;
  ScriptLog& operator=(const ScriptLog&) = delete;
  ~ScriptLog() {
    if (fd_ >= 0) ::close(fd_);
    if (!kept_) remove();
  }
  int fd() const { return fd_; }
  // What the script wrote (its last 64 kB).
  std::string text() const {
    const off_t size = ::lseek(fd_, 0, SEEK_END);
    const off_t from = std::max<off_t>(0, size - 65536);
    std::string out(static_cast<std::size_t>(std::max<off_t>(0, size - from)), '\0');
    std::size_t got = 0;
    while (got < out.size()) {
      const ssize_t n = ::pread(fd_, out.data() + got, out.size() - got, from + static_cast<off_t>(got));
      if (n <= 0) break;
      got += static_cast<std::size_t>(n);
    }
    out.resize(got);
    truncated_ = from > 0;
    return out;
  }
  bool truncated() const { return truncated_; }
  // Where to read all of it: the kept file, or its last line where there is none.
  std::string where(const std::string& last_line) {
    if (!path_.empty()) {
      kept_ = true;
      return "its output is in " + path_;
    }
    return "its last line: " + io::escaped_control_characters(last_line.substr(0, 300));
  }

 private:
  void remove() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove(path_, ec);
  }
  std::string path_;
  int fd_ = -1;
  bool kept_ = false;
  mutable bool truncated_ = false;
};

// The text's last non-empty line, and whether it holds other text besides it.
struct LogTail {
  std::string last_line;
  bool more = false;
};

LogTail tail_of(std::string text, bool truncated) {
  LogTail t;
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) text.pop_back();
  const std::size_t start = text.rfind('\n');
  t.last_line = start == std::string::npos ? text : text.substr(start + 1);
  t.more = truncated || start != std::string::npos;
  return t;
}

// Which file a name holds and when it was last written: a file the script
// wrote has another inode or modification time than the one before it ran
// (a file system whose times are coarser than the time between two runs
// writing a file in place would read as unwritten).
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
  ScriptLog log;
  const int status = run_python_script_logged(script, args, what, log.fd());
  const std::string text = log.text();
  const LogTail tail = tail_of(text, log.truncated());
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    if (!output.empty()) {
      const std::optional<FileStamp> after = stamp_of(output);
      if (!after || (before && *after == *before))
        throw Error(ErrorKind::Io, script + ": " + what + " " + how_it_ended(status) + " without writing " + output +
                                       (tail.last_line.empty() ? "" : "; " + log.where(tail.last_line)));
    }
    std::cerr << text;  // its warnings, if any
    std::cerr.flush();
    return;
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 2 && tail.last_line.rfind("nearcap: error (", 0) == 0) {
    std::cerr << io::escaped_control_characters(tail.last_line);
    if (tail.more) std::cerr << " (" << what << "'s other output: " << log.where(tail.last_line) << ")";
    std::cerr << "\n";
    throw ExitCode{2};
  }
  if (tail.last_line.empty() && !tail.more)
    throw Error(ErrorKind::Io,
                script + ": " + what + " " + how_it_ended(status) + " without a message (it wrote nothing on stderr)");
  throw Error(ErrorKind::Io, script + ": " + what + " " + how_it_ended(status) + " without an error line; " +
                                 log.where(tail.last_line));
}

}  // namespace

void check_script_file(const std::string& script, const std::string& what) {
  struct stat st {};
  if (::stat(script.c_str(), &st) != 0)
    throw Error(ErrorKind::Io, script + ": " + what + " is missing: " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw Error(ErrorKind::Io, script + ": " + what + " is not a regular file");
  if (::access(script.c_str(), R_OK) != 0)
    throw Error(ErrorKind::Io, script + ": " + what + " cannot be read: " + std::strerror(errno));
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
