// The hard-configuration sampler (analysis/hard_case_sampler.hpp): every
// configuration replays from (seed, index) alone, loads as a scene (or is
// rejected for a light inside an occluder, which the sampler does not avoid),
// is of the kind it says, checked exactly, and runs through the program as a
// scene file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include "cli_support.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/classification.hpp"
#include "nearcap/exact/eye_count.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "support/sampled_scenes.hpp"

namespace nearcap {
namespace {

using analysis::HardCase;
using analysis::HardCaseKind;

analysis::SamplerSpec spec(std::uint64_t seed, std::vector<HardCaseKind> kinds = analysis::all_hard_case_kinds()) {
  analysis::SamplerSpec s = test::bundled_sampler_spec(seed);
  s.kinds = std::move(kinds);
  s.width = 16;
  s.height = 12;
  return s;
}

TEST(HardCaseSampler, EveryConfigurationReplaysFromSeedAndIndexAlone) {
  const analysis::HardCaseSampler a(spec(42)), b(spec(42)), other(spec(43));
  for (std::uint64_t i : {0u, 1u, 17u, 999u}) {
    EXPECT_EQ(a.sample(i).scene_json, b.sample(i).scene_json) << i;
    EXPECT_NE(a.sample(i).scene_json, other.sample(i).scene_json) << i;
  }
  // Order does not matter: index 5 first, or after 0..4.
  const std::string direct = analysis::HardCaseSampler(spec(7)).sample(5).scene_json;
  const analysis::HardCaseSampler c(spec(7));
  for (std::uint64_t i = 0; i < 5; ++i) (void)c.sample(i);
  EXPECT_EQ(c.sample(5).scene_json, direct);
}

// A seed's configurations under the default kinds are pinned: the held-out
// evaluations (seed 4242, docs/findings/policy-oracle.md) and the findings
// tables name seeds, and a seed must keep meaning the same configurations.
// A change that moves them (a kind added to the default set, a draw
// reordered, another standard library's uniform_int_distribution) fails
// here; where that is meant, measure the findings that name seeds again and
// update the digest.
TEST(HardCaseSampler, TheDefaultKindsConfigurationsOfASeedArePinned) {
  const analysis::SamplerSpec s = test::bundled_sampler_spec(4242);
  const analysis::HardCaseSampler sampler(s);
  const std::string meshes = std::filesystem::absolute(s.mesh_directory).lexically_normal().string();
  std::uint64_t digest = 14695981039346656037ull;  // FNV-1a, 64 bits
  for (std::uint64_t i = 0; i < 200; ++i) {
    std::string json = sampler.sample(i).scene_json;
    for (std::size_t at = json.find(meshes); at != std::string::npos; at = json.find(meshes, at))
      json.replace(at, meshes.size(), "MESHES");
    ASSERT_EQ(json.find(NEARCAP_SOURCE_DIR), std::string::npos) << "a path of this checkout in the digest";
    for (unsigned char c : json) digest = (digest ^ c) * 1099511628211ull;
  }
  EXPECT_EQ(digest, 0xe61952e21f753a54ull) << std::hex << digest;
}

TEST(HardCaseSampler, KindNamesRoundTripAndUnknownOnesAreNamed) {
  for (HardCaseKind k : values_of<HardCaseKind>())
    EXPECT_EQ(analysis::hard_case_kind_from_string(analysis::to_string(k)), k);
  try {
    (void)analysis::hard_case_kind_from_string("lite-near-plane");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Usage);
    EXPECT_NE(std::string(e.what()).find("lite-near-plane"), std::string::npos);
  }
}

// EyeNearVolume: the eye within 2^-14 of the line from the light through
// a box corner or an edge's midpoint, or of the light, or the box behind
// the camera and the eye in its volume.
void eye_near_volume_is_what_it_says(const Scene& scene, const CameraSpaceScene& cs, const std::string& detail) {
  // The sampler's view is a translation by -eye.
  const Affine3d& view = scene.camera.view;
  const Vec3d eye{-view.rows[0][3], -view.rows[1][3], -view.rows[2][3]};
  const auto length = [](const Vec3d& v) { return std::sqrt(dot(v, v)); };
  const Vec3d l = scene.lights[0].position;
  if (detail.find("behind") != std::string::npos) {
    EXPECT_GT(cs.vertex_estimate(0, 0).z + cs.vertex_estimate(0, 7).z, 0.0) << "the box behind the camera";
    EXPECT_EQ(exact_eye_count(cs, 0).count, 1u);
    return;
  }
  if (detail.find("beyond") == std::string::npos) {  // "eye m*2^-e from the light"
    EXPECT_LE(length(eye - l), std::ldexp(1.0, -14));
    return;
  }
  // The box's corners and edge midpoints, world space.
  const SceneObject& box = scene.objects[0];
  std::vector<Vec3d> points;
  for (const Vec3d& p : box.mesh->positions) points.push_back(box.object_to_world.apply(p));
  for (std::size_t a = 0; a < 8; ++a)
    for (std::size_t b = a + 1; b < 8; ++b) points.push_back(0.5 * (points[a] + points[b]));
  double nearest = 1e300;
  const Vec3d d = l - eye;
  for (const Vec3d& p : points) nearest = std::min(nearest, length(cross(p - eye, d)) / length(d));
  EXPECT_LE(nearest, std::ldexp(1.0, -14)) << "the line eye -> light through a corner or an edge's midpoint";
}

// Each kind, 12 configurations: loads (or a light is inside an occluder), and
// has the property its name promises, decided exactly.
TEST(HardCaseSampler, EachKindIsWhatItSays) {
  std::vector<HardCaseKind> kinds = analysis::all_hard_case_kinds();
  for (int k = 0; k < analysis::kHardCaseKindCount; ++k)
    if (analysis::asked_for_by_name_only(static_cast<HardCaseKind>(k))) kinds.push_back(static_cast<HardCaseKind>(k));
  for (HardCaseKind kind : kinds) {
    const analysis::HardCaseSampler sampler(spec(2026, {kind}));
    int loaded = 0;
    for (std::uint64_t i = 0; i < 12; ++i) {
      const HardCase c = sampler.sample(i);
      SCOPED_TRACE(std::string(analysis::to_string(kind)) + " #" + std::to_string(i) + ": " + c.detail);
      ASSERT_EQ(c.kind, kind);
      Scene scene;
      try {
        scene = parse_scene(c.scene_json, "sampled", ".");
      } catch (const Error& e) {
        ASSERT_EQ(e.kind(), ErrorKind::Light) << e.what();
        continue;
      }
      ++loaded;
      const CameraSpaceScene cs(scene);
      const Rational light_to_near = cs.exact_light(0).z + Rational(scene.camera.frustum.near);
      std::size_t occluders = 0;
      for (const SceneObject& o : scene.objects) occluders += o.occluder;
      switch (kind) {
        case HardCaseKind::LightNearNearPlane: {
          const Rational d = abs(light_to_near);
          EXPECT_GT(sgn(d), 0);
          EXPECT_LE(d, Rational(0.5));
          EXPECT_EQ(d.get_num(), 1) << "a power of two: " << d;  // 2^-k exactly
          break;
        }
        case HardCaseKind::LightInNearPlane:
          EXPECT_EQ(sgn(light_to_near), 0);
          EXPECT_TRUE(classify_scene(cs).lights[0].light_in_near_plane);
          break;
        case HardCaseKind::Grazing:
          EXPECT_GT(classify_scene(cs).lights[0].objects[0].edge_on_triangles, 0u);
          break;
        case HardCaseKind::EyeInShadow: {
          const PixelReference ref = compute_pixel_reference(cs, 0);
          EXPECT_GT(*std::max_element(ref.cap.begin(), ref.cap.end()), 0u) << "the near rectangle is in shadow";
          break;
        }
        case HardCaseKind::FarFromOrigin: {
          const Vec3d& l = scene.lights[0].position;
          EXPECT_GE(std::max({std::fabs(l.x), std::fabs(l.y), std::fabs(l.z)}), 999000.0);
          break;
        }
        case HardCaseKind::TinyNear:
          EXPECT_LE(scene.camera.frustum.near, std::ldexp(1.0, -10));
          break;
        case HardCaseKind::Straddling: {
          int before = 0, beyond = 0;
          const Rational near(scene.camera.frustum.near);
          for (std::size_t v = 0; v < scene.objects[0].mesh->positions.size(); ++v) {
            const int s = sgn(Rational(cs.exact_vertex(0, static_cast<VertexIndex>(v)).z + near));
            before += s > 0;
            beyond += s < 0;
          }
          EXPECT_GT(before, 0);
          EXPECT_GT(beyond, 0);
          break;
        }
        case HardCaseKind::SeveralOccluders:
          EXPECT_GE(occluders, 2u);
          break;
        case HardCaseKind::SeveralLights:
          EXPECT_GE(scene.lights.size(), 2u);
          break;
        case HardCaseKind::RealMesh:
          EXPECT_GT(scene.objects[0].mesh->triangle_count(), 12u);
          break;
        case HardCaseKind::EyeNearVolume:
          eye_near_volume_is_what_it_says(scene, cs, c.detail);
          break;
        case HardCaseKind::FarLight: {
          // The distance from the box's centre its detail names (10^k or
          // 2^k), to rounding.
          const Vec3d centre = scene.objects[0].object_to_world.apply(Vec3d{0, 0, 0});
          const Vec3d to_light = scene.lights[0].position - centre;
          const std::size_t at = c.detail.find("light ") + 6;
          const bool decimal = c.detail.compare(at, 2, "1e") == 0;
          const int k = std::stoi(c.detail.substr(at + 2));
          const double named = decimal ? std::pow(10.0, k) : std::ldexp(1.0, k);
          EXPECT_NEAR(std::sqrt(dot(to_light, to_light)) / named, 1.0, 1e-9);
          EXPECT_GE(named, 100.0);
          break;
        }
      }
    }
    std::printf("  %-20s %d of 12 loaded\n", std::string(analysis::to_string(kind)).c_str(), loaded);
    EXPECT_GE(loaded, 6) << analysis::to_string(kind) << ": most configurations load";
  }
}

TEST(HardCaseSampler, AConfigurationWrittenOutRunsThroughTheProgram) {
  const analysis::HardCaseSampler sampler(spec(5));
  const auto dir = std::filesystem::temp_directory_path() / ("nearcap_sampler_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  int ran = 0;
  for (std::uint64_t i = 0; i < 6; ++i) {
    const auto file = dir / ("case" + std::to_string(i) + ".json");
    std::ofstream(file) << sampler.sample(i).scene_json;
    const test::CliResult r =
        test::run_cli("cracks " + file.string() + " --light 0 --method zpplus-corrected", "sampler");
    EXPECT_TRUE(r.exit_code == 0 || (r.exit_code == 2 && r.err.find("error (light)") != std::string::npos))
        << r.exit_code << " " << r.err;
    ran += r.exit_code == 0;
  }
  EXPECT_GT(ran, 0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace nearcap
