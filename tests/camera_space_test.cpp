// CameraSpaceScene: its orientation sign and its exact side, which it composes
// only when asked (exact_vertex, exact_light), once for all threads.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/io/mesh_file.hpp"
#include "nearcap/io/scene_builder.hpp"

namespace nearcap {
namespace {

TriangleMesh unit_box() { return read_mesh(std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/box.off"); }

Affine3d linear(const std::array<std::array<double, 3>, 3>& rows, const Vec3d& at) {
  Affine3d a;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) a.rows[i][j] = rows[i][j];
    a.rows[i][3] = at[i];
  }
  return a;
}

bool same(const RationalVec3& a, const RationalVec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// The sign of view * object_to_world's linear part, from rationals alone.
Sign exact_handedness(const Scene& scene, std::size_t o) {
  return RationalAffine::from(scene.objects[o].object_to_world)
      .then(RationalAffine::from(scene.camera.view))
      .linear_determinant_sign();
}

TEST(CameraSpaceScene, HandednessIsTheSignOfTheExactMapsDeterminant) {
  std::vector<std::array<std::array<double, 3>, 3>> maps{
      {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
      {{{0, 1, 0}, {1, 0, 0}, {0.5, 0, 1}}},  // mirrored: determinant -1
      // Nearly singular, either sign: the third row is the sum of the first
      // two (dyadic, so exactly) but for +-2^-52 in z.  The determinant,
      // +-2^-52 times 19/32 times the view's (a rotation's, positive), is
      // below the rounding of the composed map's entries, so the float
      // filter cannot decide it.
      {{{0.75, 0.25, 0.125}, {0.25, 0.875, 0.375}, {1.0, 1.125, 0.5 + 0x1p-52}}},
      {{{0.75, 0.25, 0.125}, {0.25, 0.875, 0.375}, {1.0, 1.125, 0.5 - 0x1p-52}}},
  };
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> entry(-1, 1);
  for (int k = 0; k < 40; ++k) {
    std::array<std::array<double, 3>, 3> m{};
    for (auto& row : m)
      for (double& x : row) x = entry(rng);
    maps.push_back(m);
  }
  SceneBuilder b("handedness");
  b.camera(look_at_camera({0.3, 2.1, 7.7}, {0.1, -0.2, 0.05}, {0, 1, 0}, 55, 0.1, 100, 32, 24));
  b.light({0.5, 40, 3});
  for (std::size_t k = 0; k < maps.size(); ++k)
    b.receiver(unit_box(), linear(maps[k], {0.25 * static_cast<double>(k), 0, -3}));
  const Scene scene = b.build();
  const CameraSpaceScene cs(scene);
  int negative = 0;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    EXPECT_EQ(cs.handedness(o), exact_handedness(scene, o)) << "object " << o;
    negative += cs.handedness(o) == Sign::Negative;
  }
  EXPECT_EQ(cs.handedness(1), Sign::Negative);
  EXPECT_EQ(cs.handedness(2), Sign::Positive);
  EXPECT_EQ(cs.handedness(3), Sign::Negative);
  EXPECT_GT(negative, 10);
}

TEST(CameraSpaceScene, ExactVerticesAndLightsAreTheComposedMapsFromEveryThreadAtOnce) {
  SceneBuilder b("exact side");
  b.camera(look_at_camera({0.3, 2.1, 7.7}, {0.1, -0.2, 0.05}, {0, 1, 0}, 55, 0.1, 100, 32, 24));
  b.light({0.5, 40, 3});
  b.light({-9.25, 12.5, 0.1});
  b.object(unit_box(), linear({{{0.6, 0.1, 0}, {0, 0.7, 0.2}, {0.1, 0, 0.9}}}, {0.3, 0.1, -0.7}));
  b.receiver(unit_box(), linear({{{5, 0, 0}, {0, 0.5, 0}, {0, 0, 5}}}, {0, -2, 0}));
  const Scene scene = b.build();
  const RationalAffine view = RationalAffine::from(scene.camera.view);
  const CameraSpaceScene cs(scene);
  // Four threads ask for the exact side at the same time, its first use.
  std::vector<int> mismatches(4, 0);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < mismatches.size(); ++t)
    threads.emplace_back([&, t] {
      for (std::size_t k = 0; k < scene.lights.size(); ++k)
        mismatches[t] += !same(cs.exact_light(k), view.apply(to_rational(scene.lights[k].position)));
      for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        const RationalAffine map = RationalAffine::from(scene.objects[o].object_to_world).then(view);
        const TriangleMesh& mesh = *scene.objects[o].mesh;
        for (std::size_t v = 0; v < mesh.positions.size(); ++v)
          mismatches[t] +=
              !same(cs.exact_vertex(o, static_cast<VertexIndex>(v)), map.apply(to_rational(mesh.positions[v])));
      }
    });
  for (std::thread& t : threads) t.join();
  for (std::size_t t = 0; t < mismatches.size(); ++t) EXPECT_EQ(mismatches[t], 0) << "thread " << t;
  // And each estimate lies within its bound of the exact vertex.
  for (std::size_t o = 0; o < scene.objects.size(); ++o)
    for (std::size_t v = 0; v < scene.objects[o].mesh->positions.size(); ++v) {
      const RationalVec3 exact = cs.exact_vertex(o, static_cast<VertexIndex>(v));
      const Vec3d& estimate = cs.vertex_estimate(o, static_cast<VertexIndex>(v));
      for (int i = 0; i < 3; ++i)
        EXPECT_LE(std::fabs(to_double(exact[i] - Rational(estimate[i]))), cs.max_error(o)) << o << " " << v;
    }
}

}  // namespace
}  // namespace nearcap
