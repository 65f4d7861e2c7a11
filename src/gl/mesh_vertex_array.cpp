// An object's mesh as indexed draws read it (see mesh_vertex_array.hpp).
#include "mesh_vertex_array.hpp"

namespace nearcap::gl {

MeshVertexArray mesh_vertex_array(const TriangleMesh& mesh) {
  MeshVertexArray a;
  a.vertices.reserve(mesh.positions.size());
  a.directions.reserve(mesh.positions.size());
  for (const Vec3d& p : mesh.positions) {
    const float x = static_cast<float>(p.x), y = static_cast<float>(p.y), z = static_cast<float>(p.z);
    a.vertices.push_back({x, y, z, 1.0f});
    a.directions.push_back({x, y, z, 0.0f});
  }
  a.corner_vertex.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) a.corner_vertex.insert(a.corner_vertex.end(), t.begin(), t.end());
  return a;
}

std::vector<ShadowVertex> corners(const MeshVertexArray& a) { return per_corner(a.vertices, a.corner_vertex); }

}  // namespace nearcap::gl
