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
