#include "nearcap/error.hpp"

namespace nearcap {

std::string_view to_string(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::Io:
      return "io";
    case ErrorKind::Parse:
      return "parse";
    case ErrorKind::Schema:
      return "schema";
    case ErrorKind::NonFinite:
      return "non-finite";
    case ErrorKind::Mesh:
      return "mesh";
    case ErrorKind::Camera:
      return "camera";
    case ErrorKind::Light:
      return "light";
    case ErrorKind::Range:
      return "range";
    case ErrorKind::Degenerate:
      return "degenerate";
    case ErrorKind::Usage:
      return "usage";
    case ErrorKind::Gl:
      return "gl";
    case ErrorKind::Resource:
      return "resource";
    case ErrorKind::Unavailable:
      return "unavailable";
  }
  return "unknown";
}

}  // namespace nearcap
