// Mesh reading: the format dispatch and the checks shared by every reader.
// Each format has its own reader (off_reader.cpp, obj_reader.cpp,
// ply_reader.cpp, stl_reader.cpp), all written for nearcap: OpenMesh's readers
// abort or crash on malformed input (its OBJ reader asserts on "f\t/A/", its
// PLY reader writes through a wild pointer on a property declared before any
// element; both found by the fuzzers, kept in fuzz/regressions/), and a reader
// of outside data must not.  OpenMesh stays as the tests' reference reader for
// well-formed files (tests/openmesh_reference_reader.cpp).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "mesh_reading.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/input_files.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {
namespace mesh_reading {

void fail(ErrorKind kind, const std::string& source, const std::string& what) {
  throw Error(kind, source + ": " + what);
}

// Checks that apply to every format once vertices and faces are in memory.
void check_read_mesh(const TriangleMesh& mesh) {
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3d& p = mesh.positions[i];
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(p[k])) {
        std::ostringstream s;
        s << "vertex " << i << " has a non-finite coordinate (" << p.x << ", " << p.y << ", " << p.z << ")";
        fail(ErrorKind::NonFinite, mesh.source, s.str());
      }
    }
  }
  if (mesh.triangles.empty()) fail(ErrorKind::Mesh, mesh.source, "the mesh has no faces (empty mesh)");
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      if (t[k] >= mesh.positions.size()) {
        std::ostringstream s;
        s << "face " << f << " refers to vertex " << t[k] << " but the file has " << mesh.positions.size()
          << " vertices";
        fail(ErrorKind::Mesh, mesh.source, s.str());
      }
    }
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      std::ostringstream s;
      s << "face " << f << " repeats a vertex (" << t[0] << ", " << t[1] << ", " << t[2] << ")";
      fail(ErrorKind::Mesh, mesh.source, s.str());
    }
  }
}

std::string printable(const std::string& word) {
  std::string shown = word.substr(0, 32);
  for (char& c : shown)
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  return shown;
}

std::size_t line_end(const std::string& text, std::size_t pos, std::size_t& next) {
  std::size_t end = pos;
  while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
  next = end == text.size() ? end : end + (text.compare(end, 2, "\r\n") == 0 ? 2 : 1);
  return end;
}

std::vector<std::string> split_whitespace(const std::string& line) {
  std::vector<std::string> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

bool TextTokens::next(std::string& token) {
  for (;;) {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      if (is_line_end(text_, pos_)) ++line_;
      ++pos_;
    }
    if (pos_ >= text_.size()) return false;
    if (!is_comment(text_[pos_])) break;
    skip_rest_of_line();
  }
  const std::size_t start = pos_;
  while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) && !is_comment(text_[pos_]))
    ++pos_;
  token = text_.substr(start, pos_ - start);
  return true;
}

void TextTokens::skip_rest_of_line() {
  while (pos_ < text_.size() && !is_line_end(text_, pos_)) ++pos_;
}

std::vector<std::string> TextTokens::rest_of_line() {
  std::vector<std::string> words;
  for (std::string word;;) {
    while (pos_ < text_.size() && !is_line_end(text_, pos_) && std::isspace(static_cast<unsigned char>(text_[pos_])))
      ++pos_;
    // A comment ends the line's words; next() skips it later.
    if (pos_ >= text_.size() || is_line_end(text_, pos_) || is_comment(text_[pos_])) return words;
    next(word);
    words.push_back(word);
  }
}

std::string TextTokens::need(const std::string& what) {
  std::string t;
  if (!next(t)) error("unexpected end of file, expected " + what + " (truncated file?)");
  return t;
}

}  // namespace mesh_reading

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

TriangleMesh read_mesh(const std::string& path) {
  // The format first: a name nearcap would not parse is refused before a byte is read.
  const std::string ext = lower_extension(path);
  if (ext.empty())
    mesh_reading::fail(ErrorKind::Parse, path,
                       "the mesh file name has no extension (nearcap reads .off, .obj, .ply and .stl)");
  if (ext != "off" && ext != "obj" && ext != "ply" && ext != "stl")
    mesh_reading::fail(ErrorKind::Parse, path,
                       "unknown mesh format '." + ext + "' (nearcap reads .off, .obj, .ply and .stl)");
  return parse_mesh(io::read_input_file(path, "mesh file"), ext, path);
}

TriangleMesh parse_mesh(const std::string& bytes, const std::string& format, const std::string& source) {
  if (format == "off") return parse_off(bytes, source);
  if (format == "obj") return parse_obj(bytes, source);
  if (format == "ply") return parse_ply(bytes, source);
  if (format == "stl") return parse_stl(bytes, source);
  mesh_reading::fail(ErrorKind::Parse, source,
                     "unknown mesh format '." + format + "' (nearcap reads .off, .obj, .ply and .stl)");
}

}  // namespace nearcap
