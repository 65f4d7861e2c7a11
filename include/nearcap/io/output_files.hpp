// nearcap/io/output_files.hpp — writing a command's outputs: all or nothing,
// and never over a special file.
//
// A command with several outputs (reference: three images and a summary;
// cracks: one image per method and a summary; cap: JSON and SVG) writes them
// through write_output_files, which promises:
//   - every destination is checked before any is touched: a directory, a
//     block device, a socket, two outputs naming the same file (through a
//     symlink or a hard link too) or a missing parent that cannot be created
//     is an Error naming the path, and nothing is written;
//   - a regular file or a new name is written to a temporary in the same
//     directory and renamed into place (so a reader never sees half a file);
//     a symlink is followed and its target is what gets replaced;
//   - a destination that exists and is not a regular file (a character device
//     such as /dev/null or a terminal, a FIFO, /proc/self/fd/1) is opened and
//     written through, never renamed over: as root a rename would replace the
//     device node itself;
//   - if any step fails, the files already moved into place are rolled back
//     (a replaced file gets its old content back, a new one is removed, as are
//     the directories the call created), and the Error says what failed.
//     Bytes already written through to a FIFO or a device cannot be taken back,
//     so those are written last, after every rename has succeeded.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace nearcap::io {

struct OutputFile {
  std::string path;     // as the user named it
  std::string content;  // the bytes to write
};

// Writes every file or none of them (see above).  Missing parent directories
// are created, and removed again if the call fails.
void write_output_files(const std::vector<OutputFile>& files);

// The first of those promises alone, before a command's work: every
// destination that write_output_files would refuse (a directory, a block
// device, a socket, two paths naming one file, a directory where no file can
// be made: probed with a temporary, removed at once) is an Error before the
// command's work; nothing else is created or written.
void check_output_files(const std::vector<std::string>& paths);

// The file a write to `path` lands in: symbolic links followed, a dangling one
// to the name it would create, the result weakly canonical.  Two outputs
// collide where these are equal.  Throws Error(Io) on a loop of links or a
// folder on the way that cannot be read.
std::string output_destination(const std::string& path);

// The same promises for outputs made one at a time (a camera path's frames):
// add() checks a destination against the special files and the outputs added
// before it, creates its missing parents and writes its bytes to the
// temporary beside it at once, so the caller keeps no output in memory (a
// write-through destination, a device or a FIFO, keeps its bytes until
// commit).  commit() moves every temporary into place, all or nothing as
// write_output_files does; an object destroyed without commit() (the
// command failed) removes its temporaries and the directories it created,
// and no destination is touched.  A destination is checked when it is added,
// not before the first output is written: a bad one late in a path costs
// the frames before it, and still leaves nothing behind.
class StagedOutputFiles {
 public:
  StagedOutputFiles();
  ~StagedOutputFiles();
  StagedOutputFiles(const StagedOutputFiles&) = delete;
  StagedOutputFiles& operator=(const StagedOutputFiles&) = delete;

  // Throws Error(Io) or Error(Usage) as write_output_files does for this
  // file; the outputs added before it stay staged.
  void add(const OutputFile& file);
  // Throws as write_output_files' renames do, every output rolled back.
  // Once committed, add() and commit() throw Error(Usage).
  void commit();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace nearcap::io
