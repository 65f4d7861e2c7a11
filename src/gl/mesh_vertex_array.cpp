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

std::vector<ShadowVertex> corners(const MeshVertexArray& a) {
  std::vector<ShadowVertex> out;
  out.reserve(3 * a.mesh->triangles.size());
  for (const auto& t : a.mesh->triangles)
    for (VertexIndex v : t) out.push_back(a.vertices[v]);
  return out;
}

std::vector<Vec4f> run_vertex_program(VertexProgram p, const ShadowUniforms& u, const MeshVertexArray& a) {
  const std::vector<Vec4f> per_vertex = run_vertex_program(p, u, a.vertices);
  std::vector<Vec4f> out;
  out.reserve(3 * a.mesh->triangles.size());
  for (const auto& t : a.mesh->triangles)
    for (VertexIndex v : t) out.push_back(per_vertex[v]);
  return out;
}

}  // namespace nearcap::gl
