// Wavefront OBJ, parsed by nearcap.
#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <iterator>
#include <string>
#include <vector>

#include "mesh_reading.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {
using mesh_reading::check_read_mesh;
using mesh_reading::fail;

namespace {

// nearcap reads OBJ itself: OpenMesh's OBJ reader asserts (aborts the process)
// on malformed face lines such as "f\t\t/A/" (found by fuzz_obj, kept in
// fuzz/regressions/obj/), and it hands coordinates over as float32.

// The statements of the OBJ format that carry no polygonal geometry; they are
// skipped.  Free-form geometry (curves, surfaces) is refused rather than
// silently dropped.
bool is_ignored_obj_keyword(const std::string& k) {
  static const char* const kIgnored[] = {"vt",       "vn",       "g",          "o",         "s",      "mg",
                                         "usemtl",   "mtllib",   "l",          "p",         "lod",    "bevel",
                                         "c_interp", "d_interp", "shadow_obj", "trace_obj", "maplib", "usemap"};
  return std::find_if(std::begin(kIgnored), std::end(kIgnored), [&](const char* i) { return k == i; }) !=
         std::end(kIgnored);
}

bool is_free_form_obj_keyword(const std::string& k) {
  static const char* const kFreeForm[] = {"vp",   "cstype", "deg",  "bmat", "step", "curv", "curv2", "surf", "parm",
                                          "trim", "hole",   "scrv", "sp",   "end",  "con",  "ctech", "stech"};
  return std::find_if(std::begin(kFreeForm), std::end(kFreeForm), [&](const char* i) { return k == i; }) !=
         std::end(kFreeForm);
}

}  // namespace

TriangleMesh parse_obj(const std::string& text, const std::string& source) {
  TriangleMesh mesh;
  mesh.source = source;
  std::size_t pos = 0;
  int line_number = 0;
  int statement_line = 0;  // messages name the line a statement starts on
  std::size_t face = 0;
  auto error = [&](ErrorKind kind, const std::string& what) {
    fail(kind, source, "line " + std::to_string(statement_line) + ": " + what);
  };
  while (pos < text.size()) {
    // One logical line: '\' at the end of a physical line continues it.
    std::string line;
    statement_line = line_number + 1;
    for (;;) {
      std::size_t next = 0;
      const std::size_t end = mesh_reading::line_end(text, pos, next);
      ++line_number;
      std::string part = text.substr(pos, end - pos);
      pos = next;
      const std::size_t hash = part.find('#');
      if (hash != std::string::npos) part.resize(hash);
      if (!part.empty() && part.back() == '\\' && pos < text.size()) {
        part.pop_back();
        line += part + ' ';
        continue;
      }
      line += part;
      break;
    }
    const std::vector<std::string> tokens = mesh_reading::split_whitespace(line);
    if (tokens.empty()) continue;
    const std::string& keyword = tokens[0];
    if (keyword == "v") {
      // "v x y z", "v x y z w" (w must be 1: rational weights are for
      // free-form geometry) or "v x y z r g b" (vertex colours, ignored).
      if (tokens.size() < 4)
        error(ErrorKind::Parse, "a vertex needs 3 coordinates, found " + std::to_string(tokens.size() - 1));
      std::vector<double> values;
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        char* end = nullptr;
        const double v = std::strtod(tokens[k].c_str(), &end);
        if (end != tokens[k].c_str() + tokens[k].size())
          error(ErrorKind::Parse, "expected a vertex coordinate, found '" + mesh_reading::printable(tokens[k]) + "'");
        values.push_back(v);
      }
      if (values.size() == 4 && values[3] != 1.0)
        error(ErrorKind::Parse, "vertex weight w = " + tokens[4] + " (nearcap reads w = 1 only)");
      mesh.positions.push_back({values[0], values[1], values[2]});
    } else if (keyword == "f") {
      if (tokens.size() < 4)
        error(ErrorKind::Parse, "a face needs at least 3 vertices, found " + std::to_string(tokens.size() - 1));
      if (tokens.size() != 4)
        error(ErrorKind::Mesh, "face " + std::to_string(face) + " has " + std::to_string(tokens.size() - 1) +
                                   " vertices; nearcap reads triangle meshes only");
      std::array<VertexIndex, 3> t{};
      for (int k = 0; k < 3; ++k) {
        // "i", "i/t", "i//n" or "i/t/n": the position index comes first.
        const std::string& token = tokens[static_cast<std::size_t>(k) + 1];
        const std::string index_text = token.substr(0, token.find('/'));
        long long index = 0;
        std::size_t used = 0;
        try {
          index = std::stoll(index_text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (index_text.empty() || used != index_text.size())
          error(ErrorKind::Parse, "face " + std::to_string(face) + ": expected a vertex index, found '" +
                                      mesh_reading::printable(token) + "'");
        const long long defined = static_cast<long long>(mesh.positions.size());
        const long long resolved = index < 0 ? defined + index : index - 1;  // negative: relative to the end
        if (index == 0 || resolved < 0 || resolved >= defined)
          error(ErrorKind::Mesh, "face " + std::to_string(face) + " refers to vertex " + index_text + " but " +
                                     std::to_string(defined) + " vertices are defined before it");
        t[static_cast<std::size_t>(k)] = static_cast<VertexIndex>(resolved);
      }
      mesh.triangles.push_back(t);
      ++face;
    } else if (is_free_form_obj_keyword(keyword)) {
      error(ErrorKind::Mesh, "free-form geometry ('" + keyword + "') is not supported; nearcap reads triangle meshes");
    } else if (!is_ignored_obj_keyword(keyword)) {
      std::string shown = keyword.substr(0, 32);
      for (char& c : shown)
        if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
      error(ErrorKind::Parse, "unknown OBJ statement '" + shown + "' (not an OBJ file?)");
    }
  }
  check_read_mesh(mesh);
  return mesh;
}

}  // namespace nearcap
