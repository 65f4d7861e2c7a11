// nearcap/io/input_files.hpp — reading a scene or mesh file with bounds.
//
// Outside data is read only from regular files (a directory, a FIFO, a device
// such as /dev/zero — also through a symlink — is named and refused, never
// read: a FIFO would block for ever, /dev/zero would grow without end), and
// only up to a size limit: 1 GiB by default, overridden by the environment
// variable NEARCAP_MAX_INPUT_MB (megabytes, a positive integer).  A file over
// the limit is a Resource error that names the file, its size and the limit.
#pragma once

#include <cstdint>
#include <string>

namespace nearcap::io {

// The limit in bytes (NEARCAP_MAX_INPUT_MB, or 1 GiB).  A malformed variable
// is a Usage error naming it.
std::uint64_t max_input_bytes();

// The whole file's bytes.  `what` names the kind in messages ("scene file",
// "mesh file").  Errors: Io (missing, unreadable, not a regular file),
// Resource (over the limit).
std::string read_input_file(const std::string& path, const std::string& what);

// The checks read_input_file makes before it reads, for a reader that streams
// the file line by line (sweep CSVs): the path names a regular file (also
// through a symlink) within the limit.  Returns its size in bytes; the reader
// applies max_input_bytes() to what it reads (the file may grow meanwhile).
// Errors as read_input_file's.
std::uint64_t check_input_file(const std::string& path, const std::string& what);

}  // namespace nearcap::io
