// An occluder's facing under a light and the cache a renderer's frame loop
// keeps of it (analysis/occluder_facing.hpp): a kept facing is the one
// computed afresh, computed once while the mesh and the light stay put,
// again when the light moves or the pair was dropped, and the decision is
// the same with the cache as without it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../src/analysis/affine_inverse.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/occluder_facing.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/exact/camera_space.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap {
namespace {

void expect_same_facing(const analysis::OccluderFacing& a, const analysis::OccluderFacing& b, const std::string& what) {
  EXPECT_EQ(a.front, b.front) << what;
  EXPECT_EQ(a.light_facing, b.light_facing) << what;
  EXPECT_EQ(a.edges, b.edges) << what;
}

Vec3d light_in_object_space(const Scene& s, std::size_t o) {
  return analysis::inverse_apply(s.objects[o].object_to_world, s.lights[0].position);
}

// fly_around's frames share their meshes (one MeshCache), and its light and
// occluders stay put: one facing per occluder for the whole path.
TEST(FacingCache, KeepsAFacingWhileTheMeshAndTheLightStayPut) {
  const analysis::CameraPath path =
      analysis::load_camera_path(std::string(NEARCAP_SOURCE_DIR) + "/data/paths/fly_around.json");
  MeshCache meshes;
  analysis::FacingCache cache;
  std::size_t occluders = 0;
  for (int f = 0; f < path.frames; f += 9) {
    const Scene s = parse_scene(analysis::path_frame_json(path, f), "fly_around", ".", &meshes);
    occluders = 0;
    for (std::size_t o = 0; o < s.objects.size(); ++o) {
      if (!s.objects[o].occluder) continue;
      ++occluders;
      const Vec3d l = light_in_object_space(s, o);
      expect_same_facing(cache.facing(s.objects[o].mesh, l), analysis::occluder_facing(*s.objects[o].mesh, l),
                         "frame " + std::to_string(f) + " object " + std::to_string(o));
    }
  }
  ASSERT_GT(occluders, 0u);
  EXPECT_EQ(cache.computed(), occluders);
}

// A light that moves: each position computed once, its facing its own.
TEST(FacingCache, ComputesAgainWhereTheLightMoves) {
  Scene s = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/room.json");
  std::size_t o = 0;
  while (!s.objects[o].occluder) ++o;
  analysis::FacingCache cache;
  std::vector<std::vector<std::uint8_t>> fronts;
  for (int step = 0; step < 4; ++step) {
    const Vec3d l = light_in_object_space(s, o);
    const analysis::OccluderFacing& kept = cache.facing(s.objects[o].mesh, l);
    expect_same_facing(kept, analysis::occluder_facing(*s.objects[o].mesh, l), "step " + std::to_string(step));
    EXPECT_EQ(cache.computed(), static_cast<std::size_t>(step + 1));
    fronts.push_back(kept.front);
    cache.facing(s.objects[o].mesh, l);  // asked again at once: kept
    EXPECT_EQ(cache.computed(), static_cast<std::size_t>(step + 1));
    s.lights[0].position.x += 1.5;
  }
  EXPECT_NE(fronts.front(), fronts.back());  // the torus's facing changed as the light moved
}

// More pairs than it keeps: the one asked for longest ago is dropped.
TEST(FacingCache, DropsThePairUsedLongestAgo) {
  const Scene s = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/default.json");
  std::size_t o = 0;
  while (!s.objects[o].occluder) ++o;
  const auto& mesh = s.objects[o].mesh;
  analysis::FacingCache cache;
  auto light = [](std::size_t k) { return Vec3d{0.5 + static_cast<double>(k), 7, 0.25}; };
  for (std::size_t k = 0; k < analysis::FacingCache::kKept; ++k) cache.facing(mesh, light(k));
  EXPECT_EQ(cache.computed(), analysis::FacingCache::kKept);
  cache.facing(mesh, light(0));  // kept, and now the newest
  EXPECT_EQ(cache.computed(), analysis::FacingCache::kKept);
  cache.facing(mesh, light(analysis::FacingCache::kKept));  // a new pair: light(1) is dropped
  EXPECT_EQ(cache.computed(), analysis::FacingCache::kKept + 1);
  cache.facing(mesh, light(0));
  EXPECT_EQ(cache.computed(), analysis::FacingCache::kKept + 1);
  expect_same_facing(cache.facing(mesh, light(1)), analysis::occluder_facing(*mesh, light(1)), "light 1 again");
  EXPECT_EQ(cache.computed(), analysis::FacingCache::kKept + 2);
}

// The shipped policy's decisions along near_plane_sweep, with one cache for
// the path and without: the same methods, prices and predicted frame time.
TEST(FacingCache, TheDecisionIsTheSameWithTheCache) {
  const analysis::SwitchPolicy policy = analysis::load_policy(std::string(NEARCAP_SOURCE_DIR) + "/data/policy.json");
  ASSERT_TRUE(policy.device_profile.has_value());
  const analysis::CameraPath path =
      analysis::load_camera_path(std::string(NEARCAP_SOURCE_DIR) + "/data/paths/near_plane_sweep.json");
  MeshCache meshes;
  analysis::FacingCache cache;
  for (int f = 0; f < path.frames; f += 3) {
    const Scene s = parse_scene(analysis::path_frame_json(path, f), "near_plane_sweep", ".", &meshes);
    const CameraSpaceScene cs(s);
    for (std::size_t light = 0; light < s.lights.size(); ++light) {
      const analysis::PolicyDecision with = analysis::decide(policy, cs, light, {}, &cache);
      const analysis::PolicyDecision without = analysis::decide(policy, cs, light, {});
      const std::string what = "frame " + std::to_string(f) + " light " + std::to_string(light);
      EXPECT_EQ(with.object_methods, without.object_methods) << what;
      EXPECT_EQ(with.predicted_ms, without.predicted_ms) << what;
      for (std::size_t o = 0; o < s.objects.size(); ++o) EXPECT_EQ(with.reason(o), without.reason(o)) << what;
    }
  }
  EXPECT_LE(cache.computed(), 2u);
}

}  // namespace
}  // namespace nearcap
