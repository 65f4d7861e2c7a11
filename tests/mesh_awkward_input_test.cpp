// Legal but awkward meshes: handled, not rejected, with documented behaviour.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

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

// An ascii STL file's "solid" line and `mesh`'s facets, up to its "endsolid".
std::string ascii_stl_facets(const TriangleMesh& mesh) {
  std::string stl = "solid t\n";
  for (const auto& f : mesh.triangles) {
    stl += "facet normal 0 0 0\nouter loop\n";
    for (VertexIndex v : f) {
      const Vec3d& p = mesh.positions[v];
      stl += "vertex " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    }
    stl += "endloop\nendfacet\n";
  }
  return stl;
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
  TriangleMesh ascii_stl = parse_mesh(ascii_stl_facets(off) + "endsolid t" + tail, "stl", "t.stl");
  EXPECT_EQ(ascii_stl.triangle_count(), 12u);
  EXPECT_NO_THROW(validate_occluder(ascii_stl));
}

// Every '\n' of `text` as the classic Mac OS line end, a lone '\r'.
std::string with_cr_line_ends(std::string text) {
  std::replace(text.begin(), text.end(), '\n', '\r');
  return text;
}

TEST(AwkwardMesh, CarriageReturnLineEndsReadAsLineFeeds) {
  // A lone '\r' ends a line (classic Mac OS files), as "\r\n" and "\n" do:
  // each text format reads the same mesh, its comments and face colours
  // ending at the line's end.
  std::string off = std::string("# a box\nOFF\n8 12 0\n") + kBoxVertices + kBoxFaces;
  off.replace(off.find("3 0 1 3\n"), 8, "3 0 1 3 255 0 0 # a red face\n");
  std::string obj = "# a box\n";
  std::istringstream vertices(kBoxVertices);
  for (std::string line; std::getline(vertices, line);) obj += "v " + line + "\n";
  std::istringstream faces(kBoxFaces);
  for (int a = 0, b = 0, c = 0, n = 0; faces >> n >> a >> b >> c;)
    obj += "f " + std::to_string(a + 1) + " \\\n" + std::to_string(b + 1) + " " + std::to_string(c + 1) + " # face\n";
  const std::string ply =
      std::string("ply\nformat ascii 1.0\ncomment a box\nelement vertex 8\nproperty double x\nproperty double y\n") +
      "property double z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n" + kBoxVertices +
      kBoxFaces;
  const TriangleMesh expected = parse_off(off, "lf.off");
  ASSERT_EQ(expected.triangle_count(), 12u);
  for (const auto& [format, text] : {std::pair<std::string, std::string>{"off", off}, {"obj", obj}, {"ply", ply}}) {
    SCOPED_TRACE(format);
    const TriangleMesh lf = parse_mesh(text, format, "lf." + format);
    const TriangleMesh cr = parse_mesh(with_cr_line_ends(text), format, "cr." + format);
    EXPECT_EQ(lf.triangles, expected.triangles);
    EXPECT_EQ(cr.triangles, expected.triangles);
    ASSERT_EQ(cr.positions.size(), expected.positions.size());
    for (std::size_t i = 0; i < cr.positions.size(); ++i)
      for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(cr.positions[i][k], expected.positions[i][k]);
  }
  const std::string stl = ascii_stl_facets(expected) + "endsolid t\n";
  const TriangleMesh stl_lf = parse_mesh(stl, "stl", "lf.stl");
  EXPECT_EQ(stl_lf.triangle_count(), 12u);
  EXPECT_EQ(parse_mesh(with_cr_line_ends(stl), "stl", "cr.stl").triangles, stl_lf.triangles);
}

TEST(AwkwardMesh, CarriageReturnLineEndsCountInErrorLines) {
  // An error names its line however the lines end; in "\r\n" the pair is one
  // line end.
  const std::string off = std::string("OFF\n8 12 0\n") + kBoxVertices + "3 0 1 x\n";  // line 11
  for (const std::string& text : {off, with_cr_line_ends(off), [&] {
                                    std::string crlf;
                                    for (char c : off) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
                                    return crlf;
                                  }()}) {
    try {
      (void)parse_off(text, "t.off");
      ADD_FAILURE() << "read";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("line 11:"), std::string::npos) << e.what();
    }
  }
  try {
    (void)parse_mesh(with_cr_line_ends("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"), "obj", "t.obj");
    ADD_FAILURE() << "read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("line 4:"), std::string::npos) << e.what();
  }
}

TEST(AwkwardMesh, BinaryPlyAfterACarriageReturnEndedHeader) {
  // The header's lines may end with a lone '\r'; the binary data starts after
  // end_header's.
  std::string ply =
      "ply\rformat binary_little_endian 1.0\relement vertex 3\rproperty float x\rproperty float y\r"
      "property float z\relement face 1\rproperty list uchar int vertex_indices\rend_header\r";
  for (float v : {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f})
    ply.append(reinterpret_cast<const char*>(&v), sizeof v);
  ply.push_back('\x03');
  for (std::int32_t i : {0, 1, 2}) ply.append(reinterpret_cast<const char*>(&i), sizeof i);
  const TriangleMesh mesh = parse_mesh(ply, "ply", "cr.ply");
  ASSERT_EQ(mesh.triangle_count(), 1u);
  EXPECT_EQ(mesh.positions[1].x, 1.0);
  EXPECT_EQ(mesh.positions[2].y, 1.0);
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
