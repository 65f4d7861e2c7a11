// Mesh reading and occluder validation from bytes in memory: a valid box is
// read exactly as written and gets its adjacency; every fault is an
// nearcap::Error of the documented kind whose message names the source and the
// element.  (Legal-but-awkward meshes: mesh_awkward_input_test.cpp.)
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "nearcap/error.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {
namespace {

// The unit cube [-1/2, 1/2]^3, counter-clockwise seen from outside.
const char* const kBoxVertices =
    "-0.5 -0.5 -0.5\n-0.5 -0.5 0.5\n-0.5 0.5 -0.5\n-0.5 0.5 0.5\n"
    "0.5 -0.5 -0.5\n0.5 -0.5 0.5\n0.5 0.5 -0.5\n0.5 0.5 0.5\n";
const char* const kBoxFaces[12] = {"3 0 1 3\n", "3 0 3 2\n", "3 4 6 7\n", "3 4 7 5\n", "3 0 4 5\n", "3 0 5 1\n",
                                   "3 2 3 7\n", "3 2 7 6\n", "3 0 2 6\n", "3 0 6 4\n", "3 1 5 7\n", "3 1 7 3\n"};

std::string box_faces() {
  std::string s;
  for (const char* f : kBoxFaces) s += f;
  return s;
}
// The box's vertex lines with line k replaced.
std::string box_vertices_with(int k, const std::string& line) {
  std::string v = kBoxVertices;
  std::size_t start = 0;
  for (int i = 0; i < k; ++i) start = v.find('\n', start) + 1;
  return v.replace(start, v.find('\n', start) - start, line);
}
std::string box_off() { return std::string("OFF\n8 12 0\n") + kBoxVertices + box_faces(); }

// Runs `f`, which must throw nearcap::Error of `kind` with `fragment` (and the
// source name) in its message.
void expect_error(const std::function<void()>& f, ErrorKind kind, const std::string& fragment,
                  const std::string& source) {
  try {
    f();
    ADD_FAILURE() << "no error; expected " << to_string(kind) << " with '" << fragment << "'";
  } catch (const Error& e) {
    EXPECT_EQ(to_string(e.kind()), to_string(kind)) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(source), std::string::npos) << "names the source: " << e.what();
  }
}
void expect_parse_error(const std::string& text, ErrorKind kind, const std::string& fragment) {
  expect_error([&] { (void)parse_off(text, "t.off"); }, kind, fragment, "t.off");
}
void expect_invalid_occluder(const std::string& text, const std::string& fragment) {
  TriangleMesh mesh = parse_off(text, "t.off");  // reads fine
  expect_error([&] { validate_occluder(mesh); }, ErrorKind::Mesh, fragment, "t.off");
}

TEST(MeshRead, BoxIsReadExactlyAsWritten) {
  const TriangleMesh mesh = parse_off(box_off(), "box.off");
  EXPECT_EQ(mesh.source, "box.off");
  ASSERT_EQ(mesh.positions.size(), 8u);
  ASSERT_EQ(mesh.triangle_count(), 12u);
  EXPECT_EQ(mesh.positions[5].x, 0.5);
  EXPECT_EQ(mesh.positions[5].y, -0.5);
  EXPECT_EQ(mesh.positions[5].z, 0.5);
  EXPECT_EQ(mesh.triangles[2], (std::array<VertexIndex, 3>{4, 6, 7}));
  EXPECT_FALSE(mesh.has_adjacency()) << "adjacency comes from validation";
}

TEST(MeshRead, DecimalCoordinatesAreTheNearestDouble) {
  const TriangleMesh mesh =
      parse_off("OFF\n4 4 0\n0.1 0 0\n0 0.1 0\n0 0 0.1\n0 0 0\n3 0 1 2\n3 0 3 1\n3 1 3 2\n3 2 3 0\n", "t.off");
  EXPECT_EQ(mesh.positions[0].x, 0.1) << "strtod's binary64, not a float";
}

TEST(MeshRead, ParseMeshOffIsParseOff) {
  const TriangleMesh a = parse_off(box_off(), "box.off");
  const TriangleMesh b = parse_mesh(box_off(), "off", "box.off");
  EXPECT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) EXPECT_EQ(a.positions[i].z, b.positions[i].z);
}

TEST(MeshRead, FaceColoursAndTrailingCommentsAreIgnored) {
  std::string faces = box_faces();
  faces.replace(0, std::string(kBoxFaces[0]).size(), "3 0 1 3 255 0 0 # red\n");
  const TriangleMesh mesh = parse_off(std::string("OFF\n8 12 0 # counts\n") + kBoxVertices + faces, "t.off");
  EXPECT_EQ(mesh.triangles[0], (std::array<VertexIndex, 3>{0, 1, 3}));
  EXPECT_EQ(mesh.triangles[1], (std::array<VertexIndex, 3>{0, 3, 2}));
}

TEST(MeshValidate, BoxIsAValidOccluderWithSymmetricAdjacency) {
  TriangleMesh mesh = parse_off(box_off(), "box.off");
  ASSERT_NO_THROW(validate_occluder(mesh));
  ASSERT_TRUE(mesh.has_adjacency());
  for (FaceIndex f = 0; f < mesh.triangle_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
      const FaceIndex g = mesh.neighbours[f][k];
      ASSERT_NE(g, kNoFace);
      ASSERT_NE(g, f);
      // g has the twin half-edge b -> a, and its neighbour across it is f.
      bool twin = false;
      for (int j = 0; j < 3; ++j)
        if (mesh.triangles[g][j] == b && mesh.triangles[g][(j + 1) % 3] == a) {
          twin = true;
          EXPECT_EQ(mesh.neighbours[g][j], f);
        }
      EXPECT_TRUE(twin) << "face " << f << " corner " << k;
    }
}

TEST(MeshValidate, OpenMeshNamesABoundaryEdge) {
  std::string faces = box_faces();
  faces.erase(faces.find(kBoxFaces[11]));  // drop the last face (1, 7, 3)
  expect_invalid_occluder(std::string("OFF\n8 11 0\n") + kBoxVertices + faces, "no neighbouring face");
}

TEST(MeshValidate, BuildAdjacencyMarksBoundaryEdgesOnOpenMeshes) {
  std::string faces = box_faces();
  faces.erase(faces.find(kBoxFaces[11]));
  TriangleMesh mesh = parse_off(std::string("OFF\n8 11 0\n") + kBoxVertices + faces, "t.off");
  build_adjacency(mesh);
  ASSERT_TRUE(mesh.has_adjacency());
  int boundary = 0;
  for (const auto& n : mesh.neighbours)
    for (FaceIndex g : n) boundary += g == kNoFace;
  EXPECT_EQ(boundary, 3) << "the missing triangle's three edges";
}

TEST(MeshValidate, ThirdFaceOnAnEdgeIsANonManifoldEdge) {
  // A fin: vertex 8 outside the box, triangle (0, 1, 8) on the box edge (0, 1).
  expect_invalid_occluder(std::string("OFF\n9 13 0\n") + kBoxVertices + "-1 -1 0\n" + box_faces() + "3 0 1 8\n",
                          "non-manifold edge");
}

TEST(MeshValidate, TwoTetrahedraSharingAVertexIsANonManifoldVertex) {
  // Both outward; they share vertex 0 only.
  const std::string text =
      "OFF\n7 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n-1 0 0\n0 -1 0\n0 0 -1\n"
      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
      "3 0 4 5\n3 0 6 4\n3 0 5 6\n3 4 6 5\n";
  TriangleMesh probe = parse_off(text, "t.off");
  expect_error([&] { validate_occluder(probe); }, ErrorKind::Mesh, "vertex 0", "t.off");
  expect_invalid_occluder(text, "non-manifold vertex");
}

TEST(MeshValidate, OneFlippedFaceIsAnInconsistentOrientation) {
  std::string faces = box_faces();
  faces.replace(0, std::string(kBoxFaces[0]).size(), "3 0 3 1\n");
  expect_invalid_occluder(std::string("OFF\n8 12 0\n") + kBoxVertices + faces, "inconsistent orientation");
}

TEST(MeshValidate, AllFacesFlippedIsInward) {
  std::string faces;
  for (const char* f : kBoxFaces) {
    int a, b, c;
    ASSERT_EQ(std::sscanf(f, "3 %d %d %d", &a, &b, &c), 3);
    faces += "3 " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(b) + "\n";
  }
  expect_invalid_occluder(std::string("OFF\n8 12 0\n") + kBoxVertices + faces, "inward");
}

// A mesh of boxes, each (centre x, half-size, turned inside out or not):
// every box its own component.
std::string boxes_off(const std::vector<std::tuple<double, double, bool>>& boxes) {
  std::string vertices, faces;
  int first = 0;
  for (const auto& [x, half, inside_out] : boxes) {
    for (int k = 0; k < 8; ++k)
      vertices += std::to_string(x + ((k & 4) ? half : -half)) + " " + std::to_string((k & 2) ? half : -half) + " " +
                  std::to_string((k & 1) ? half : -half) + "\n";
    for (const char* f : kBoxFaces) {
      int a, b, c;
      std::sscanf(f, "3 %d %d %d", &a, &b, &c);
      if (inside_out) std::swap(b, c);
      faces +=
          "3 " + std::to_string(first + a) + " " + std::to_string(first + b) + " " + std::to_string(first + c) + "\n";
    }
    first += 8;
  }
  return "OFF\n" + std::to_string(first) + " " + std::to_string(12 * boxes.size()) + " 0\n" + vertices + faces;
}

// The whole mesh's orientation is what validation checks; whether the mesh
// bounds outward solids is recorded (eye_setup.hpp reads it): not where a
// small box turned inside out lies beside a large one or inside it (a
// cavity), nor where two boxes pass through each other, nor with a
// zero-area face; all of these pass validation.
TEST(MeshValidate, WhetherTheMeshBoundsOutwardSolidsIsRecorded) {
  const std::tuple<const char*, std::string, bool> cases[] = {
      {"a box", boxes_off({{0, 0.5, false}}), true},
      {"two boxes apart", boxes_off({{0, 0.5, false}, {3, 0.25, false}}), true},
      {"a box beside one inside out", boxes_off({{0, 0.5, false}, {3, 0.25, true}}), false},
      {"a box with a cavity", boxes_off({{0, 0.5, false}, {0, 0.25, true}}), false},
      {"two boxes through each other", boxes_off({{0, 0.5, false}, {0.5, 0.5, false}}), false},
      {"a box with a zero-area face",
       "OFF\n9 14 0\n" + std::string(kBoxVertices) + "0 0.5 0.5\n" +
           [] {
             std::string f;
             for (int k = 0; k < 12; ++k)
               if (k != 6) f += kBoxFaces[k];
             // Face 6 (2 3 7) split at the midpoint 8 of edge 3-7.
             return f + "3 2 3 8\n3 2 8 7\n3 3 7 8\n";
           }(),
       false},
  };
  for (const auto& [what, off, bounds] : cases) {
    TriangleMesh mesh = parse_off(off, "boxes.off");
    EXPECT_FALSE(mesh.bounds_outward_solids()) << what << ": before validation";
    ASSERT_NO_THROW(validate_occluder(mesh)) << what;
    EXPECT_EQ(mesh.bounds_outward_solids(), bounds) << what;
  }
}

// The answer is decided at the first call and shared by the mesh's copies;
// validating a copy again (its positions changed) decides it anew, and a
// mesh that fails validation answers false.
TEST(MeshValidate, ACopyValidatedAgainDecidesWhetherItBoundsOutwardSolidsAnew) {
  TriangleMesh apart = parse_off(boxes_off({{0, 0.5, false}, {3, 0.25, false}}), "apart.off");
  validate_occluder(apart);
  const TriangleMesh shared = apart;
  EXPECT_TRUE(shared.bounds_outward_solids());
  EXPECT_TRUE(apart.bounds_outward_solids());

  TriangleMesh through = apart;
  through.positions = parse_off(boxes_off({{0, 0.5, false}, {0.5, 0.5, false}}), "through.off").positions;
  ASSERT_EQ(through.triangles, apart.triangles);
  validate_occluder(through);
  EXPECT_FALSE(through.bounds_outward_solids());
  EXPECT_TRUE(apart.bounds_outward_solids());

  TriangleMesh open = apart;
  open.triangles.pop_back();
  EXPECT_THROW(validate_occluder(open), Error);
  EXPECT_FALSE(open.bounds_outward_solids());
  EXPECT_TRUE(apart.bounds_outward_solids());
}

TEST(MeshValidate, TwoSidedFlatMeshHasZeroVolume) {
  // One triangle glued to its reverse: closed, consistent, manifold, volume 0.
  expect_invalid_occluder("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n", "signed volume is zero");
}

// The edge checks and the adjacency as a hash map of directed half-edges
// states them, face by face: the reference the sorted half-edges
// (mesh_validation.cpp, EdgeRuns) must agree with, message for message.
std::uint64_t directed_key(VertexIndex a, VertexIndex b) { return (std::uint64_t(a) << 32) | b; }

std::vector<std::array<FaceIndex, 3>> reference_neighbours(const TriangleMesh& mesh) {
  std::unordered_map<std::uint64_t, FaceIndex> face_of;
  for (FaceIndex f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) face_of.emplace(directed_key(mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3]), f);
  std::vector<std::array<FaceIndex, 3>> out(mesh.triangles.size(), {kNoFace, kNoFace, kNoFace});
  for (FaceIndex f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k)
      if (const auto it = face_of.find(directed_key(mesh.triangles[f][(k + 1) % 3], mesh.triangles[f][k]));
          it != face_of.end())
        out[f][k] = it->second;
  return out;
}

std::optional<std::string> reference_edge_fault(const TriangleMesh& mesh) {
  auto name = [](VertexIndex a, VertexIndex b) {
    return "edge (" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
  };
  std::unordered_map<std::uint64_t, std::uint32_t> undirected, directed;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      ++undirected[directed_key(std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]))];
  for (FaceIndex f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
      const std::uint32_t n = undirected[directed_key(std::min(a, b), std::max(a, b))];
      if (n > 2)
        return name(a, b) + " is shared by " + std::to_string(n) + " faces (non-manifold edge; first at face " +
               std::to_string(f) + ")";
    }
  for (FaceIndex f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
      const auto [it, inserted] = directed.emplace(directed_key(a, b), f);
      if (!inserted)
        return name(a, b) + " is traversed in the same direction by faces " + std::to_string(it->second) + " and " +
               std::to_string(f) + " (inconsistent orientation)";
    }
  for (FaceIndex f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
      if (directed.find(directed_key(b, a)) == directed.end())
        return name(a, b) + " of face " + std::to_string(f) + " has no neighbouring face (open mesh: boundary edge)";
    }
  return std::nullopt;
}

TEST(MeshValidate, SortedHalfEdgesAgreeWithTheHashMapFormulation) {
  // The box and an octahedron, each mutated at random: faces dropped,
  // repeated, reversed, moved, or a corner moved to another vertex (a loop
  // a -> a among them, which parse_off refuses but a built mesh may hold).
  TriangleMesh box = parse_off(box_off(), "t.off");
  TriangleMesh octahedron = parse_off(
      "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
      "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n",
      "t.off");
  ASSERT_NO_THROW(validate_occluder(octahedron));
  std::mt19937 random(20261203);
  std::map<std::string, int> outcomes;
  for (int trial = 0; trial < 4000; ++trial) {
    TriangleMesh mesh = trial % 2 ? box : octahedron;
    mesh.neighbours.clear();
    const int mutations = static_cast<int>(random() % 3);
    for (int m = 0; m < mutations && !mesh.triangles.empty(); ++m) {
      auto& faces = mesh.triangles;
      const std::size_t f = random() % faces.size();
      switch (random() % 5) {
        case 0:
          faces.erase(faces.begin() + static_cast<std::ptrdiff_t>(f));
          break;
        case 1:
          faces.push_back(faces[f]);
          break;
        case 2:
          std::swap(faces[f][1], faces[f][2]);
          break;
        case 3:
          std::swap(faces[f], faces[random() % faces.size()]);
          break;
        default:
          faces[f][random() % 3] = static_cast<VertexIndex>(random() % mesh.positions.size());
          break;
      }
    }
    TriangleMesh adjacency = mesh;
    build_adjacency(adjacency);
    ASSERT_EQ(adjacency.neighbours, reference_neighbours(mesh)) << "trial " << trial;
    if (mesh.triangles.empty()) continue;
    const std::optional<std::string> expected = reference_edge_fault(mesh);
    std::string got;
    try {
      validate_occluder(mesh);
      EXPECT_EQ(mesh.neighbours, reference_neighbours(mesh)) << "trial " << trial;
    } catch (const Error& e) {
      got = e.what();
    }
    if (expected) {
      EXPECT_EQ(got, "t.off: " + *expected) << "trial " << trial;
      for (const char* kind : {"non-manifold edge", "inconsistent orientation", "boundary edge"})
        if (expected->find(kind) != std::string::npos) ++outcomes[kind];
    } else {
      EXPECT_TRUE(got.empty() || got.find("non-manifold vertex") != std::string::npos ||
                  got.find("signed volume") != std::string::npos)
          << "trial " << trial << ": " << got;
      ++outcomes[got.empty() ? "valid" : "a later check"];
    }
  }
  // Each edge fault and valid meshes are exercised (about 500 to 1,700 of each).
  for (const char* outcome : {"non-manifold edge", "inconsistent orientation", "boundary edge", "valid"})
    EXPECT_GT(outcomes[outcome], 100) << outcome;
}

TEST(MeshValidate, ValidatingAnEmptyMeshIsAnError) {
  TriangleMesh mesh;
  mesh.source = "t.off";
  expect_error([&] { validate_occluder(mesh); }, ErrorKind::Mesh, "no faces", "t.off");
}

TEST(MeshParse, NanCoordinateIsNonFiniteAndNamesTheVertex) {
  expect_parse_error(std::string("OFF\n8 12 0\n") + box_vertices_with(2, "-0.5 nan -0.5") + box_faces(),
                     ErrorKind::NonFinite, "vertex 2");
}

TEST(MeshParse, InfCoordinateIsNonFiniteAndNamesTheVertex) {
  expect_parse_error(std::string("OFF\n8 12 0\n") + box_vertices_with(5, "0.5 -0.5 inf") + box_faces(),
                     ErrorKind::NonFinite, "vertex 5");
  expect_parse_error(std::string("OFF\n8 12 0\n") + box_vertices_with(5, "0.5 -1e999 0.5") + box_faces(),
                     ErrorKind::NonFinite, "vertex 5");  // overflows to -inf
}

TEST(MeshParse, NoFacesIsAnEmptyMesh) {
  expect_parse_error("OFF\n0 0 0\n", ErrorKind::Mesh, "no faces");
  expect_parse_error(std::string("OFF\n8 0 0\n") + kBoxVertices, ErrorKind::Mesh, "no faces");
}

TEST(MeshParse, EmptyTextIsAParseError) { expect_parse_error("", ErrorKind::Parse, "end of file"); }

TEST(MeshParse, TruncatedFileIsAParseErrorWithTheLine) {
  const std::string full = box_off();
  // Cut in the middle of the face list.
  expect_parse_error(full.substr(0, full.size() - 10), ErrorKind::Parse, "truncated");
  // Cut in the vertex list: fewer vertices than declared.
  expect_parse_error("OFF\n8 12 0\n0 0 0\n1 1", ErrorKind::Parse, "line 4");
}

TEST(MeshParse, QuadFaceIsRejectedAsNotATriangle) {
  expect_parse_error(
      std::string("OFF\n8 7 0\n") + kBoxVertices + "4 0 1 3 2\n3 4 6 7\n3 4 7 5\n3 0 4 5\n3 0 5 1\n3 2 3 7\n3 2 7 6\n",
      ErrorKind::Mesh, "face 0 has 4 vertices");
}

TEST(MeshParse, VertexIndexOutOfRangeIsNamed) {
  std::string faces = box_faces();
  faces.replace(0, std::string(kBoxFaces[0]).size(), "3 0 1 8\n");
  expect_parse_error(std::string("OFF\n8 12 0\n") + kBoxVertices + faces, ErrorKind::Parse, "refers to vertex 8");
  faces.replace(0, std::string("3 0 1 8\n").size(), "3 0 -1 3\n");
  expect_parse_error(std::string("OFF\n8 12 0\n") + kBoxVertices + faces, ErrorKind::Parse, "refers to vertex -1");
}

TEST(MeshParse, RepeatedVertexInAFaceIsRejected) {
  std::string faces = box_faces();
  faces.replace(0, std::string(kBoxFaces[0]).size(), "3 0 1 1\n");
  expect_parse_error(std::string("OFF\n8 12 0\n") + kBoxVertices + faces, ErrorKind::Mesh, "repeats a vertex");
}

TEST(MeshParse, BadHeaderAndBadTokensAreParseErrors) {
  expect_parse_error("COFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", ErrorKind::Parse, "keyword OFF");
  expect_parse_error("OFF\n3 x 0\n", ErrorKind::Parse, "found 'x'");
  expect_parse_error("OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n", ErrorKind::Parse, "found 'zero'");
  expect_parse_error("OFF\n-3 1 0\n", ErrorKind::Parse, "out of range");
  expect_parse_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", ErrorKind::Parse, "found '1.5'");
}

TEST(MeshParse, ContentAfterTheDeclaredFacesIsRejectedWithItsLine) {
  // A face beyond the header's count, or anything else after the last face, is
  // refused rather than dropped: the header and the file disagree.
  const std::string tetra = "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n";
  expect_parse_error(tetra + "3 0 1 3\n", ErrorKind::Parse,
                     "line 8: found '3' after the last of the 1 face the header declares");
  std::string eleven = box_off();
  eleven.replace(eleven.find("8 12 0"), 6, "8 11 0");
  expect_parse_error(eleven, ErrorKind::Parse, "line 22: found '3' after the last of the 11 faces the header declares");
  expect_parse_error(box_off() + "\n# done\ngarbage\n", ErrorKind::Parse,
                     "line 25: found 'garbage' after the last of the 12 faces the header declares");
}

TEST(MeshParse, AFaceLineHoldsItsIndicesAndAtMostAColour) {
  // A colour after the indices (one colour-map index, RGB or RGBA) is read and
  // ignored; two faces on one line (seven values after the first's indices) or
  // a word that is not a number are refused, not dropped.
  const std::string head = "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  for (const char* colour : {"", " 7", " 255 0 0", " 0.5 0.5 0.5 1", "  # a comment", " 7\r", " 255 0 0 \r"}) {
    const TriangleMesh mesh = parse_off(head + "3 0 2 1" + colour + "\n3 0 1 3\n", "t.off");
    EXPECT_EQ(mesh.triangle_count(), 2u) << colour;
  }
  EXPECT_EQ(parse_off(head + "3 0 2 1\n3 0 1 3 255 0 0", "t.off").triangle_count(), 2u);  // no newline at the end
  // Four numbers after the indices read as RGBA: the second face is then missing.
  expect_parse_error(head + "3 0 2 1 3 0 1 3\n", ErrorKind::Parse, "expected a face's vertex count");
  expect_parse_error("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1 3 0 1 3 3 1 2 3\n", ErrorKind::Parse,
                     "line 7: face 0 has 8 values after its vertex indices; a face colour is 1, 3 or 4 numbers");
  expect_parse_error(head + "3 0 2 1 255 0\n3 0 1 3\n", ErrorKind::Parse, "line 7: face 0 has 2 values after");
  expect_parse_error(head + "3 0 2 1 red\n3 0 1 3\n", ErrorKind::Parse, "line 7: face 0: expected a colour value");
}

TEST(MeshParse, UnknownFormatIsAParseError) {
  expect_error([] { (void)parse_mesh(box_off(), "gltf", "t.gltf"); }, ErrorKind::Parse, "unknown mesh format",
               "t.gltf");
}

TEST(MeshParse, MissingFileIsAnIoError) {
  expect_error([] { (void)read_mesh("/nonexistent/nearcap/none.off"); }, ErrorKind::Io, "cannot open",
               "/nonexistent/nearcap/none.off");
}

// ---- other formats through OpenMesh ----------------------------------------

std::string box_obj() {
  std::string s = "# the unit box\n";
  for (const char* v : {"-0.5 -0.5 -0.5", "-0.5 -0.5 0.5", "-0.5 0.5 -0.5", "-0.5 0.5 0.5", "0.5 -0.5 -0.5",
                        "0.5 -0.5 0.5", "0.5 0.5 -0.5", "0.5 0.5 0.5"})
    s += std::string("v ") + v + "\n";
  for (const char* f : kBoxFaces) {
    int a, b, c;
    std::sscanf(f, "3 %d %d %d", &a, &b, &c);
    s += "f " + std::to_string(a + 1) + " " + std::to_string(b + 1) + " " + std::to_string(c + 1) + "\n";
  }
  return s;
}

TEST(MeshReadOtherFormats, ObjBoxKeepsFacesAndOrder) {
  TriangleMesh mesh = parse_mesh(box_obj(), "obj", "box.obj");
  ASSERT_EQ(mesh.positions.size(), 8u);
  ASSERT_EQ(mesh.triangle_count(), 12u);
  const TriangleMesh off = parse_off(box_off(), "box.off");
  EXPECT_EQ(mesh.triangles, off.triangles);
  EXPECT_EQ(mesh.positions[7].x, 0.5);
  EXPECT_NO_THROW(validate_occluder(mesh));
}

TEST(MeshReadOtherFormats, ObjQuadIsRejectedAsNotATriangle) {
  expect_error([] { (void)parse_mesh("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", "obj", "q.obj"); },
               ErrorKind::Mesh, "triangle meshes only", "q.obj");
}

TEST(MeshReadObj, FaceEntriesWithTextureAndNormalIndices) {
  // "i/t/n", "i//n", "i/t" and negative (relative) indices all name positions.
  const std::string obj =
      "# a tetrahedron\nmtllib t.mtl\no tetra\nv 0 0 0\nv 1 0 0 1\nv 0 1 0 0.5 0.5 0.5\nv 0 0 1\n"
      "vt 0 0\nvn 0 0 1\ng side\nusemtl m\ns off\n"
      "f 1/1/1 3/1/1 2/1/1\nf 1//1 2//1 4//1\nf -4/1 -1/1 -2/1\nf 2 3 \\\n 4\n";
  TriangleMesh mesh = parse_mesh(obj, "obj", "t.obj");
  ASSERT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(mesh.triangles, (std::vector<std::array<VertexIndex, 3>>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}));
  EXPECT_NO_THROW(validate_occluder(mesh));
}

TEST(MeshReadObj, ErrorsNameTheLine) {
  auto obj_error = [](const std::string& text, ErrorKind kind, const std::string& fragment) {
    expect_error([&] { (void)parse_mesh(text, "obj", "e.obj"); }, kind, fragment, "e.obj");
  };
  const std::string verts = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  obj_error(verts + "f 1 2 4\n", ErrorKind::Mesh, "line 4: face 0 refers to vertex 4 but 3 vertices are defined");
  obj_error(verts + "f 0 1 2\n", ErrorKind::Mesh, "refers to vertex 0");
  obj_error(verts + "f 1 2 -4\n", ErrorKind::Mesh, "refers to vertex -4");
  obj_error(verts + "f 1 2\n", ErrorKind::Parse, "line 4: a face needs at least 3 vertices");
  obj_error(verts + "f 1 2 x/1\n", ErrorKind::Parse, "expected a vertex index, found 'x/1'");
  obj_error(verts + "f /1 2 3\n", ErrorKind::Parse, "expected a vertex index, found '/1'");
  obj_error("v 0 0\n", ErrorKind::Parse, "line 1: a vertex needs 3 coordinates");
  obj_error("v 0 0 zero\n", ErrorKind::Parse, "expected a vertex coordinate, found 'zero'");
  obj_error("v 0 0 0 2\n", ErrorKind::Parse, "vertex weight w = 2");
  obj_error("\n\n" + verts + "curv 0 1 1 2\n", ErrorKind::Mesh, "line 6: free-form geometry ('curv')");
  obj_error("this is not an obj file\n", ErrorKind::Parse, "line 1: unknown OBJ statement 'this'");
  obj_error(verts, ErrorKind::Mesh, "empty mesh");
  obj_error("v nan 0 0\n" + verts + "f 2 3 4\n", ErrorKind::NonFinite, "vertex 0 has a non-finite coordinate");
}

TEST(MeshReadObj, OpenMeshAssertionInputIsAnError) {
  // fuzz_obj's first crash: OpenMesh's OBJ reader asserted on this face line
  // (a face of tabs and "/A/"); nearcap's reader says what is wrong with it.
  expect_error([] { (void)parse_mesh("f\t\t\t\t\t\t\t\t\t\t\t\t/A/", "obj", "c.obj"); }, ErrorKind::Parse,
               "line 1: a face needs at least 3 vertices, found 1", "c.obj");
}

TEST(MeshReadOtherFormats, AsciiPlyBox) {
  std::string s =
      "ply\nformat ascii 1.0\nelement vertex 8\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 12\nproperty list uchar int vertex_indices\nend_header\n";
  s += kBoxVertices;
  s += box_faces();
  TriangleMesh mesh = parse_mesh(s, "ply", "box.ply");
  ASSERT_EQ(mesh.triangle_count(), 12u);
  EXPECT_EQ(mesh.triangles, parse_off(box_off(), "box.off").triangles);
  EXPECT_NO_THROW(validate_occluder(mesh));
}

// A tetrahedron with one coordinate 0.1, in three formats.  The exactness
// convention (README) makes every number read from a mesh file an exact
// binary64 value: 0.1 must read as the double nearest to 1/10, as OFF does.
const char* const kTetraObj = "v 0.1 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
const char* const kTetraPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
    "0.1 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

// Coordinates keep the precision the file declares (README, exactness
// convention): OBJ and OFF decimals read as the nearest double, a PLY property
// as its declared type, STL as float32 (the format's definition).  These tests
// pin that documented behaviour: if a reader changes, they fail and the README
// must change with them.
TEST(MeshReadOtherFormats, ObjCoordinatesAreTheNearestDouble) {
  const TriangleMesh mesh = parse_mesh(kTetraObj, "obj", "t.obj");
  ASSERT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(mesh.positions[0].x, 0.1) << std::setprecision(17) << mesh.positions[0].x;
}

TEST(MeshReadOtherFormats, PlyCoordinatesKeepTheirDeclaredType) {
  const TriangleMesh as_double = parse_mesh(kTetraPly, "ply", "t.ply");
  ASSERT_EQ(as_double.positions.size(), 4u);
  EXPECT_EQ(as_double.positions[0].x, 0.1) << std::setprecision(17) << as_double.positions[0].x;
  std::string float_ply = kTetraPly;
  for (std::size_t at; (at = float_ply.find("property double")) != std::string::npos;)
    float_ply.replace(at, 15, "property float");
  const TriangleMesh as_float = parse_mesh(float_ply, "ply", "t.ply");
  EXPECT_EQ(as_float.positions[0].x, static_cast<double>(0.1f)) << std::setprecision(17) << as_float.positions[0].x;
}

TEST(MeshReadOtherFormats, OffCoordinatesAreTheNearestDouble) {
  const TriangleMesh mesh =
      parse_off("OFF\n4 4 0\n0.1 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", "t.off");
  EXPECT_EQ(mesh.positions[0].x, 0.1);
}

TEST(MeshReadOtherFormats, AsciiStlSharesVerticesByPosition) {
  // STL lists three positions per facet; equal positions become one vertex, so
  // a closed STL solid is a valid occluder.  (STL is float32 by definition.)
  std::string stl = "solid t\n";
  auto facet = [&](const char* a, const char* b, const char* c) {
    stl += std::string("facet normal 0 0 0\nouter loop\nvertex ") + a + "\nvertex " + b + "\nvertex " + c +
           "\nendloop\nendfacet\n";
  };
  facet("0 0 0", "0 1 0", "1 0 0");
  facet("0 0 0", "1 0 0", "0 0 1");
  facet("0 0 0", "0 0 1", "0 1 0");
  facet("1 0 0", "0 1 0", "0 0 1");
  stl += "endsolid t\n";
  TriangleMesh mesh = parse_mesh(stl, "stl", "t.stl");
  EXPECT_EQ(mesh.positions.size(), 4u);
  ASSERT_EQ(mesh.triangle_count(), 4u);
  EXPECT_NO_THROW(validate_occluder(mesh));
}

TEST(MeshReadPly, ErrorsNameTheLineOrByte) {
  auto ply_error = [](const std::string& text, ErrorKind kind, const std::string& fragment) {
    expect_error([&] { (void)parse_mesh(text, "ply", "e.ply"); }, kind, fragment, "e.ply");
  };
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string faces = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string verts = "0 0 0\n1 0 0\n0 1 0\n";
  ply_error("plyx\n", ErrorKind::Parse, "line 1: the file does not start with the line 'ply'");
  ply_error(head + faces, ErrorKind::Parse, "line 10: unexpected end of data, expected property 'x' of vertex 0");
  ply_error(head + faces + verts + "4 0 1 2 0\n", ErrorKind::Mesh, "line 13: face 0 has 4 vertices");
  ply_error(head + faces + verts + "3 0 1 x\n", ErrorKind::Parse,
            "expected item 2 of 'vertex_indices' of face 0 (an integer), found 'x'");
  ply_error(head + faces + verts + "3 0 1 3\n", ErrorKind::Mesh,
            "face 0 refers to vertex 3 but the file has 3 vertices");
  ply_error(head + faces + verts + "300 0 1 2\n", ErrorKind::Parse, "does not fit its declared type");
  ply_error(head + "element face 1\nproperty list float int vertex_indices\nend_header\n", ErrorKind::Parse,
            "line 8: list count type 'float' is not an integer type");
  ply_error(head + "end_header\n" + verts, ErrorKind::Mesh, "empty mesh");
  ply_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n",
            ErrorKind::Parse, "the vertex element lacks one of the properties x, y, z");
  ply_error(
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\nend_header\n\x01\x02",
      ErrorKind::Parse, "byte 115: unexpected end of data, expected property 'x' of vertex 0");
  ply_error("ply\nformat ascii 1.0\nelement vertex 3\n", ErrorKind::Parse, "no end_header line");
  ply_error("ply\nformat ascii 2.0\nend_header\n", ErrorKind::Parse, "line 2: unsupported PLY version '2.0'");
  // fuzz_ply's first input through OpenMesh (a segmentation fault in its
  // header check): a property declared before any element.
  ply_error("ply\nformat ascii 1.0\nex 8\nproperty float x\nend_header\n", ErrorKind::Parse,
            "line 3: unknown PLY header line 'ex'");
  ply_error("ply\nformat ascii 1.0\nproperty float x\nend_header\n", ErrorKind::Parse,
            "line 3: a property declared before any element");
  // Which of two y's, or two vertex elements, a reader takes is a guess:
  // refused, naming the line.
  ply_error(head + "property float y\n" + faces, ErrorKind::Parse,
            "line 7: element 'vertex' declares property 'y' twice");
  ply_error(head + "element vertex 3\nproperty float x\n" + faces, ErrorKind::Parse,
            "line 7: a second 'vertex' element (a mesh has one)");
}

TEST(MeshReadPly, ContentAfterTheLastElementIsRejected) {
  auto ply_error = [](const std::string& text, const std::string& fragment) {
    expect_error([&] { (void)parse_mesh(text, "ply", "e.ply"); }, ErrorKind::Parse, fragment, "e.ply");
  };
  std::string one_face = kTetraPly;
  one_face.replace(one_face.find("element face 4"), 14, "element face 3");
  ply_error(one_face, "line 17: found '3' after the last element the header declares ('element face 3')");
  ply_error(std::string(kTetraPly) + "\ngarbage", "line 19: found 'garbage' after the last element");
  // Binary: the data ends with the last element's last byte; the message
  // names the offset of the first byte past it.
  std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
  auto put = [&](const auto& v) { binary.append(reinterpret_cast<const char*>(&v), sizeof v); };
  for (const float c : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f}) put(c);
  const std::int32_t faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& f : faces) {
    put(std::uint8_t{3});
    for (std::int32_t i : f) put(i);
  }
  TriangleMesh mesh = parse_mesh(binary, "ply", "b.ply");
  EXPECT_NO_THROW(validate_occluder(mesh));
  const std::string end = std::to_string(binary.size());
  ply_error(binary + "\n", "byte " + end + ": 1 byte after the last element the header declares ('element face 4')");
}

TEST(MeshReadPly, OtherElementsAndPropertiesAreSkippedByType) {
  // A binary file with an extra vertex property (a double), a list before the
  // face indices and an element of its own: only x, y, z and vertex_indices count.
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty double quality\n"
      "property float y\nproperty float z\nelement face 4\nproperty list uchar short tags\n"
      "property list ushort uint vertex_indices\nelement material 2\nproperty uchar red\nend_header\n";
  auto put = [&](const auto& v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); };
  const float xyz[4][3] = {{0.1f, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& p : xyz) {
    put(p[0]);
    put(double{7.5});
    put(p[1]);
    put(p[2]);
  }
  const std::uint32_t faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& f : faces) {
    put(std::uint8_t{2});
    put(std::int16_t{-1});
    put(std::int16_t{5});
    put(std::uint16_t{3});
    for (std::uint32_t i : f) put(i);
  }
  s += "\x10\x20";
  TriangleMesh mesh = parse_mesh(s, "ply", "b.ply");
  ASSERT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(mesh.positions[0].x, static_cast<double>(0.1f));
  EXPECT_EQ(mesh.triangles, (std::vector<std::array<VertexIndex, 3>>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}));
  EXPECT_NO_THROW(validate_occluder(mesh));
}

TEST(MeshReadStl, ErrorsNameTheFacet) {
  auto stl_error = [](const std::string& text, ErrorKind kind, const std::string& fragment) {
    expect_error([&] { (void)parse_mesh(text, "stl", "e.stl"); }, kind, fragment, "e.stl");
  };
  const std::string facet =
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
  stl_error("solid s\n" + facet, ErrorKind::Parse, "line 9: unexpected end of file, expected 'facet' or 'endsolid'");
  stl_error("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n", ErrorKind::Parse,
            "line 6: facet 0 has 2 vertices");
  stl_error("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\n",
            ErrorKind::Mesh, "facet 0 has more than 3 vertices");
  stl_error(
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 nan 0\nvertex 1 0 0\nvertex 0 1 "
      "0\nendloop\nendfacet\nendsolid\n",
      ErrorKind::NonFinite, "facet 0 vertex 0 has a non-finite coordinate");
  stl_error("not an stl", ErrorKind::Parse, "at least 84 bytes, this one 10");
  std::string binary(80, ' ');
  binary += std::string("\x02\x00\x00\x00", 4) + std::string(50, '\0');
  stl_error(binary, ErrorKind::Parse, "binary STL header says 2 facets (184 bytes) but the file holds 134 bytes");
}

TEST(MeshReadStl, ContentAfterEndsolidIsRejected) {
  auto stl_error = [](const std::string& text, const std::string& fragment) {
    expect_error([&] { (void)parse_mesh(text, "stl", "e.stl"); }, ErrorKind::Parse, fragment, "e.stl");
  };
  const std::string facet =
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
  stl_error("solid s\n" + facet + "endsolid s\n" + facet,
            "line 10: found 'facet' after 'endsolid' (only whitespace or another 'solid' may follow)");
  stl_error("solid s\n" + facet + "endsolid s\n\n  garbage\n", "line 11: found 'garbage' after 'endsolid'");
  // Padding is not the end when something follows it.
  stl_error("solid s\n" + facet + "endsolid s\n" + std::string("\0\0\n", 3) + "garbage\n",
            "found 'garbage' after 'endsolid'");
}

// NUL bytes or a DOS end-of-file mark after the last endsolid, as some
// writers pad a file: read as its end.
TEST(MeshReadStl, PaddingAfterTheLastEndsolidIsTheEnd) {
  const std::string facet =
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
  for (const std::string& padding : {std::string("\0\0\0\0", 4), std::string("\x1a"), std::string("\n\0 \x1a\n", 5)}) {
    const TriangleMesh mesh = parse_mesh("solid s\n" + facet + "endsolid s\n" + padding, "stl", "p.stl");
    EXPECT_EQ(mesh.triangle_count(), 1u);
  }
}

TEST(MeshReadStl, BinaryFileStartingWithSolidIsBinary) {
  // Exporters write "solid" into binary headers; the size decides.
  std::string s = "solid but binary";
  s.resize(80, ' ');
  auto put = [&](const auto& v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); };
  put(std::uint32_t{4});
  const float tetra[4][3][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}},
                                {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}},
                                {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                                {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (const auto& f : tetra) {
    for (int k = 0; k < 3; ++k) put(0.0f);
    for (const auto& v : f)
      for (float c : v) put(c);
    put(std::uint16_t{0});
  }
  TriangleMesh mesh = parse_mesh(s, "stl", "b.stl");
  EXPECT_EQ(mesh.positions.size(), 4u);
  ASSERT_EQ(mesh.triangle_count(), 4u);
  EXPECT_NO_THROW(validate_occluder(mesh));
}

TEST(MeshReadOtherFormats, GarbageIsAParseErrorNotACrash) {
  for (const char* format : {"obj", "ply", "stl"}) {
    try {
      TriangleMesh mesh = parse_mesh(std::string("\x01\x02 garbage\nply\nsolid\n"), format, "g");
      validate_occluder(mesh);
      ADD_FAILURE() << format << ": garbage accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("g:"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace nearcap
