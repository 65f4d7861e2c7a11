#include "nearcap/exact/silhouette.hpp"

#include "nearcap/check.hpp"

namespace nearcap {

std::vector<SilhouetteEdge> silhouette_edges(const TriangleMesh& mesh, const std::vector<Facing>& facing) {
  NEARCAP_CHECK(mesh.has_adjacency());
  NEARCAP_CHECK_EQ(facing.size(), mesh.triangle_count());
  std::vector<SilhouetteEdge> edges;
  for (FaceIndex f = 0; f < mesh.triangle_count(); ++f) {
    if (facing[f] != Facing::Front) continue;
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const FaceIndex g = mesh.neighbours[f][k];
      NEARCAP_CHECK(g != kNoFace);
      if (facing[g] != Facing::Front) edges.push_back({t[k], t[(k + 1) % 3], f, g});
    }
  }
  return edges;
}

}  // namespace nearcap
