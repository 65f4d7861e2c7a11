// An object's mesh as the depth pre-pass and the near-cap pass draw it (see
// mesh_vertex_array.hpp).
#include "mesh_vertex_array.hpp"

namespace nearcap::gl {

MeshVertexArray mesh_vertex_array(const TriangleMesh& mesh) {
  MeshVertexArray a;
  a.mesh = &mesh;
  a.vertices.reserve(mesh.positions.size());
  for (const Vec3d& p : mesh.positions)
    a.vertices.push_back({static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), 1.0f});
  return a;
}

namespace {

// One value per corner of `mesh`'s triangles, in order, from one per vertex.
template <class T>
std::vector<T> per_corner(const std::vector<T>& per_vertex, const TriangleMesh& mesh) {
  std::vector<T> out;
  out.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    for (VertexIndex v : t) out.push_back(per_vertex[v]);
  return out;
}

}  // namespace

std::vector<ShadowVertex> corners(const MeshVertexArray& a) { return per_corner(a.vertices, *a.mesh); }

std::vector<Vec4f> run_vertex_program(VertexProgram p, const ShadowUniforms& u, const MeshVertexArray& a) {
  return per_corner(run_vertex_program(p, u, a.vertices), *a.mesh);
}

}  // namespace nearcap::gl
