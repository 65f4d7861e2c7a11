// The exact reference's light side kept across frames (light_setup.hpp): a
// sequence of frames that share one cache, the camera moving, then the light,
// then an object, gives every frame the reference a fresh tracer gives, and
// the grids still agree with brute force on every pixel.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>
#include <tbb/task_group.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "nearcap/exact/light_setup.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "random_scene.hpp"
#include "support/cached_reference_frames.hpp"

namespace nearcap {
namespace {

using test::ReferenceFrame;
using test::same_reference;

// One frame's JSON with the camera turned by `degrees` about its y axis
// after the translation (the view's rotation part is no longer the identity).
std::string turned(const std::string& json, double degrees) {
  nlohmann::json j = nlohmann::json::parse(json);
  const double c = std::cos(degrees * M_PI / 180), s = std::sin(degrees * M_PI / 180);
  auto& v = j["camera"]["view"];
  const double t[3] = {v[0][3].get<double>(), v[1][3].get<double>(), v[2][3].get<double>()};
  v = {{c, 0, s, c * t[0] + s * t[2]}, {0, 1, 0, t[1]}, {-s, 0, c, -s * t[0] + c * t[2]}, {0, 0, 0, 1}};
  return j.dump();
}

// The frames of one property case: still, the camera moved twice, the light
// moved, the first box moved.
std::vector<ReferenceFrame> frames_of(test::RandomSceneParams p) {
  std::vector<ReferenceFrame> frames;
  frames.push_back({"first frame", test::random_scene_json(p)});
  p.eye16[0] += 3;
  frames.push_back({"camera moved", test::random_scene_json(p)});
  p.eye16[1] -= 2;
  frames.push_back({"camera moved and turned", turned(test::random_scene_json(p), 10)});
  p.light16[0] += 24;
  p.light16[2] -= 16;
  frames.push_back({"light moved", turned(test::random_scene_json(p), 10)});
  p.box_centres16[0][0] += 5;
  frames.push_back({"object moved", turned(test::random_scene_json(p), 10)});
  return frames;
}

RC_GTEST_PROP(LightSetupCache, FramesSharingTheCacheEqualFreshReferences, ()) {
  const std::vector<ReferenceFrame> frames = frames_of(*test::random_scene_params());
  MeshCache meshes;
  const std::vector<Scene> scenes = test::parse_reference_frames(frames, meshes);
  LightSetupCache cache;
  std::size_t occluders = 0;
  for (const SceneObject& o : scenes.front().objects) occluders += o.occluder ? 1 : 0;
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    RC_LOG() << frames[k].what << "\n";
    const CameraSpaceScene cs(scenes[k]);
    const PixelReferenceTracer cached(cs, 0, &cache), fresh(cs, 0);
    test::rc_assert_cached_equals_fresh(cached, fresh);
  }
  // Built for the first frame, reused for the two camera moves, built again
  // for the moved light and the moved box; the moved box's facing alone is
  // computed again, the other boxes' are reused.
  const LightSetupCache::Counts n = cache.counts();
  RC_ASSERT(n.setup_builds == 3u);
  RC_ASSERT(n.setup_hits == 2u);
  RC_ASSERT(n.facing_builds == 2 * occluders + 1);
  RC_ASSERT(n.facing_hits == occluders - 1);
}

// A bundled mesh scene along a few frames of the same kind, at a small
// resolution: the cached and fresh references agree on every frame.
TEST(LightSetupCache, BundledSceneFramesEqualFreshReferences) {
  MeshCache meshes;
  LightSetupCache cache;
  const std::string path = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/twisted.json";
  std::ifstream in(path);
  nlohmann::json j = nlohmann::json::parse(in);
  j["camera"]["width"] = 40;
  j["camera"]["height"] = 30;
  const std::string base = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes";
  auto frame = [&](const char* what) {
    SCOPED_TRACE(what);
    const Scene scene = parse_scene(j.dump(), what, base, &meshes);
    const CameraSpaceScene cs(scene);
    const PixelReferenceTracer cached(cs, 0, &cache), fresh(cs, 0);
    const PixelReference a = compute_pixel_reference(cached), b = compute_pixel_reference(fresh);
    EXPECT_TRUE(same_reference(a, b));
    std::size_t shadowed = 0;
    for (std::size_t p = 0; p < a.stencil.size(); ++p)
      shadowed += a.stencil[p] != PixelReference::kNothingSeen && a.stencil[p] > 0;
    return shadowed;
  };
  const std::size_t still = frame("first frame");
  j["camera"]["eye"][0] = 0.35;
  j["camera"]["target"][1] = -0.45;
  frame("camera moved");
  j["lights"][0]["position"][0] = -1.0;
  frame("light moved");
  j["objects"][0]["translate"][0] = 0.25;
  frame("object moved");
  EXPECT_GT(still, 0u) << "the first frame has shadowed pixels";
  const LightSetupCache::Counts n = cache.counts();
  EXPECT_EQ(n.setup_builds, 3u);
  EXPECT_EQ(n.setup_hits, 1u);
}

// Threads that ask for the same light setup at once (a sweep's first
// configurations on every core) get one setup, built once: the first
// builds it and the others join that build.  The bunny's light setup takes
// long enough (tens of milliseconds) that threads started together overlap
// it.
TEST(LightSetupCache, ThreadsAskingAtOnceShareOneBuild) {
  MeshCache meshes;
  const Scene scene = test::bundled_scene_at("bunny", 8, 6, meshes);
  const CameraSpaceScene cs(scene);
  LightSetupCache cache;
  constexpr int kThreads = 4;
  std::vector<std::shared_ptr<const LightSetup>> got(kThreads);
  std::atomic<int> ready{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      ++ready;
      while (ready.load() < kThreads) std::this_thread::yield();
      got[t] = light_setup(cs, 0, &cache);
    });
  for (std::thread& t : threads) t.join();
  for (int t = 0; t < kThreads; ++t) {
    ASSERT_NE(got[t], nullptr);
    EXPECT_EQ(got[t].get(), got[0].get()) << "thread " << t;
  }
  const LightSetupCache::Counts n = cache.counts();
  EXPECT_EQ(n.setup_builds, 1u);
  EXPECT_EQ(n.setup_hits, static_cast<std::size_t>(kThreads - 1));
  EXPECT_FALSE(got[0]->lit.empty());
}

// A light setup built in a task group that is cancelled meanwhile (as TBB
// cancels a group when a task of it throws: its nested loops stop taking
// iterations and return as if done) is whole in the cache all the same:
// the next frame's setup and reference are a fresh build's.
TEST(LightSetupCache, ABuildInACancelledGroupIsWholeInTheCache) {
  MeshCache meshes;
  const Scene scene = test::bundled_scene_at("bunny", 32, 24, meshes);
  const CameraSpaceScene cs(scene);
  LightSetupCache cache;
  tbb::task_group_context group_context;
  tbb::task_group group(group_context);
  group.run_and_wait([&] {
    group_context.cancel_group_execution();
    light_setup(cs, 0, &cache);
  });
  ASSERT_EQ(cache.counts().setup_builds, 1u);
  const std::shared_ptr<const LightSetup> cached = light_setup(cs, 0, &cache), fresh = light_setup(cs, 0);
  EXPECT_EQ(cache.counts().setup_hits, 1u);
  EXPECT_EQ(cached->lit, fresh->lit);
  const PixelReferenceTracer from_cache(cs, 0, &cache), built(cs, 0);
  EXPECT_TRUE(same_reference(compute_pixel_reference(from_cache), compute_pixel_reference(built)));
}

// WorldDirections: the world direction's estimate lies within its bound of
// the exact V^-1 w (Cramer's rule over rationals) for turned views.
TEST(WorldDirections, BoundHoldsForTurnedViews) {
  for (int k = 0; k < 50; ++k) {
    const double a = 0.37 * k, b = 0.11 * k + 0.2;
    const Camera cam = look_at_camera({std::cos(a) * 3, std::sin(b), std::sin(a) * 3 + 0.1 * k}, {0.1, -0.2, 0.05},
                                      {0, 1, 0}, 60, 0.1, 100, 4, 3);
    const WorldDirections map(cam.view);
    const Vec3d w{0.3 - 0.01 * k, -1.7 + 0.05 * k, 2.5};
    double err = 0;
    const Vec3d y = map.apply(w, 0.0, err);
    ASSERT_TRUE(std::isfinite(err));
    // Exact V^-1 w by Cramer's rule over rationals.
    Rational m[3][3];
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 3; ++c) m[i][c] = cam.view.rows[i][c];
    auto det3 = [](const Rational(&q)[3][3]) {
      return Rational(q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) -
                      q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
                      q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0]));
    };
    const Rational det = det3(m);
    const Rational wr[3] = {w.x, w.y, w.z};
    for (int c = 0; c < 3; ++c) {
      Rational q[3][3];
      for (int i = 0; i < 3; ++i)
        for (int cc = 0; cc < 3; ++cc) q[i][cc] = cc == c ? wr[i] : m[i][cc];
      const Rational exact = det3(q) / det;
      const Rational diff = Rational(y[c]) - exact;
      EXPECT_NE(sign_of(Rational(Rational(err) - diff)), Sign::Negative) << "view " << k << ", coordinate " << c;
      EXPECT_NE(sign_of(Rational(Rational(err) + diff)), Sign::Negative) << "view " << k << ", coordinate " << c;
    }
    EXPECT_LT(err, 1e-12) << "a usable bound";
  }
}

}  // namespace
}  // namespace nearcap
