// Legal but awkward meshes: handled, not rejected, with documented behaviour.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli_support.hpp"
#include "nearcap/exact/light_facing.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/scene/mesh.hpp"
#include "nearcap/scene/scene.hpp"
#include "random_scene.hpp"

namespace nearcap {
namespace {

const char* const kBoxVertices =
    "-0.5 -0.5 -0.5\n-0.5 -0.5 0.5\n-0.5 0.5 -0.5\n-0.5 0.5 0.5\n"
    "0.5 -0.5 -0.5\n0.5 -0.5 0.5\n0.5 0.5 -0.5\n0.5 0.5 0.5\n";
const char* const kBoxFaces =
    "3 0 1 3\n3 0 3 2\n3 4 6 7\n3 4 7 5\n3 0 4 5\n3 0 5 1\n3 2 3 7\n3 2 7 6\n3 0 2 6\n3 0 6 4\n3 1 5 7\n3 1 7 3\n";

TEST(AwkwardMesh, OffWithLeadingCommentsIsRead) {
  const std::string text = std::string("# a comment before the header\n# and another\nOFF\n# counts next\n8 12 0\n") +
                           kBoxVertices + kBoxFaces;
  TriangleMesh mesh = parse_off(text, "comments.off");
  EXPECT_EQ(mesh.triangle_count(), 12u);
  EXPECT_NO_THROW(validate_occluder(mesh));
}

TEST(AwkwardMesh, WhitespaceAfterTheLastElementIsRead) {
  // After the declared elements only whitespace may follow (and in OFF,
  // comments, which the format allows anywhere): blank lines, CRLF, tabs.
  const std::string tail = "\n\r\n \t\n  \n";
  TriangleMesh off =
      parse_off(std::string("OFF\n8 12 0\n") + kBoxVertices + kBoxFaces + tail + "# the end\n\n# really\n", "t.off");
  EXPECT_EQ(off.triangle_count(), 12u);
  const std::string ply_head =
      "ply\nformat ascii 1.0\nelement vertex 8\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 12\nproperty list uchar int vertex_indices\nend_header\n";
  TriangleMesh ply = parse_mesh(ply_head + kBoxVertices + kBoxFaces + tail, "ply", "t.ply");
  EXPECT_EQ(ply.triangles, off.triangles);
  std::string stl = "solid t\n";
  for (const auto& f : off.triangles) {
    stl += "facet normal 0 0 0\nouter loop\n";
    for (VertexIndex v : f) {
      const Vec3d& p = off.positions[v];
      stl += "vertex " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    }
    stl += "endloop\nendfacet\n";
  }
  TriangleMesh ascii_stl = parse_mesh(stl + "endsolid t" + tail, "stl", "t.stl");
  EXPECT_EQ(ascii_stl.triangle_count(), 12u);
  EXPECT_NO_THROW(validate_occluder(ascii_stl));
}

TEST(AwkwardMesh, AsciiStlWithSeveralSolidsReadsEveryOne) {
  // Several "solid ... endsolid" blocks in one ascii file occur in the wild:
  // all their facets make one mesh (vertices shared by position across them).
  auto facet = [](const char* a, const char* b, const char* c) {
    return std::string("facet normal 0 0 0\nouter loop\nvertex ") + a + "\nvertex " + b + "\nvertex " + c +
           "\nendloop\nendfacet\n";
  };
  const std::string stl = "solid first part\n" + facet("0 0 0", "0 1 0", "1 0 0") + facet("0 0 0", "1 0 0", "0 0 1") +
                          "endsolid first part\n\nsolid second\n" + facet("0 0 0", "0 0 1", "0 1 0") +
                          facet("1 0 0", "0 1 0", "0 0 1") + "endsolid second\n";
  TriangleMesh mesh = parse_mesh(stl, "stl", "two.stl");
  EXPECT_EQ(mesh.positions.size(), 4u);
  ASSERT_EQ(mesh.triangle_count(), 4u);
  EXPECT_NO_THROW(validate_occluder(mesh));
}

TEST(AwkwardMesh, UnreferencedAndDuplicateVerticesAreLegal) {
  // Vertex 8 duplicates vertex 7's position, vertex 9 is referenced by no face.
  const std::string text = std::string("OFF\n10 12 0\n") + kBoxVertices + "0.5 0.5 0.5\n9 9 9\n" + kBoxFaces;
  TriangleMesh mesh = parse_off(text, "extra_vertices.off");
  EXPECT_EQ(mesh.positions.size(), 10u);
  EXPECT_NO_THROW(validate_occluder(mesh));
}

// The box with its top-front edge (3, 7) split at its midpoint m = 8 on the top
// side only, closed by the zero-area sliver (m, 3, 7).
std::string sliver_box() {
  std::string faces = kBoxFaces;
  const std::string top = "3 2 3 7\n";
  faces.replace(faces.find(top), top.size(), "3 2 3 8\n3 2 8 7\n3 8 3 7\n");
  return std::string("OFF\n9 14 0\n") + kBoxVertices + "0 0.5 0.5\n" + faces;
}

TEST(AwkwardMesh, ZeroAreaTriangleIsLegalAndEdgeOnForEveryLight) {
  TriangleMesh mesh = parse_off(sliver_box(), "sliver.off");
  ASSERT_NO_THROW(validate_occluder(mesh));
  const auto path = test::temp_path("nearcap_sliver_box") += ".off";
  std::ofstream(path) << sliver_box();
  for (const auto& light : {std::array<double, 3>{0, 5, 0}, std::array<double, 3>{3, -2, 4}}) {
    nlohmann::json j;
    j["camera"] = {{"eye", {0, 1, 6}}, {"target", {0, 0, 0}}, {"fovy_deg", 40}, {"near", 1},
                   {"far", 50},        {"width", 8},          {"height", 8}};
    j["lights"] = nlohmann::json::array({{{"position", light}}});
    j["objects"] = nlohmann::json::array({{{"mesh", path.string()}}});
    const Scene scene = parse_scene(j.dump(), "sliver", ".");
    const CameraSpaceScene cs(scene);
    const std::vector<Facing> facing = light_facing(cs, 0, 0, nullptr);
    const FaceIndex sliver = 8;  // "3 8 3 7"
    ASSERT_EQ(scene.objects[0].mesh->triangles[sliver], (std::array<VertexIndex, 3>{8, 3, 7}));
    EXPECT_EQ(facing[sliver], Facing::EdgeOn);
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace nearcap
