// Silhouette edges (exact/silhouette.hpp): an edge of a light-front-facing
// triangle is a silhouette edge where its neighbour is not front-facing,
// back-facing or edge-on (the light in its plane) alike, and it is reported
// in the front triangle's winding.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "nearcap/exact/silhouette.hpp"
#include "nearcap/io/mesh_file.hpp"

namespace nearcap {
namespace {

TEST(Silhouette, AFrontTrianglesEdgeIsOneWhereItsNeighbourIsBackFacingOrEdgeOn) {
  TriangleMesh box = read_mesh(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/box.off");
  build_adjacency(box);
  ASSERT_TRUE(box.has_adjacency());
  const FaceIndex front = 0;
  // Triangle 0 faces the light; its three neighbours face away, or one of
  // them holds the light in its plane; every other triangle faces away.
  for (int edge_on = -1; edge_on < 3; ++edge_on) {
    std::vector<Facing> facing(box.triangle_count(), Facing::Back);
    facing[front] = Facing::Front;
    if (edge_on >= 0) facing[box.neighbours[front][static_cast<std::size_t>(edge_on)]] = Facing::EdgeOn;
    const std::vector<SilhouetteEdge> edges = silhouette_edges(box, facing);
    ASSERT_EQ(edges.size(), 3u) << "edge-on neighbour " << edge_on;
    for (int k = 0; k < 3; ++k) {
      const auto& t = box.triangles[front];
      const SilhouetteEdge& e = edges[static_cast<std::size_t>(k)];
      EXPECT_EQ(e.front_face, front);
      EXPECT_EQ(e.other_face, box.neighbours[front][static_cast<std::size_t>(k)]);
      EXPECT_EQ(e.a, t[static_cast<std::size_t>(k)]);
      EXPECT_EQ(e.d, t[static_cast<std::size_t>((k + 1) % 3)]);
    }
  }
  // Two front triangles side by side: their shared edge is not one.
  std::vector<Facing> facing(box.triangle_count(), Facing::Back);
  facing[front] = Facing::Front;
  facing[box.neighbours[front][0]] = Facing::Front;
  const std::vector<SilhouetteEdge> edges = silhouette_edges(box, facing);
  EXPECT_EQ(edges.size(), 4u);
  for (const SilhouetteEdge& e : edges) EXPECT_NE(facing[e.other_face], Facing::Front);
}

}  // namespace
}  // namespace nearcap
