// Outputs written all or nothing, never renamed over a special file (see
// output_files.hpp).  POSIX: lstat/stat to tell what a destination is, link()
// for no-replace moves and backups, rename() for atomic replacement.
#include "nearcap/io/output_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <utility>

#include "nearcap/error.hpp"
#include "nearcap/io/input_files.hpp"

namespace nearcap::io {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw Error(ErrorKind::Io, path + ": " + what);
}

std::string errno_text(int e) { return std::strerror(e); }

enum class Destination {
  NewName,       // nothing there: link the temporary into place
  RegularFile,   // replace atomically, keeping a backup for the rollback
  WriteThrough,  // a character device or a FIFO: open and write
};

struct Plan {
  std::string user_path;  // as given, for messages
  std::string target;     // the path actually created or replaced (symlinks followed)
  std::string canonical;  // NewName: weakly_canonical(target), to find two outputs naming it
  Destination kind = Destination::NewName;
  mode_t mode = 0666;  // the replaced file's permission bits
  dev_t dev = 0;       // identity of an existing destination
  ino_t ino = 0;
  std::string temporary;  // for NewName and RegularFile
  std::string backup;     // RegularFile: the old content, hard-linked
  bool committed = false;
};

// Follows a chain of symlinks that ends at a name that does not exist yet
// (a dangling link): the name the link would create.
std::string follow_dangling_link(const std::string& path) {
  fs::path p = fs::absolute(path);
  for (int hops = 0; hops < 40; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p.lexically_normal().string();
    const fs::path next = fs::read_symlink(p);
    p = next.is_absolute() ? next : p.parent_path() / next;
  }
  fail(path, "too many levels of symbolic links");
}

// Creates the missing ancestors of `dir`, deepest last; returns those it made.
std::vector<fs::path> create_parents(const fs::path& dir, const std::string& user_path) {
  std::vector<fs::path> missing;
  for (fs::path p = dir; !p.empty(); p = p.parent_path()) {
    struct stat st {};
    if (::stat(p.c_str(), &st) == 0) {
      if (!S_ISDIR(st.st_mode)) fail(user_path, p.string() + " is " + file_kind(st.st_mode) + ", not a directory");
      break;
    }
    if (errno != ENOENT) fail(user_path, "cannot inspect " + p.string() + ": " + errno_text(errno));
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  std::vector<fs::path> created;
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) != 0 && errno != EEXIST) {
      const int e = errno;
      for (auto c = created.rbegin(); c != created.rend(); ++c) ::rmdir(c->c_str());
      fail(user_path, "cannot create the directory " + it->string() + ": " + errno_text(e));
    }
    created.push_back(*it);
  }
  return created;
}

Plan plan_for(const std::string& path) {
  if (path.empty()) fail("(empty path)", "an output path is empty");
  Plan p;
  p.user_path = path;
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {  // exists (symlinks followed)
    p.dev = st.st_dev;
    p.ino = st.st_ino;
    if (S_ISREG(st.st_mode)) {
      p.kind = Destination::RegularFile;
      p.target = fs::canonical(path).string();
      p.mode = st.st_mode & 07777;
    } else if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
      p.kind = Destination::WriteThrough;
      p.target = path;  // opened as named: /proc/self/fd/1 resolves only through open()
    } else {
      fail(path, std::string("is ") + file_kind(st.st_mode) +
                     "; nearcap writes only regular files, character devices "
                     "and FIFOs");
    }
    return p;
  }
  if (errno != ENOENT) fail(path, "cannot inspect the output path: " + errno_text(errno));
  p.kind = Destination::NewName;
  p.target = follow_dangling_link(path);
  p.canonical = fs::weakly_canonical(p.target).string();
  return p;
}

}  // namespace

std::string output_destination(const std::string& path) {
  try {
    return fs::weakly_canonical(follow_dangling_link(path)).string();
  } catch (const fs::filesystem_error& e) {
    fail(path, std::string("cannot resolve the output path: ") + e.code().message());
  }
}

namespace {

std::string temporary_name(const std::string& target, std::size_t k) {
  static std::atomic<unsigned> counter{0};
  const fs::path t(target);
  return (t.parent_path() / ("." + t.filename().string() + ".nearcap-" + std::to_string(::getpid()) + "-" +
                             std::to_string(k) + "-" + std::to_string(counter++)))
      .string();
}

void write_all(int fd, const std::string& content, const std::string& user_path) {
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int e = errno;
      ::close(fd);
      fail(user_path, "write failed: " + errno_text(e));
    }
    done += static_cast<std::size_t>(n);
  }
}

void write_temporary(Plan& p, const std::string& content, std::size_t k) {
  p.temporary = temporary_name(p.target, k);
  const int fd = ::open(p.temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, p.mode);
  if (fd < 0) {
    const int e = errno;
    p.temporary.clear();
    fail(p.user_path, "cannot write the output file: " + errno_text(e));
  }
  if (p.kind == Destination::RegularFile) ::fchmod(fd, p.mode);  // keep the replaced file's permissions
  try {
    write_all(fd, content, p.user_path);
  } catch (...) {
    ::unlink(p.temporary.c_str());
    p.temporary.clear();
    throw;
  }
  if (::close(fd) != 0) {
    const int e = errno;
    ::unlink(p.temporary.c_str());
    p.temporary.clear();
    fail(p.user_path, "write failed: " + errno_text(e));
  }
}

// Moves p's temporary into place.  Throws on failure, leaving p uncommitted.
void commit(Plan& p, std::size_t k) {
  if (p.kind == Destination::NewName) {
    // link() never replaces: a name that appeared since the check is an error.
    if (::link(p.temporary.c_str(), p.target.c_str()) != 0)
      fail(p.user_path, "cannot move the output into place: " + errno_text(errno));
    ::unlink(p.temporary.c_str());
    p.temporary.clear();
    p.committed = true;
    return;
  }
  // RegularFile: keep the old content under a backup name, then replace.
  p.backup = temporary_name(p.target, k) + ".old";
  if (::link(p.target.c_str(), p.backup.c_str()) != 0)
    fail(p.user_path, "cannot keep a backup of the file being replaced: " + errno_text(errno));
  if (::rename(p.temporary.c_str(), p.target.c_str()) != 0) {
    const int e = errno;
    ::unlink(p.backup.c_str());
    p.backup.clear();
    fail(p.user_path, "cannot move the output into place: " + errno_text(e));
  }
  p.temporary.clear();
  p.committed = true;
}

void roll_back(Plan& p) {
  if (!p.committed) return;
  if (p.kind == Destination::NewName) {
    ::unlink(p.target.c_str());
  } else if (p.kind == Destination::RegularFile && !p.backup.empty()) {
    ::rename(p.backup.c_str(), p.target.c_str());
    p.backup.clear();
  }
  p.committed = false;
}

void write_through(const Plan& p, const std::string& content) {
  const int fd = ::open(p.target.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) fail(p.user_path, "cannot open for writing: " + errno_text(errno));
  write_all(fd, content, p.user_path);
  ::close(fd);
}

// Two plans that name one file: the same existing inode, or the same new name.
bool same_destination(const Plan& a, const Plan& b) {
  if (a.kind != Destination::NewName && b.kind != Destination::NewName) return a.dev == b.dev && a.ino == b.ino;
  return a.kind == Destination::NewName && b.kind == Destination::NewName && a.canonical == b.canonical;
}

[[noreturn]] void fail_same_destination(const Plan& first, const Plan& second) {
  throw Error(ErrorKind::Usage, second.user_path + ": two outputs of this command name the same file ('" +
                                    first.user_path + "' and '" + second.user_path + "')");
}

// Creates p's missing parents (a new name only), appending them to `created`.
void create_parents_of(const Plan& p, std::vector<fs::path>& created) {
  if (p.kind != Destination::NewName) return;
  const std::vector<fs::path> made = create_parents(fs::path(p.target).parent_path(), p.user_path);
  created.insert(created.end(), made.begin(), made.end());
}

void remove_temporaries(std::vector<Plan>& plans) {
  for (Plan& p : plans)
    if (!p.temporary.empty()) {
      ::unlink(p.temporary.c_str());
      p.temporary.clear();
    }
}

void remove_directories(const std::vector<fs::path>& created) {
  for (auto it = created.rbegin(); it != created.rend(); ++it) ::rmdir(it->c_str());
}

// Every temporary of `plans` moved into place, then the write-throughs
// (`through[k]` the bytes of plans[k] when it is one); on any failure every
// output is rolled back and the temporaries and `created` removed.
void commit_all(std::vector<Plan>& plans, const std::vector<const std::string*>& through,
                const std::vector<fs::path>& created) {
  try {
    for (std::size_t k = 0; k < plans.size(); ++k)
      if (plans[k].kind != Destination::WriteThrough) commit(plans[k], k);
    for (std::size_t k = 0; k < plans.size(); ++k)
      if (plans[k].kind == Destination::WriteThrough) write_through(plans[k], *through[k]);
  } catch (...) {
    for (auto it = plans.rbegin(); it != plans.rend(); ++it) roll_back(*it);
    remove_temporaries(plans);
    remove_directories(created);
    throw;
  }
  for (Plan& p : plans)
    if (!p.backup.empty()) ::unlink(p.backup.c_str());
}

// Every destination's plan, each checked, and no two naming one file.
std::vector<Plan> checked_plans(const std::vector<std::string>& paths) {
  std::vector<Plan> plans;
  plans.reserve(paths.size());
  for (const std::string& p : paths) plans.push_back(plan_for(p));
  for (std::size_t a = 0; a < plans.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (same_destination(plans[a], plans[b])) fail_same_destination(plans[b], plans[a]);
  return plans;
}

void write_output_files_unguarded(const std::vector<OutputFile>& files) {
  // 1. Check every destination before touching any.
  std::vector<std::string> paths;
  paths.reserve(files.size());
  for (const OutputFile& f : files) paths.push_back(f.path);
  std::vector<Plan> plans = checked_plans(paths);

  // 2. Directories, then temporaries; any failure removes what was made.
  std::vector<fs::path> created_dirs;
  try {
    for (const Plan& p : plans) create_parents_of(p, created_dirs);
    for (std::size_t k = 0; k < plans.size(); ++k)
      if (plans[k].kind != Destination::WriteThrough) write_temporary(plans[k], files[k].content, k);
  } catch (...) {
    remove_temporaries(plans);
    remove_directories(created_dirs);
    throw;
  }

  // 3. Renames, rolled back together on any failure; then the write-throughs.
  std::vector<const std::string*> through;
  through.reserve(files.size());
  for (const OutputFile& f : files) through.push_back(&f.content);
  commit_all(plans, through, created_dirs);
}

template <typename F>
auto filesystem_errors_as_io(F&& f) {
  try {
    return f();
  } catch (const fs::filesystem_error& e) {
    throw Error(ErrorKind::Io, e.path1().string() + ": " + e.code().message());
  }
}

}  // namespace

void write_output_files(const std::vector<OutputFile>& files) {
  filesystem_errors_as_io([&] { write_output_files_unguarded(files); });
}

// Can a file be made where p's target goes?  A temporary made and removed
// at once in the target's directory, or, where that does not exist yet, in
// its deepest ancestor that does (where the write would create the rest).
void probe_writable(const Plan& p, std::size_t k) {
  if (p.kind == Destination::WriteThrough) return;
  fs::path dir = fs::path(p.target).parent_path();
  for (;;) {
    if (dir.empty()) dir = ".";
    struct stat st {};
    if (::stat(dir.c_str(), &st) == 0) break;
    if (errno != ENOENT || dir == dir.parent_path() || dir == ".") return;  // the write says what is wrong
    dir = dir.parent_path();
  }
  const std::string temporary = temporary_name((dir / fs::path(p.target).filename()).string(), k);
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) fail(p.user_path, "cannot write in " + dir.string() + ": " + errno_text(errno));
  ::close(fd);
  ::unlink(temporary.c_str());
}

void check_output_files(const std::vector<std::string>& paths) {
  filesystem_errors_as_io([&] {
    const std::vector<Plan> plans = checked_plans(paths);
    for (std::size_t k = 0; k < plans.size(); ++k) probe_writable(plans[k], k);
  });
}

struct StagedOutputFiles::State {
  std::vector<Plan> plans;
  std::vector<std::string> through;  // a write-through plan's bytes, else empty
  std::set<std::pair<dev_t, ino_t>> existing;
  std::map<std::string, std::size_t> new_names;  // canonical target -> plan
  std::vector<fs::path> created_dirs;
  bool committed = false;
};

StagedOutputFiles::StagedOutputFiles() : state_(std::make_unique<State>()) {}

StagedOutputFiles::~StagedOutputFiles() {
  if (state_->committed) return;
  remove_temporaries(state_->plans);
  remove_directories(state_->created_dirs);
}

void StagedOutputFiles::add(const OutputFile& file) {
  State& s = *state_;
  if (s.committed) throw Error(ErrorKind::Usage, file.path + ": added to outputs already committed");
  filesystem_errors_as_io([&] {
    Plan p = plan_for(file.path);
    // The same checks as same_destination, through an index: a path has thousands of frames.
    if (p.kind == Destination::NewName) {
      const auto [it, fresh] = s.new_names.emplace(p.canonical, s.plans.size());
      if (!fresh) fail_same_destination(s.plans[it->second], p);
    } else if (!s.existing.insert({p.dev, p.ino}).second) {
      for (const Plan& q : s.plans)
        if (same_destination(q, p)) fail_same_destination(q, p);
    }
    try {
      create_parents_of(p, s.created_dirs);
      if (p.kind != Destination::WriteThrough) write_temporary(p, file.content, s.plans.size());
    } catch (...) {
      if (p.kind == Destination::NewName)
        s.new_names.erase(p.canonical);
      else
        s.existing.erase({p.dev, p.ino});
      throw;
    }
    s.through.push_back(p.kind == Destination::WriteThrough ? file.content : std::string());
    s.plans.push_back(std::move(p));
  });
}

void StagedOutputFiles::commit() {
  State& s = *state_;
  if (s.committed) throw Error(ErrorKind::Usage, "outputs committed twice");
  std::vector<const std::string*> through;
  through.reserve(s.through.size());
  for (const std::string& t : s.through) through.push_back(&t);
  s.committed = true;  // commit_all cleans up after itself when it fails: nothing is left for the destructor
  filesystem_errors_as_io([&] { commit_all(s.plans, through, s.created_dirs); });
}

}  // namespace nearcap::io
