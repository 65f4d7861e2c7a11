// Outputs all or nothing, never renamed over a special file
// (nearcap/io/output_files.hpp).  Every test works in its own temporary
// directory; none touches /dev/null or another device node.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "cli_support.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/output_files.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

class OutputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nearcap_output_files_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static void put(const std::string& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
  // The directory's entries, so a test can see that no temporary or backup is left.
  std::set<std::string> entries(const fs::path& d) const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(d)) names.insert(e.path().filename().string());
    return names;
  }
  static bool is_fifo(const std::string& p) {
    struct stat st {};
    return ::lstat(p.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
  }
  fs::path dir_;
};

ErrorKind kind_of_failure(const std::vector<io::OutputFile>& files) {
  try {
    io::write_output_files(files);
  } catch (const Error& e) {
    return e.kind();
  }
  ADD_FAILURE() << "no error";
  return ErrorKind::Usage;
}

TEST_F(OutputFiles, NewFilesAreWrittenAndNothingElseIsLeft) {
  io::write_output_files({{path("a.json"), "A"}, {path("b.svg"), "B"}});
  EXPECT_EQ(test::slurp(path("a.json")), "A");
  EXPECT_EQ(test::slurp(path("b.svg")), "B");
  EXPECT_EQ(entries(dir_), (std::set<std::string>{"a.json", "b.svg"}));
}

TEST_F(OutputFiles, ARegularFileIsReplacedWithItsPermissions) {
  put(path("a.json"), "old");
  ::chmod(path("a.json").c_str(), 0640);
  io::write_output_files({{path("a.json"), "new"}});
  EXPECT_EQ(test::slurp(path("a.json")), "new");
  struct stat st {};
  ASSERT_EQ(::stat(path("a.json").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);
  EXPECT_EQ(entries(dir_), (std::set<std::string>{"a.json"}));
}

TEST_F(OutputFiles, ASymlinkIsFollowedAndStaysALink) {
  put(path("target.json"), "old");
  fs::create_symlink("target.json", path("link.json"));
  io::write_output_files({{path("link.json"), "new"}});
  EXPECT_TRUE(fs::is_symlink(path("link.json")));
  EXPECT_EQ(test::slurp(path("target.json")), "new");
}

TEST_F(OutputFiles, ADanglingSymlinkCreatesItsTarget) {
  fs::create_directories(dir_ / "sub");
  fs::create_symlink("sub/made.json", path("link.json"));
  io::write_output_files({{path("link.json"), "new"}});
  EXPECT_TRUE(fs::is_symlink(path("link.json")));
  EXPECT_EQ(test::slurp(path("sub/made.json")), "new");
}

TEST_F(OutputFiles, AFifoIsWrittenThroughAndStaysAFifo) {
  ASSERT_EQ(::mkfifo(path("f").c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = test::slurp(path("f")); });
  io::write_output_files({{path("f"), "through the pipe"}, {path("a.json"), "A"}});
  reader.join();
  EXPECT_EQ(received, "through the pipe");
  EXPECT_TRUE(is_fifo(path("f")));
  EXPECT_EQ(test::slurp(path("a.json")), "A");
}

TEST_F(OutputFiles, ADirectoryIsRefusedBeforeAnythingIsWritten) {
  fs::create_directories(dir_ / "x.svg");
  EXPECT_EQ(kind_of_failure({{path("out.json"), "A"}, {path("x.svg"), "B"}}), ErrorKind::Io);
  EXPECT_EQ(entries(dir_), (std::set<std::string>{"x.svg"}));
}

TEST_F(OutputFiles, TwoOutputsNamingOneFileAreRefused) {
  EXPECT_EQ(kind_of_failure({{path("same.json"), "A"}, {path("same.json"), "B"}}), ErrorKind::Usage);
  EXPECT_EQ(kind_of_failure({{path("same.json"), "A"}, {path("./same.json"), "B"}}), ErrorKind::Usage);
  put(path("t.json"), "old");
  fs::create_symlink("t.json", path("l.json"));
  fs::create_hard_link(path("t.json"), path("h.json"));
  EXPECT_EQ(kind_of_failure({{path("t.json"), "A"}, {path("l.json"), "B"}}), ErrorKind::Usage);
  EXPECT_EQ(kind_of_failure({{path("t.json"), "A"}, {path("h.json"), "B"}}), ErrorKind::Usage);
  EXPECT_EQ(test::slurp(path("t.json")), "old");
  EXPECT_EQ(entries(dir_), (std::set<std::string>{"t.json", "l.json", "h.json"}));
}

TEST_F(OutputFiles, AFailureAfterTheRenamesRollsEveryOutputBack) {
  // The write-through comes last; its reader goes away, so the write fails
  // (EPIPE) after the two other files were moved into place.
  put(path("old.json"), "old content");
  ASSERT_EQ(::mkfifo(path("f").c_str(), 0600), 0);
  const auto previous = std::signal(SIGPIPE, SIG_IGN);
  std::thread reader([&] {
    const int fd = ::open(path("f").c_str(), O_RDONLY);
    ::close(fd);
  });
  const std::string big(1 << 20, 'x');  // larger than a pipe's buffer
  EXPECT_EQ(kind_of_failure({{path("new.json"), "A"}, {path("old.json"), "B"}, {path("f"), big}}), ErrorKind::Io);
  reader.join();
  std::signal(SIGPIPE, previous);
  EXPECT_FALSE(fs::exists(path("new.json")));
  EXPECT_EQ(test::slurp(path("old.json")), "old content");
  EXPECT_TRUE(is_fifo(path("f")));
  EXPECT_EQ(entries(dir_), (std::set<std::string>{"old.json", "f"}));
}

TEST_F(OutputFiles, MissingParentsAreCreatedAndRemovedAgainOnFailure) {
  io::write_output_files({{path("a/b/c.json"), "C"}});
  EXPECT_EQ(test::slurp(path("a/b/c.json")), "C");
  fs::create_directories(dir_ / "blocked.png");
  EXPECT_EQ(kind_of_failure({{path("x/y/z.json"), "Z"}, {path("blocked.png"), "P"}}), ErrorKind::Io);
  EXPECT_FALSE(fs::exists(path("x")));
  put(path("file"), "");
  EXPECT_EQ(kind_of_failure({{path("file/sub.json"), "S"}}), ErrorKind::Io);  // a parent that is a file
}

TEST_F(OutputFiles, SocketsAndBlockDevicesAreRefused) {
  // A socket: bind one in the directory.
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  const std::string sock = path("s");
  ASSERT_LT(sock.size(), sizeof addr.sun_path);
  std::copy(sock.begin(), sock.end(), addr.sun_path);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  EXPECT_EQ(kind_of_failure({{sock, "S"}}), ErrorKind::Io);
  ::close(fd);
}

// ---- outputs staged one at a time (StagedOutputFiles) ----------------------

TEST_F(OutputFiles, StagedOutputsAppearOnlyAtTheCommit) {
  put(path("old.json"), "old");
  io::StagedOutputFiles staged;
  staged.add({path("frames/a/frame-0000.png"), "0"});
  staged.add({path("frames/a/frame-0001.png"), "1"});
  staged.add({path("old.json"), "new"});
  EXPECT_FALSE(fs::exists(path("frames/a/frame-0000.png")));  // only its temporary so far
  EXPECT_EQ(test::slurp(path("old.json")), "old");
  staged.commit();
  EXPECT_EQ(test::slurp(path("frames/a/frame-0000.png")), "0");
  EXPECT_EQ(test::slurp(path("frames/a/frame-0001.png")), "1");
  EXPECT_EQ(test::slurp(path("old.json")), "new");
  EXPECT_EQ(entries(dir_), (std::set<std::string>{"frames", "old.json"}));
  EXPECT_EQ(entries(dir_ / "frames" / "a"), (std::set<std::string>{"frame-0000.png", "frame-0001.png"}));
}

TEST_F(OutputFiles, StagedOutputsWithoutACommitLeaveNothing) {
  put(path("old.json"), "old");
  {
    io::StagedOutputFiles staged;
    staged.add({path("frames/a/frame-0000.png"), "0"});
    staged.add({path("old.json"), "new"});
  }  // the command failed before its commit
  EXPECT_EQ(test::slurp(path("old.json")), "old");
  EXPECT_EQ(entries(dir_), (std::set<std::string>{"old.json"}));
}

TEST_F(OutputFiles, AStagedOutputIsCheckedAgainstTheOnesBeforeIt) {
  put(path("t.json"), "old");
  fs::create_hard_link(path("t.json"), path("h.json"));
  fs::create_directories(dir_ / "d.png");
  io::StagedOutputFiles staged;
  staged.add({path("n.json"), "A"});
  staged.add({path("t.json"), "B"});
  auto kind_of_add = [&](const std::string& p) {
    try {
      staged.add({p, "X"});
    } catch (const Error& e) {
      return e.kind();
    }
    ADD_FAILURE() << p << ": no error";
    return ErrorKind::Io;
  };
  EXPECT_EQ(kind_of_add(path("./n.json")), ErrorKind::Usage);
  EXPECT_EQ(kind_of_add(path("h.json")), ErrorKind::Usage);
  EXPECT_EQ(kind_of_add(path("d.png")), ErrorKind::Io);
  staged.commit();  // the outputs staged before the refusals are still whole
  EXPECT_EQ(test::slurp(path("n.json")), "A");
  EXPECT_EQ(test::slurp(path("t.json")), "B");
  EXPECT_EQ(entries(dir_), (std::set<std::string>{"n.json", "t.json", "h.json", "d.png"}));
}

}  // namespace
}  // namespace nearcap
