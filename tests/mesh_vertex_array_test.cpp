// The mesh's vertex array (src/gl/mesh_vertex_array.hpp): each vertex program
// run once per mesh vertex and gathered per corner gives, bit for bit, what
// running it on every corner gives, the corners in the mesh's triangle order;
// and the shadow volume's caps are its points and directions gathered.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../src/gl/mesh_vertex_array.hpp"
#include "nearcap/gl/engine_classification.hpp"
#include "nearcap/gl/shadow_vertex_programs.hpp"
#include "nearcap/gl/shadow_volume_geometry.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap::gl {
namespace {

bool same_bits(const Vec4f& a, const Vec4f& b) { return std::memcmp(&a, &b, sizeof(Vec4f)) == 0; }

Mat4f random_matrix(std::mt19937& rng) {
  std::uniform_real_distribution<float> entry(-3.0f, 3.0f);
  Mat4f m;
  for (float& e : m.m) e = entry(rng);
  return m;
}

TEST(MeshVertexArray, EachProgramGivesTheBitsOfRunningItOnEveryCorner) {
  const TriangleMesh bunny = read_mesh(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/bunny.off");
  const MeshVertexArray a = mesh_vertex_array(bunny);
  ASSERT_EQ(a.vertices.size(), bunny.positions.size());
  const std::vector<ShadowVertex> c = corners(a);
  ASSERT_EQ(c.size(), 3 * bunny.triangles.size());
  for (std::size_t t = 0; t < bunny.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3d& p = bunny.positions[bunny.triangles[t][static_cast<std::size_t>(k)]];
      const ShadowVertex& v = c[3 * t + static_cast<std::size_t>(k)];
      ASSERT_EQ(v.x, static_cast<float>(p.x));
      ASSERT_EQ(v.y, static_cast<float>(p.y));
      ASSERT_EQ(v.z, static_cast<float>(p.z));
      ASSERT_EQ(v.w, 1.0f);
    }
  std::mt19937 rng(7);
  for (int trial = 0; trial < 4; ++trial)
    for (Arithmetic arithmetic : {Arithmetic::Separate, Arithmetic::Fused})
      for (VertexProgram p : {VertexProgram::Extrusion, VertexProgram::Figure7, VertexProgram::NearCap}) {
        ShadowUniforms u;
        u.modelview_projection = random_matrix(rng);
        u.light_modelview = random_matrix(rng);
        u.light_projection = random_matrix(rng);
        u.light_position = {0.5f, 2.0f, -1.0f, 1.0f};
        u.arithmetic = arithmetic;
        const std::vector<Vec4f> gathered = per_corner(run_vertex_program(p, u, a.vertices), a.corner_vertex);
        const std::vector<Vec4f> per_corner = run_vertex_program(p, u, c);
        ASSERT_EQ(gathered.size(), per_corner.size());
        for (std::size_t k = 0; k < gathered.size(); ++k)
          ASSERT_TRUE(same_bits(gathered[k], per_corner[k])) << to_string(p) << " corner " << k;
      }
}

bool same_bits(const ShadowVertex& a, const ShadowVertex& b) { return std::memcmp(&a, &b, sizeof(ShadowVertex)) == 0; }

// Z-fail's caps drawn as indexed draws (shadow_methods.cpp) read the mesh's
// points and directions through the geometry's vertex indices: the caps'
// own vertices, bit for bit.
TEST(MeshVertexArray, TheCapsAreThePointsAndDirectionsOfTheirVertices) {
  for (const char* name : {"near_cap_bunny_wall.json", "case_d.json"}) {
    const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/" + name);
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      if (!scene.objects[o].occluder) continue;
      const TriangleMesh& mesh = *scene.objects[o].mesh;
      const MeshVertexArray a = mesh_vertex_array(mesh);
      const ShadowVolumeGeometry g = shadow_volume_geometry(mesh, engine_silhouette(scene, o, 0));
      ASSERT_FALSE(g.light_cap.empty()) << name;
      ASSERT_FALSE(g.dark_cap.empty()) << name;
      const std::vector<ShadowVertex> light = per_corner(a.vertices, g.light_cap_vertex),
                                      dark = per_corner(a.directions, g.dark_cap_vertex);
      ASSERT_EQ(light.size(), g.light_cap.size());
      ASSERT_EQ(dark.size(), g.dark_cap.size());
      for (std::size_t k = 0; k < light.size(); ++k) ASSERT_TRUE(same_bits(light[k], g.light_cap[k])) << name << k;
      for (std::size_t k = 0; k < dark.size(); ++k) ASSERT_TRUE(same_bits(dark[k], g.dark_cap[k])) << name << k;
    }
  }
}

}  // namespace
}  // namespace nearcap::gl
