// OFF, parsed by nearcap (OpenMesh 9 rejects '#' comment lines and misreads face colours).
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

// OFF's words: '#' starts a comment.
class OffTokens : public mesh_reading::TextTokens {
 public:
  OffTokens(const std::string& text, const std::string& source) : TextTokens(text, source, '#') {}
  long long need_integer(const char* what) {
    const std::string t = need(what);
    std::size_t used = 0;
    long long v = 0;
    try {
      v = std::stoll(t, &used);
    } catch (const std::exception&) {
      error(std::string("expected ") + what + ", found '" + mesh_reading::printable(t) + "'");
    }
    if (used != t.size()) error(std::string("expected ") + what + ", found '" + mesh_reading::printable(t) + "'");
    return v;
  }
  double need_double(const char* what) {
    const std::string t = need(what);
    // strtod accepts "nan" and "inf": those are reported as NonFinite later, by vertex.
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size())
      error(std::string("expected ") + what + ", found '" + mesh_reading::printable(t) + "'");
    return v;
  }
};

// What may follow a face's vertex indices on its line: a colour, one number
// (a colour-map index) or three or four (RGB or RGBA).  Anything else, such as
// a second face on the same line, is refused rather than dropped; a face
// written as four numbers on its predecessor's line still reads as a colour.
void check_face_colour(const OffTokens& tokens, long long face, const std::vector<std::string>& words) {
  const std::size_t n = words.size();
  const bool colour_size = n == 0 || n == 1 || n == 3 || n == 4;
  for (const std::string& w : words) {
    char* end = nullptr;
    std::strtod(w.c_str(), &end);
    if (end != w.c_str() + w.size())
      tokens.error("face " + std::to_string(face) + ": expected a colour value or the end of the line after its " +
                   "vertex indices, found '" + mesh_reading::printable(w) + "'");
  }
  if (!colour_size)
    tokens.error("face " + std::to_string(face) + " has " + std::to_string(n) +
                 " values after its vertex indices; a face colour is 1, 3 or 4 numbers (two faces on one line?)");
}

}  // namespace

TriangleMesh parse_off(const std::string& text, const std::string& source) {
  TriangleMesh mesh;
  mesh.source = source;
  OffTokens tokens(text, source);
  std::string header = tokens.need("the OFF header");
  if (header != "OFF")
    tokens.error("the file does not start with the keyword OFF (found '" + mesh_reading::printable(header) + "')");
  const long long nv = tokens.need_integer("the vertex count");
  const long long nf = tokens.need_integer("the face count");
  tokens.need_integer("the edge count");
  constexpr long long kMaxElements = 100'000'000;
  if (nv < 0 || nf < 0 || nv > kMaxElements || nf > kMaxElements)
    tokens.error("vertex or face count out of range (" + std::to_string(nv) + ", " + std::to_string(nf) + ")");
  mesh.positions.reserve(static_cast<std::size_t>(std::min<long long>(nv, 1 << 20)));
  for (long long i = 0; i < nv; ++i) {
    const double x = tokens.need_double("a vertex coordinate");
    const double y = tokens.need_double("a vertex coordinate");
    const double z = tokens.need_double("a vertex coordinate");
    mesh.positions.push_back({x, y, z});
  }
  mesh.triangles.reserve(static_cast<std::size_t>(std::min<long long>(nf, 1 << 20)));
  for (long long f = 0; f < nf; ++f) {
    const long long n = tokens.need_integer("a face's vertex count");
    if (n != 3)
      fail(ErrorKind::Mesh, source,
           "line " + std::to_string(tokens.line()) + ": face " + std::to_string(f) + " has " + std::to_string(n) +
               " vertices; nearcap reads triangle meshes only");
    std::array<VertexIndex, 3> t{};
    for (int k = 0; k < 3; ++k) {
      const long long idx = tokens.need_integer("a vertex index");
      if (idx < 0 || idx >= nv)
        tokens.error("face " + std::to_string(f) + " refers to vertex " + std::to_string(idx) + " but the file has " +
                     std::to_string(nv) + " vertices");
      t[k] = static_cast<VertexIndex>(idx);
    }
    check_face_colour(tokens, f, tokens.rest_of_line());
    mesh.triangles.push_back(t);
  }
  // Only whitespace and comments may follow the declared faces: an extra face
  // or trailing garbage is refused, not dropped.
  std::string extra;
  if (tokens.next(extra))
    tokens.error("found '" + mesh_reading::printable(extra) + "' after the last of the " + std::to_string(nf) +
                 (nf == 1 ? " face" : " faces") +
                 " the header declares (only whitespace and comments may follow; more faces than declared?)");
  check_read_mesh(mesh);
  return mesh;
}

}  // namespace nearcap
