// CGAL Surface_mesh into nearcap (io/cgal_adapter.hpp): the same mesh as its
// file.  Its own object library: only this unit carries CGAL's flags.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include "nearcap/error.hpp"
#include "nearcap/io/cgal_adapter.hpp"
#include "nearcap/io/mesh_file.hpp"

namespace nearcap {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

bool same_positions(const std::vector<Vec3d>& a, const std::vector<Vec3d>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].x != b[k].x || a[k].y != b[k].y || a[k].z != b[k].z) return false;
  return true;
}

TEST(CgalAdapter, GivesTheSameMeshAsTheFileAndSkipsRemovedElements) {
  const TriangleMesh file = read_mesh(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/torus.off");
  SurfaceMesh sm;
  const auto extra = sm.add_vertex({9, 9, 9});  // removed again below: its index is skipped
  std::vector<SurfaceMesh::Vertex_index> v;
  for (const Vec3d& p : file.positions) v.push_back(sm.add_vertex({p.x, p.y, p.z}));
  for (const auto& t : file.triangles) ASSERT_NE(sm.add_face(v[t[0]], v[t[1]], v[t[2]]), SurfaceMesh::null_face());
  sm.remove_vertex(extra);
  const TriangleMesh adapted = mesh_from_cgal(sm, "torus (CGAL)");
  EXPECT_TRUE(same_positions(adapted.positions, file.positions));
  EXPECT_EQ(adapted.triangles, file.triangles);
}

TEST(CgalAdapter, AQuadFaceIsNamed) {
  SurfaceMesh sm;
  const auto a = sm.add_vertex({0, 0, 0}), b = sm.add_vertex({1, 0, 0}), c = sm.add_vertex({1, 1, 0}),
             d = sm.add_vertex({0, 1, 0});
  sm.add_face(a, b, c, d);
  try {
    (void)mesh_from_cgal(sm, "quad");
    FAIL() << "a quad was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Mesh);
    EXPECT_NE(std::string(e.what()).find("face 0 has 4 vertices"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nearcap
