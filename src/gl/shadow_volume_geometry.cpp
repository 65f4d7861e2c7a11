// Shadow-volume vertex arrays (see shadow_volume_geometry.hpp).
#include "nearcap/gl/shadow_volume_geometry.hpp"

namespace nearcap::gl {
namespace {

ShadowVertex at(const Vec3d& p, float w) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), w};
}

void add_quad(std::vector<ShadowVertex>& out, const ShadowVertex& v0, const ShadowVertex& v1, const ShadowVertex& v2,
              const ShadowVertex& v3) {
  out.insert(out.end(), {v0, v1, v2, v0, v2, v3});
}

}  // namespace

ShadowVolumeGeometry shadow_volume_geometry(const TriangleMesh& mesh, const EngineSilhouette& silhouette) {
  ShadowVolumeGeometry g;
  for (std::size_t k = 0; k < silhouette.edges.size(); ++k) {
    const Vec3d& a = mesh.positions[silhouette.edges[k].a];
    const Vec3d& d = mesh.positions[silhouette.edges[k].d];
    add_quad(g.sides, at(d, 1), at(a, 1), at(a, 0), at(d, 0));
    const VertexIndex ia = silhouette.edges[k].a, id = silhouette.edges[k].d;
    g.sides_vertex.insert(g.sides_vertex.end(), {id, ia, ia, id, ia, id});
    if (silhouette.cases[k] == QuadCase::C1) add_quad(g.corrective, at(a, 2), at(a, 1), at(d, 1), at(d, 2));
    if (silhouette.cases[k] == QuadCase::C2) add_quad(g.corrective, at(a, 0), at(a, 4), at(d, 4), at(d, 0));
  }
  for (FaceIndex f = 0; f < mesh.triangle_count(); ++f) {
    const bool front = silhouette.facing[f] == Facing::Front;
    auto& cap = front ? g.light_cap : g.dark_cap;
    auto& index = front ? g.light_cap_vertex : g.dark_cap_vertex;
    for (VertexIndex v : mesh.triangles[f]) {
      cap.push_back(at(mesh.positions[v], front ? 1.0f : 0.0f));
      index.push_back(v);
    }
  }
  return g;
}

}  // namespace nearcap::gl
