// STL (ascii and binary), parsed by nearcap.
//
// STL lists three positions per facet and no topology; equal positions become
// one vertex, in order of first appearance, so a closed STL solid is a valid
// occluder.  Coordinates are float32 by the format's definition (ascii values
// are read as the nearest float32).  The stored facet normals are ignored: the
// orientation is the vertex order, as every STL consumer takes it.
//
// Binary or ascii: a file whose size is exactly 84 + 50 n bytes, n being the
// facet count stored at byte 80, is binary (binary files may start with
// "solid" too); otherwise a file starting with "solid" is ascii; anything else
// is reported as a binary file of the wrong size.
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <tuple>

#include "mesh_reading.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {
namespace {

using mesh_reading::fail;

// Shares vertices by exact position.
class VertexWelder {
 public:
  explicit VertexWelder(TriangleMesh& mesh) : mesh_(mesh) {}
  // `where` names the facet corner in messages.
  VertexIndex index_of(float x, float y, float z, const std::string& where) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      fail(ErrorKind::NonFinite, mesh_.source,
           where + " has a non-finite coordinate (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
               std::to_string(z) + ")");
    // +0 and -0 are one position (std::map compares them equal).
    const auto [it, inserted] =
        index_.try_emplace(std::make_tuple(x, y, z), static_cast<VertexIndex>(mesh_.positions.size()));
    if (inserted) mesh_.positions.push_back({x, y, z});
    return it->second;
  }

 private:
  TriangleMesh& mesh_;
  std::map<std::tuple<float, float, float>, VertexIndex> index_;
};

std::uint32_t read_u32_le(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

float read_f32_le(const unsigned char* p) {
  const std::uint32_t bits = read_u32_le(p);
  float f = 0;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

void parse_binary(const std::string& bytes, TriangleMesh& mesh) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::uint64_t facets = read_u32_le(data + 80);
  VertexWelder welder(mesh);
  mesh.triangles.reserve(static_cast<std::size_t>(facets));
  for (std::uint64_t f = 0; f < facets; ++f) {
    const unsigned char* facet = data + 84 + 50 * f + 12;  // past the normal
    std::array<VertexIndex, 3> t{};
    for (int k = 0; k < 3; ++k) {
      const unsigned char* v = facet + 12 * k;
      t[static_cast<std::size_t>(k)] = welder.index_of(read_f32_le(v), read_f32_le(v + 4), read_f32_le(v + 8),
                                                       "facet " + std::to_string(f) + " vertex " + std::to_string(k));
    }
    mesh.triangles.push_back(t);
  }
}

class AsciiStlTokens : public mesh_reading::TextTokens {
 public:
  using TextTokens::TextTokens;
  void expect(const char* keyword) {
    const std::string t = need(std::string("'") + keyword + "'");
    if (t != keyword) error(std::string("expected '") + keyword + "', found '" + mesh_reading::printable(t) + "'");
  }
  float need_float(const std::string& what) {
    const std::string t = need(what);
    char* end = nullptr;
    const float v = std::strtof(t.c_str(), &end);  // the float32 nearest the decimal
    if (end != t.c_str() + t.size()) error("expected " + what + ", found '" + mesh_reading::printable(t) + "'");
    return v;
  }
};

// One or more solids, each "solid [name]" ... "endsolid [name]", their facets
// all read into one mesh; after the last, only whitespace (and padding).
void parse_ascii(const std::string& text, TriangleMesh& mesh) {
  AsciiStlTokens tokens(text, mesh.source);
  tokens.expect("solid");
  tokens.skip_rest_of_line();  // the solid's name
  VertexWelder welder(mesh);
  for (;;) {
    const std::size_t f = mesh.triangles.size();  // facets count through every solid of the file
    const std::string t = tokens.need("'facet' or 'endsolid'");
    if (t == "endsolid") {
      tokens.skip_rest_of_line();  // the solid's name
      // NUL bytes or a DOS end-of-file mark (0x1A), which some writers pad
      // their files with, end the text as its end does.
      const auto padding = [](const std::string& w) {
        return w.find_first_not_of(std::string("\0\x1a", 2)) == std::string::npos;
      };
      std::string next;
      bool more = tokens.next(next);
      while (more && padding(next)) more = tokens.next(next);
      if (!more) return;
      if (next != "solid")
        tokens.error("found '" + mesh_reading::printable(next) +
                     "' after 'endsolid' (only whitespace or another 'solid' may follow)");
      tokens.skip_rest_of_line();  // the next solid's name
      continue;
    }
    if (t != "facet") tokens.error("expected 'facet' or 'endsolid', found '" + mesh_reading::printable(t) + "'");
    tokens.expect("normal");
    for (int k = 0; k < 3; ++k) (void)tokens.need_float("a normal component");
    tokens.expect("outer");
    tokens.expect("loop");
    std::array<VertexIndex, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const std::string v = tokens.need("'vertex'");
      if (v == "endloop")
        tokens.error("facet " + std::to_string(f) + " has " + std::to_string(k) +
                     " vertices; nearcap reads triangles only");
      if (v != "vertex") tokens.error("expected 'vertex', found '" + mesh_reading::printable(v) + "'");
      const float x = tokens.need_float("a vertex coordinate");
      const float y = tokens.need_float("a vertex coordinate");
      const float z = tokens.need_float("a vertex coordinate");
      tri[static_cast<std::size_t>(k)] =
          welder.index_of(x, y, z, "facet " + std::to_string(f) + " vertex " + std::to_string(k));
    }
    const std::string end = tokens.need("'endloop'");
    if (end == "vertex")
      fail(ErrorKind::Mesh, mesh.source,
           "facet " + std::to_string(f) + " has more than 3 vertices; nearcap reads triangles only");
    if (end != "endloop") tokens.error("expected 'endloop', found '" + mesh_reading::printable(end) + "'");
    tokens.expect("endfacet");
    mesh.triangles.push_back(tri);
  }
}

}  // namespace

TriangleMesh parse_stl(const std::string& bytes, const std::string& source) {
  TriangleMesh mesh;
  mesh.source = source;
  const bool sized_as_binary =
      bytes.size() >= 84 &&
      bytes.size() ==
          84 + 50 * static_cast<std::uint64_t>(read_u32_le(reinterpret_cast<const unsigned char*>(bytes.data()) + 80));
  std::size_t first = 0;
  while (first < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[first]))) ++first;
  if (sized_as_binary) {
    parse_binary(bytes, mesh);
  } else if (bytes.compare(first, 5, "solid") == 0) {
    parse_ascii(bytes, mesh);
  } else if (bytes.size() < 84) {
    fail(ErrorKind::Parse, source,
         "a binary STL file holds at least 84 bytes, this one " + std::to_string(bytes.size()) +
             " (truncated, or not an STL file)");
  } else {
    const std::uint32_t facets = read_u32_le(reinterpret_cast<const unsigned char*>(bytes.data()) + 80);
    fail(ErrorKind::Parse, source,
         "binary STL header says " + std::to_string(facets) + " facets (" +
             std::to_string(84 + 50 * static_cast<std::uint64_t>(facets)) + " bytes) but the file holds " +
             std::to_string(bytes.size()) + " bytes (truncated, or not an STL file)");
  }
  mesh_reading::check_read_mesh(mesh);
  return mesh;
}

}  // namespace nearcap
