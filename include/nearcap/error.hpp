// nearcap/error.hpp — the one error type raised at nearcap's boundaries.
//
// Everything that reads outside data (scene files, mesh files, command-line
// arguments) reports faults as nearcap::Error: a kind, for programs, and a
// message, for people, that names the file, the element and the fault
// ("data/x.off: edge (3, 7) is used by 3 faces (non-manifold)").  Internal
// invariants are not Errors; they are checks (NEARCAP_CHECK) that print their
// operands and abort, because reaching one is a bug in nearcap, not in the input.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace nearcap {

enum class ErrorKind {
  Io,           // a file is missing, unreadable or unwritable
  Parse,        // a file is not syntactically what its format says (JSON, OFF, ...)
  Schema,       // a scene file has unknown keys, wrong types or missing fields
  NonFinite,    // NaN or infinity where a finite number is required
  Mesh,         // an occluder is not a closed, consistently outward-oriented 2-manifold
  Camera,       // degenerate frustum, non-invertible view, zero-pixel viewport
  Light,        // a light inside or on an occluder, or otherwise unusable
  Range,        // finite, but too large for the float32 pipeline to represent the scene
  Degenerate,   // the requested construction is undefined for this configuration
  Usage,        // a bad command-line argument (light index out of range, ...)
  Gl,           // no OpenGL context could be made, or the GL reported an error
  Resource,     // over a documented size or memory limit, or out of memory
  Unavailable,  // this build lacks what was asked for (nearcap built without Embree)
};

// Stable lower-case name of a kind ("mesh", "camera", ...), used in messages and
// in the bad-input catalogue.
std::string_view to_string(ErrorKind kind);

class Error : public std::runtime_error {
 public:
  // A NUL byte of the message (from a file's bytes or a name in it) is
  // written as \0: what() is a C string, and the rest would be lost.
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(without_nul(message)), kind_(kind) {}
  ErrorKind kind() const { return kind_; }

 private:
  static std::string without_nul(const std::string& message) {
    if (message.find('\0') == std::string::npos) return message;
    std::string out;
    for (char c : message) out += c == '\0' ? std::string("\\0") : std::string(1, c);
    return out;
  }
  ErrorKind kind_;
};

}  // namespace nearcap
