// Bounded reads of regular files (see input_files.hpp).
#include "nearcap/io/input_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "nearcap/error.hpp"

namespace nearcap::io {
namespace {

constexpr std::uint64_t kDefaultMaxInputMb = 1024;

std::string megabytes(std::uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MB"; }

}  // namespace

std::uint64_t max_input_bytes() {
  const char* env = std::getenv("NEARCAP_MAX_INPUT_MB");
  if (env == nullptr || *env == '\0') return kDefaultMaxInputMb << 20;
  constexpr std::uint64_t kMaxMb = std::uint64_t{1} << 40;
  std::uint64_t mb = 0;
  bool too_large = false;
  for (const char* c = env; *c; ++c) {
    if (*c < '0' || *c > '9')
      throw Error(ErrorKind::Usage,
                  std::string("NEARCAP_MAX_INPUT_MB='") + env + "' is not a positive whole number of megabytes");
    mb = 10 * mb + static_cast<std::uint64_t>(*c - '0');
    too_large = too_large || mb > kMaxMb;
    if (too_large) mb = kMaxMb + 1;  // no overflow, whatever the digits that follow
  }
  if (too_large)
    throw Error(ErrorKind::Usage, std::string("NEARCAP_MAX_INPUT_MB='") + env + "' is above " + std::to_string(kMaxMb) +
                                      " megabytes, more than any machine reads");
  if (mb == 0) throw Error(ErrorKind::Usage, "NEARCAP_MAX_INPUT_MB must be at least 1");
  return mb << 20;
}

std::string read_input_file(const std::string& path, const std::string& what) {
  const std::uint64_t limit = max_input_bytes();
  const std::uint64_t size = check_input_file(path, what);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    throw Error(ErrorKind::Io, path + ": cannot open the " + what + ": " + std::strerror(e));
  }
  std::string bytes;
  bytes.reserve(static_cast<std::size_t>(size));
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int e = errno;
      ::close(fd);
      throw Error(ErrorKind::Io, path + ": cannot read the " + what + ": " + std::strerror(e));
    }
    if (n == 0) break;
    bytes.append(buffer, static_cast<std::size_t>(n));
    if (bytes.size() > limit) {  // the file grew while being read
      ::close(fd);
      throw Error(ErrorKind::Resource,
                  path + ": the " + what + " grew past the input limit of " + megabytes(limit) + " while being read");
    }
  }
  ::close(fd);
  return bytes;
}

std::uint64_t check_input_file(const std::string& path, const std::string& what) {
  const std::uint64_t limit = max_input_bytes();
  if (path.empty()) throw Error(ErrorKind::Usage, "the " + what + "'s name is empty");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int e = errno;
    if (e == ENOENT) throw Error(ErrorKind::Io, path + ": cannot open the " + what + " (no such file)");
    throw Error(ErrorKind::Io, path + ": cannot open the " + what + ": " + std::strerror(e));
  }
  if (!S_ISREG(st.st_mode))
    throw Error(ErrorKind::Io,
                path + ": is " + file_kind(st.st_mode) + ", not a " + what + " (nearcap reads only regular files)");
  if (static_cast<std::uint64_t>(st.st_size) > limit)
    throw Error(ErrorKind::Resource, path + ": the " + what + " is " + megabytes(st.st_size) +
                                         ", over the input limit of " + megabytes(limit) +
                                         " (raise it with NEARCAP_MAX_INPUT_MB)");
  return static_cast<std::uint64_t>(st.st_size);
}

const char* file_kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  return "a special file";
}

}  // namespace nearcap::io
