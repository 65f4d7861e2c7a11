// The exact reference's eye side kept across lights and frames
// (eye_setup.hpp): frames that share an EyeSetupCache (and a LightSetupCache),
// the camera moving, then the light, then an object, then the near distance,
// give every frame the reference a fresh tracer gives, and the grids still
// agree with brute force on every pixel; the lights of one frame share one
// eye side.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <tbb/task_group.h>

#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "nearcap/exact/crack_distance.hpp"
#include "nearcap/exact/eye_setup.hpp"
#include "nearcap/exact/light_setup.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "random_scene.hpp"
#include "support/cached_reference_frames.hpp"

namespace nearcap {
namespace {

using test::ReferenceFrame;
using test::same_reference;

// The proven status over the square of half-width `half_width` pixels around
// every pixel centre (the crack distance's question), as one list.
std::vector<std::optional<bool>> proven_statuses(const PixelReferenceTracer& tracer, std::int64_t half_width) {
  const Camera& camera = tracer.scene().scene().camera;
  std::vector<std::optional<bool>> out;
  for (int j = 0; j < camera.height; ++j)
    for (int i = 0; i < camera.width; ++i)
      out.push_back(
          tracer.proven_status_over_square(crack_square_centre(i, j), half_width << kCrackDistanceShift, nullptr));
  return out;
}

// The frames of one property case: still, the camera moved, the light moved
// (the camera as before), the first box moved, the near distance moved.
std::vector<ReferenceFrame> frames_of(test::RandomSceneParams p) {
  std::vector<ReferenceFrame> frames;
  frames.push_back({"first frame", test::random_scene_json(p)});
  p.eye16[0] += 3;
  p.eye16[1] -= 2;
  frames.push_back({"camera moved", test::random_scene_json(p)});
  p.light16[0] += 24;
  p.light16[2] -= 16;
  frames.push_back({"light moved", test::random_scene_json(p)});
  p.box_centres16[0][0] += 5;
  frames.push_back({"object moved", test::random_scene_json(p)});
  p.near64 += 3;
  frames.push_back({"near moved", test::random_scene_json(p)});
  return frames;
}

RC_GTEST_PROP(EyeSetupCache, FramesSharingTheCacheEqualFreshReferences, ()) {
  const std::vector<ReferenceFrame> frames = frames_of(*test::random_scene_params());
  MeshCache meshes;
  const std::vector<Scene> scenes = test::parse_reference_frames(frames, meshes);
  LightSetupCache light_setups;
  EyeSetupCache eye_setups;
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    RC_LOG() << frames[k].what << "\n";
    const CameraSpaceScene cs(scenes[k]);
    const PixelReferenceTracer cached(cs, 0, &light_setups, &eye_setups), fresh(cs, 0);
    test::rc_assert_cached_equals_fresh(cached, fresh);
    RC_ASSERT(proven_statuses(cached, 1) == proven_statuses(fresh, 1));
  }
  // Built for the first frame and for each move of the camera, an object or
  // the near distance; reused when only the light moved.
  const EyeSetupCache::Counts n = eye_setups.counts();
  RC_ASSERT(n.builds == 4u);
  RC_ASSERT(n.hits == 1u);
}

// A box 0.3 in front of the eye, before the near plane of the first frame
// (0.5) and beyond that of the second (0.125, the same field of view): the
// triangles wholly before the near plane are part of the eye side (the crack
// distance skips them), so a moved near distance must build it anew.  The
// squares on the box's outline, whose centres see the wall behind, are proven
// only when the box is taken as before the near plane.
TEST(EyeSetupCache, NearDistanceIsPartOfTheKey) {
  test::RandomSceneParams p;
  p.box_centres16 = {{0, 0, 32 - 5}};  // 5/16 in front of the eye
  p.box_scales16 = {2};                // 1/8 wide
  p.box_rotations_deg = {{0, 0, 0}};
  p.light16 = {0, 80, 0};
  p.eye16 = {0, 0, 32};
  p.width = 24;
  p.height = 18;
  p.near64 = 32;
  p.half_width64 = 16;
  MeshCache meshes;  // one mesh object for both frames, as a sweep has it
  const Scene far_near = parse_scene(test::random_scene_json(p), "near 0.5", ".", &meshes);
  p.near64 = 8;
  p.half_width64 = 4;
  const Scene close_near = parse_scene(test::random_scene_json(p), "near 0.125", ".", &meshes);

  EyeSetupCache eye_setups;
  const CameraSpaceScene first(far_near), second(close_near);
  const PixelReferenceTracer before(first, 0, nullptr, &eye_setups);
  const PixelReferenceTracer cached(second, 0, nullptr, &eye_setups), fresh(second, 0);
  // The box is seen in the second frame only.
  std::size_t box_pixels = 0;
  const PixelReference second_ref = compute_pixel_reference(fresh);
  for (std::int32_t o : second_ref.object) box_pixels += o == 0;
  EXPECT_GT(box_pixels, 0u);
  for (std::int32_t o : compute_pixel_reference(before).object) EXPECT_NE(o, 0);

  EXPECT_TRUE(same_reference(compute_pixel_reference(cached), second_ref));
  for (std::int64_t half_width : {1, 2, 3}) {
    const std::vector<std::optional<bool>> a = proven_statuses(cached, half_width),
                                           b = proven_statuses(fresh, half_width);
    std::size_t differ = 0;
    for (std::size_t k = 0; k < a.size(); ++k) differ += a[k] != b[k];
    EXPECT_EQ(differ, 0u) << "squares of half-width " << half_width;
  }
  const EyeSetupCache::Counts n = eye_setups.counts();
  EXPECT_EQ(n.builds, 2u);
  EXPECT_EQ(n.hits, 0u);
}

// A bundled mesh scene with a second light: the two lights of a frame share
// one eye side, a frame whose light moved reuses it, a moved camera builds it
// anew; every reference equals a fresh tracer's.
TEST(EyeSetupCache, BundledSceneLightsShareTheEyeSide) {
  MeshCache meshes;
  LightSetupCache light_setups;
  EyeSetupCache eye_setups;
  const std::string path = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/twisted.json";
  std::ifstream in(path);
  nlohmann::json j = nlohmann::json::parse(in);
  j["camera"]["width"] = 40;
  j["camera"]["height"] = 30;
  nlohmann::json second = j["lights"][0];
  second["position"][0] = second["position"][0].get<double>() - 1.5;
  j["lights"].push_back(second);
  const std::string base = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes";
  std::size_t shadowed = 0;
  auto frame = [&](const char* what) {
    SCOPED_TRACE(what);
    const Scene scene = parse_scene(j.dump(), what, base, &meshes);
    const CameraSpaceScene cs(scene);
    for (std::size_t light = 0; light < scene.lights.size(); ++light) {
      SCOPED_TRACE("light " + std::to_string(light));
      const PixelReferenceTracer cached(cs, light, &light_setups, &eye_setups), fresh(cs, light);
      const PixelReference a = compute_pixel_reference(cached), b = compute_pixel_reference(fresh);
      EXPECT_TRUE(same_reference(a, b));
      for (std::size_t p = 0; p < a.stencil.size(); ++p)
        shadowed += a.stencil[p] != PixelReference::kNothingSeen && a.stencil[p] > 0;
      EXPECT_EQ(proven_statuses(cached, 2), proven_statuses(fresh, 2));
    }
  };
  frame("first frame");
  j["lights"][0]["position"][2] = j["lights"][0]["position"][2].get<double>() + 0.5;
  frame("light moved");
  j["camera"]["eye"][0] = 0.35;
  j["camera"]["target"][1] = -0.45;
  frame("camera moved");
  EXPECT_GT(shadowed, 0u) << "the frames have shadowed pixels";
  const EyeSetupCache::Counts n = eye_setups.counts();
  EXPECT_EQ(n.builds, 2u);
  EXPECT_EQ(n.hits, 4u);
}

// An eye setup built in a task group that is cancelled meanwhile (as TBB
// cancels a group when a task of it throws: its nested loops stop taking
// iterations and return as if done) is whole in the cache all the same: the
// frame's next light reads what a fresh build gives.
TEST(EyeSetupCache, ABuildInACancelledGroupIsWholeInTheCache) {
  MeshCache meshes;
  const Scene scene = test::bundled_scene_at("bunny", 32, 24, meshes);
  const CameraSpaceScene cs(scene);
  EyeSetupCache cache;
  tbb::task_group_context group_context;
  tbb::task_group group(group_context);
  group.run_and_wait([&] {
    group_context.cancel_group_execution();
    eye_setup(cs, &cache);
  });
  ASSERT_EQ(cache.counts().builds, 1u);
  const PixelReferenceTracer from_cache(cs, 0, nullptr, &cache), built(cs, 0);
  EXPECT_EQ(cache.counts().hits, 1u);
  EXPECT_TRUE(same_reference(compute_pixel_reference(from_cache), compute_pixel_reference(built)));
}

}  // namespace
}  // namespace nearcap
