// nearcap's own OBJ, PLY and STL readers against OpenMesh's on well-formed
// files: the bundled torus and bunny written in every format variant must
// read as the same triangles over the same positions.  (OpenMesh hands
// coordinates over as float32, so positions are compared as float32; the
// files are written with float32 values.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>

#include "nearcap/io/mesh_file.hpp"
#include "nearcap/scene/mesh.hpp"
#include "openmesh_reference_reader.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

TriangleMesh bundled(const char* name) {
  return read_mesh((fs::path(NEARCAP_SOURCE_DIR) / "data" / "meshes" / name).string());
}

float f32(double v) { return static_cast<float>(v); }

std::string decimal(float v) {
  std::ostringstream s;
  s.precision(9);  // enough digits to round-trip a float32
  s << v;
  return s.str();
}

std::string as_obj(const TriangleMesh& m) {
  std::string s = "# written by the differential test\n";
  for (const Vec3d& p : m.positions)
    s += "v " + decimal(f32(p.x)) + " " + decimal(f32(p.y)) + " " + decimal(f32(p.z)) + "\n";
  for (const auto& t : m.triangles)
    s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
  return s;
}

std::string ply_header(const TriangleMesh& m, const char* format) {
  return std::string("ply\nformat ") + format + " 1.0\ncomment differential\nelement vertex " +
         std::to_string(m.positions.size()) + "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
         std::to_string(m.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
}

std::string as_ascii_ply(const TriangleMesh& m) {
  std::string s = ply_header(m, "ascii");
  for (const Vec3d& p : m.positions) s += decimal(f32(p.x)) + " " + decimal(f32(p.y)) + " " + decimal(f32(p.z)) + "\n";
  for (const auto& t : m.triangles)
    s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  return s;
}

template <class T>
void put(std::string& s, T v, bool big_endian) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));  // the test host is little-endian (x86-64)
  s.append(b, sizeof(T));
}

std::string as_binary_ply(const TriangleMesh& m, bool big_endian) {
  std::string s = ply_header(m, big_endian ? "binary_big_endian" : "binary_little_endian");
  for (const Vec3d& p : m.positions)
    for (double c : {p.x, p.y, p.z}) put(s, f32(c), big_endian);
  for (const auto& t : m.triangles) {
    put(s, std::uint8_t{3}, big_endian);
    for (VertexIndex i : t) put(s, static_cast<std::int32_t>(i), big_endian);
  }
  return s;
}

std::string as_ascii_stl(const TriangleMesh& m) {
  std::string s = "solid differential\n";
  for (const auto& t : m.triangles) {
    s += "facet normal 0 0 0\nouter loop\n";
    for (VertexIndex i : t) {
      const Vec3d& p = m.positions[i];
      s += "vertex " + decimal(f32(p.x)) + " " + decimal(f32(p.y)) + " " + decimal(f32(p.z)) + "\n";
    }
    s += "endloop\nendfacet\n";
  }
  return s + "endsolid differential\n";
}

std::string as_binary_stl(const TriangleMesh& m) {
  std::string s(80, ' ');
  put(s, static_cast<std::uint32_t>(m.triangles.size()), false);
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) put(s, 0.0f, false);
    for (VertexIndex i : t)
      for (double c : {m.positions[i].x, m.positions[i].y, m.positions[i].z}) put(s, f32(c), false);
    put(s, std::uint16_t{0}, false);
  }
  return s;
}

// Same triangles, corner by corner, over the same float32 positions.
void expect_same_triangles(const TriangleMesh& ours, const TriangleMesh& theirs, const std::string& what) {
  ASSERT_EQ(ours.triangles.size(), theirs.triangles.size()) << what;
  for (std::size_t f = 0; f < ours.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Vec3d& a = ours.positions[ours.triangles[f][static_cast<std::size_t>(k)]];
      const Vec3d& b = theirs.positions[theirs.triangles[f][static_cast<std::size_t>(k)]];
      ASSERT_TRUE(f32(a.x) == f32(b.x) && f32(a.y) == f32(b.y) && f32(a.z) == f32(b.z))
          << what << ": face " << f << " corner " << k;
    }
}

class MeshReaderDifferential : public ::testing::TestWithParam<const char*> {};

TEST_P(MeshReaderDifferential, EveryFormatVariantReadsAsOpenMeshReadsIt) {
  const TriangleMesh source = bundled(GetParam());
  struct Variant {
    const char* name;
    const char* format;
    std::string bytes;
  };
  const Variant variants[] = {
      {"obj", "obj", as_obj(source)},
      {"ascii ply", "ply", as_ascii_ply(source)},
      {"binary little-endian ply", "ply", as_binary_ply(source, false)},
      {"ascii stl", "stl", as_ascii_stl(source)},
      {"binary stl", "stl", as_binary_stl(source)},
  };
  for (const Variant& v : variants) {
    const TriangleMesh ours = parse_mesh(v.bytes, v.format, std::string("differential.") + v.format);
    const TriangleMesh theirs = test::read_with_openmesh(v.bytes, v.format);
    expect_same_triangles(ours, theirs, v.name);
    EXPECT_EQ(ours.positions.size(), theirs.positions.size()) << v.name;
    if (std::string(v.format) != "stl") {  // STL numbers vertices by first appearance
      EXPECT_EQ(ours.triangles, source.triangles) << v.name << ": faces and vertex order as written";
    }
  }
  // Big-endian PLY: the same mesh as little-endian, bit for bit.
  const TriangleMesh le = parse_mesh(as_binary_ply(source, false), "ply", "le.ply");
  const TriangleMesh be = parse_mesh(as_binary_ply(source, true), "ply", "be.ply");
  EXPECT_EQ(le.triangles, be.triangles);
  ASSERT_EQ(le.positions.size(), be.positions.size());
  for (std::size_t i = 0; i < le.positions.size(); ++i) {
    EXPECT_TRUE(le.positions[i].x == be.positions[i].x && le.positions[i].y == be.positions[i].y &&
                le.positions[i].z == be.positions[i].z)
        << i;
  }
}

std::string mesh_name(const ::testing::TestParamInfo<const char*>& param) {
  const std::string file = param.param;
  return file.substr(0, file.find('.'));
}

INSTANTIATE_TEST_SUITE_P(Bundled, MeshReaderDifferential, ::testing::Values("torus.off", "bunny.off"), mesh_name);

}  // namespace
}  // namespace nearcap
