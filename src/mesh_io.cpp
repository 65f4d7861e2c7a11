// Mesh reading: OFF by hand, OBJ/PLY/STL through OpenMesh into a raw importer.
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "nearcap/error.hpp"
#include "nearcap/mesh.hpp"

namespace nearcap {
namespace {

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos) return {};
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

[[noreturn]] void fail(ErrorKind kind, const std::string& source, const std::string& what) {
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

// ---- OFF ------------------------------------------------------------------

// Tokenizer that skips '#' comments to end of line and tracks line numbers.
class OffTokens {
 public:
  OffTokens(const std::string& text, const std::string& source) : text_(text), source_(source) {}

  bool next(std::string& token) {
    for (;;) {
      while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
        if (text_[pos_] == '\n') ++line_;
        ++pos_;
      }
      if (pos_ >= text_.size()) return false;
      if (text_[pos_] == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
        continue;
      }
      break;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) && text_[pos_] != '#') ++pos_;
    token = text_.substr(start, pos_ - start);
    return true;
  }
  // Skips to the end of the current line (face colours and other trailing values).
  void skip_rest_of_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  int line() const { return line_; }
  [[noreturn]] void error(const std::string& what) const {
    fail(ErrorKind::Parse, source_, "line " + std::to_string(line_) + ": " + what);
  }
  std::string need(const char* what) {
    std::string t;
    if (!next(t)) error(std::string("unexpected end of file, expected ") + what + " (truncated file?)");
    return t;
  }
  long long need_integer(const char* what) {
    const std::string t = need(what);
    std::size_t used = 0;
    long long v = 0;
    try {
      v = std::stoll(t, &used);
    } catch (const std::exception&) {
      error(std::string("expected ") + what + ", found '" + t + "'");
    }
    if (used != t.size()) error(std::string("expected ") + what + ", found '" + t + "'");
    return v;
  }
  double need_double(const char* what) {
    const std::string t = need(what);
    // strtod accepts "nan" and "inf": those are reported as NonFinite later, by vertex.
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size()) error(std::string("expected ") + what + ", found '" + t + "'");
    return v;
  }

 private:
  const std::string& text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

}  // namespace

TriangleMesh parse_off(const std::string& text, const std::string& source) {
  TriangleMesh mesh;
  mesh.source = source;
  OffTokens tokens(text, source);
  std::string header = tokens.need("the OFF header");
  if (header != "OFF") tokens.error("the file does not start with the keyword OFF (found '" + header + "')");
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
    tokens.skip_rest_of_line();  // optional colour
    mesh.triangles.push_back(t);
  }
  check_read_mesh(mesh);
  return mesh;
}

namespace {

// ---- OpenMesh raw importer -----------------------------------------------

// Records vertices and faces exactly as the reader reports them; builds no
// topology, so no face is dropped or reordered.
class RawImporter final : public OpenMesh::IO::BaseImporter {
 public:
  explicit RawImporter(TriangleMesh& mesh) : mesh_(mesh) {}
  std::vector<std::size_t> polygon_sizes;  // faces with != 3 vertices: their index and size, reported later
  std::size_t first_polygon = static_cast<std::size_t>(-1);
  std::size_t first_polygon_size = 0;

  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override {
    return add_vertex(OpenMesh::Vec3d(p[0], p[1], p[2]));
  }
  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d& p) override {
    mesh_.positions.push_back({p[0], p[1], p[2]});
    return OpenMesh::VertexHandle(static_cast<int>(mesh_.positions.size() - 1));
  }
  OpenMesh::VertexHandle add_vertex() override { return add_vertex(OpenMesh::Vec3d(0, 0, 0)); }
  OpenMesh::HalfedgeHandle add_edge(OpenMesh::VertexHandle, OpenMesh::VertexHandle) override {
    return OpenMesh::HalfedgeHandle();
  }
  OpenMesh::FaceHandle add_face(const VHandles& v) override {
    const std::size_t index = faces_++;
    if (v.size() != 3) {
      if (first_polygon == static_cast<std::size_t>(-1)) {
        first_polygon = index;
        first_polygon_size = v.size();
      }
      return OpenMesh::FaceHandle(static_cast<int>(index));
    }
    std::array<VertexIndex, 3> t{};
    for (int k = 0; k < 3; ++k) t[k] = static_cast<VertexIndex>(v[k].idx());
    mesh_.triangles.push_back(t);
    return OpenMesh::FaceHandle(static_cast<int>(index));
  }
  OpenMesh::FaceHandle add_face(OpenMesh::HalfedgeHandle) override { return OpenMesh::FaceHandle(); }
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle, const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(OpenMesh::FaceHandle, int) override {}
  void set_point(OpenMesh::VertexHandle vh, const OpenMesh::Vec3f& p) override {
    if (vh.idx() >= 0 && static_cast<std::size_t>(vh.idx()) < mesh_.positions.size())
      mesh_.positions[vh.idx()] = {p[0], p[1], p[2]};
  }
  void set_halfedge(OpenMesh::VertexHandle, OpenMesh::HalfedgeHandle) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3d&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4f&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec2f&) override {}
  void set_status(OpenMesh::VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(OpenMesh::HalfedgeHandle, OpenMesh::HalfedgeHandle) override {}
  void set_face(OpenMesh::HalfedgeHandle, OpenMesh::FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec2f&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec3f&) override {}
  void set_status(OpenMesh::HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4f&) override {}
  void set_status(OpenMesh::EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3d&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4f&) override {}
  void set_status(OpenMesh::FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  size_t n_vertices() const override { return mesh_.positions.size(); }
  size_t n_faces() const override { return faces_; }
  size_t n_edges() const override { return 0; }

 private:
  TriangleMesh& mesh_;
  std::size_t faces_ = 0;
};

// Reads `in` (a file's bytes) with OpenMesh's reader for extension `ext`.
TriangleMesh read_with_openmesh(std::istream& in, const std::string& ext, const std::string& path) {
  TriangleMesh mesh;
  mesh.source = path;
  RawImporter importer(mesh);
  OpenMesh::IO::Options options;
  if (ext == "stl") {
    // OpenMesh's stream reader needs to be told binary vs ascii: ascii STL
    // starts with "solid" followed by a facet; anything else is binary.
    std::string head(512, '\0');
    in.read(&head[0], static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    in.clear();
    in.seekg(0);
    const bool ascii = head.rfind("solid", 0) == 0 && head.find("facet") != std::string::npos;
    if (!ascii) options += OpenMesh::IO::Options::Binary;
  }
  if (ext == "ply") {
    std::string head(256, '\0');
    in.read(&head[0], static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    in.clear();
    in.seekg(0);
    if (head.find("format binary") != std::string::npos) options += OpenMesh::IO::Options::Binary;
  }
  // OpenMesh prints its complaints to its own log streams; silence them, we
  // report faults ourselves.
  omerr().disable();
  omlog().disable();
  bool ok = false;
  try {
    ok = OpenMesh::IO::IOManager().read(in, "." + ext, importer, options);
  } catch (const std::exception& e) {
    omerr().enable();
    omlog().enable();
    fail(ErrorKind::Parse, path, std::string("OpenMesh failed to read the file: ") + e.what());
  }
  omerr().enable();
  omlog().enable();
  if (!ok) fail(ErrorKind::Parse, path, "OpenMesh could not parse the file (malformed or truncated)");
  if (importer.first_polygon != static_cast<std::size_t>(-1))
    fail(ErrorKind::Mesh, path,
         "face " + std::to_string(importer.first_polygon) + " has " + std::to_string(importer.first_polygon_size) +
             " vertices; nearcap reads triangle meshes only");
  check_read_mesh(mesh);
  return mesh;
}

}  // namespace

TriangleMesh read_mesh(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(ErrorKind::Io, path, "cannot open the mesh file (missing or unreadable)");
  const std::string ext = lower_extension(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_mesh(buffer.str(), ext, path);
}

TriangleMesh parse_mesh(const std::string& bytes, const std::string& format, const std::string& source) {
  if (format == "off") return parse_off(bytes, source);
  if (format == "obj" || format == "ply" || format == "stl") {
    std::istringstream in(bytes, std::ios::binary);
    return read_with_openmesh(in, format, source);
  }
  fail(ErrorKind::Parse, source, "unknown mesh format '." + format + "' (nearcap reads .off, .obj, .ply and .stl)");
}

}  // namespace nearcap
