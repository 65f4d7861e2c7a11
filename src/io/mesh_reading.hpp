// Private to the mesh readers: the error helper and the checks every format
// shares once vertices and faces are in memory.
#pragma once

#include <string>

#include "nearcap/error.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap::mesh_reading {

// Throws Error(kind, "<source>: <what>").
[[noreturn]] void fail(ErrorKind kind, const std::string& source, const std::string& what);

// Every coordinate finite, at least one face, indices in range, three distinct
// vertices per face; throws naming the vertex or face.
void check_read_mesh(const TriangleMesh& mesh);

// "line N: what" errors of the line-oriented readers.
[[noreturn]] inline void fail_at_line(ErrorKind kind, const std::string& source, int line, const std::string& what) {
  fail(kind, source, "line " + std::to_string(line) + ": " + what);
}

}  // namespace nearcap::mesh_reading
