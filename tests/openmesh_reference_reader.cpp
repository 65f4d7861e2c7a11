// OpenMesh's readers into a raw importer: see openmesh_reference_reader.hpp.
#include "openmesh_reference_reader.hpp"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include <sstream>
#include <stdexcept>

namespace nearcap::test {
namespace {

// Records vertices and faces exactly as the reader reports them; builds no
// topology, so no face is dropped or reordered.
class RawImporter final : public OpenMesh::IO::BaseImporter {
 public:
  explicit RawImporter(TriangleMesh& mesh) : mesh_(mesh) {}
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

}  // namespace

TriangleMesh read_with_openmesh(const std::string& bytes, const std::string& format) {
  TriangleMesh mesh;
  mesh.source = "openmesh." + format;
  RawImporter importer(mesh);
  OpenMesh::IO::Options options;
  // OpenMesh's stream readers must be told binary or ascii.
  if (format == "stl" && !(bytes.rfind("solid", 0) == 0 && bytes.find("facet") != std::string::npos))
    options += OpenMesh::IO::Options::Binary;
  if (format == "ply" && bytes.substr(0, 256).find("format binary") != std::string::npos) {
    options += OpenMesh::IO::Options::Binary;
    if (bytes.substr(0, 256).find("binary_big_endian") != std::string::npos) options += OpenMesh::IO::Options::MSB;
  }
  std::istringstream in(bytes, std::ios::binary);
  omerr().disable();
  omlog().disable();
  const bool ok = OpenMesh::IO::IOManager().read(in, "." + format, importer, options);
  omerr().enable();
  omlog().enable();
  if (!ok) throw std::runtime_error("OpenMesh could not read the " + format + " data");
  if (importer.first_polygon != static_cast<std::size_t>(-1)) throw std::runtime_error("OpenMesh read a polygon");
  return mesh;
}

}  // namespace nearcap::test
