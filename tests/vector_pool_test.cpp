// Grid storage kept across builds (src/exact/vector_pool.hpp): a vector taken
// from a pool is empty whatever the build before left in it, and a grid, or
// a frame of the exact reference, built in storage that earlier builds for
// other triangles and other cameras gave back lists and decides exactly what
// one built in fresh storage does.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "../src/exact/vector_pool.hpp"
#include "nearcap/exact/central_grid.hpp"
#include "nearcap/exact/crack_distance.hpp"
#include "nearcap/exact/eye_setup.hpp"
#include "nearcap/exact/light_setup.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/io/scene_file.hpp"
#include "support/cached_reference_frames.hpp"

namespace nearcap {
namespace {

// Sets whether pools reuse storage for the lifetime of this object.
class ReuseSwitch {
 public:
  explicit ReuseSwitch(bool reuse) : before_(vector_reuse_enabled().exchange(reuse)) {}
  ~ReuseSwitch() { vector_reuse_enabled() = before_; }
  ReuseSwitch(const ReuseSwitch&) = delete;
  ReuseSwitch& operator=(const ReuseSwitch&) = delete;

 private:
  bool before_;
};

// Element type of its own, so that no other code's vectors share the pool.
struct Item {
  int value;
};

TEST(VectorPool, ATakenVectorIsEmptyAndHasTheStorageGivenBack) {
  release_kept_vectors();  // all pools together keep at most kMaxKeptBytes
  const ReuseSwitch reuse(true);
  VectorPool<Item>& pool = VectorPool<Item>::instance();
  std::vector<Item> v(1000, Item{7});
  const Item* storage = v.data();
  pool.give(v);
  EXPECT_TRUE(v.empty());
  const std::vector<Item> taken = pool.take(600);
  EXPECT_TRUE(taken.empty());
  EXPECT_GE(taken.capacity(), 1000u);
  EXPECT_EQ(taken.data(), storage);
  // Nothing kept holds 2000: a new one.
  std::vector<Item> larger = pool.take(2000);
  EXPECT_TRUE(larger.empty());
  EXPECT_GE(larger.capacity(), 2000u);
}

TEST(VectorPool, PoolsTogetherKeepAtMostTheirBound) {
  release_kept_vectors();
  EXPECT_EQ(vector_pools_kept_bytes().load(), 0u);
  const ReuseSwitch reuse(true);
  constexpr std::size_t kLarge = VectorPool<Item>::kMaxKeptBytes / sizeof(Item) / 3;
  for (int k = 0; k < 5; ++k) {
    std::vector<Item> v(kLarge);
    VectorPool<Item>::instance().give(v);
    std::vector<double> w(kLarge * sizeof(Item) / sizeof(double));
    VectorPool<double>::instance().give(w);
  }
  EXPECT_LE(vector_pools_kept_bytes().load(), VectorPool<Item>::kMaxKeptBytes);
  EXPECT_GE(vector_pools_kept_bytes().load(), VectorPool<Item>::kMaxKeptBytes / 2);
  release_kept_vectors();
  EXPECT_EQ(vector_pools_kept_bytes().load(), 0u);
}

TEST(VectorPool, SwitchedOffItKeepsNothing) {
  release_kept_vectors();
  VectorPool<Item>& pool = VectorPool<Item>::instance();
  std::vector<Item> v(1000, Item{7});
  {
    const ReuseSwitch reuse(false);
    pool.give(v);
    EXPECT_TRUE(v.empty());
  }
  std::vector<Item> w(1000, Item{8});
  const Item* storage = w.data();
  {
    const ReuseSwitch reuse(true);
    pool.give(w);
  }
  const ReuseSwitch reuse(false);
  const std::vector<Item> fresh = pool.take(1000);
  EXPECT_NE(fresh.data(), storage);  // that one is still kept
  EXPECT_TRUE(fresh.empty());
}

// Triangles around a centre (as central_grid_test.cpp's fixture).
std::vector<CentralGrid::Triangle> shell(std::mt19937& rng, const Vec3d& centre, int count) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(0.01, 0.5), radius(0.5, 4.0);
  std::vector<CentralGrid::Triangle> out;
  for (int i = 0; i < count; ++i) {
    Vec3d dir{unit(rng), unit(rng), unit(rng)};
    if (i % 3 == 0) dir.y = std::copysign(std::fabs(dir.x), dir.y);
    const double r = radius(rng) / std::sqrt(dot(dir, dir));
    const double s = (i % 17 == 0) ? 3.0 : size(rng);
    CentralGrid::Triangle t;
    for (auto& v : t.vertex)
      v = centre + Vec3d{dir.x * r + unit(rng) * s, dir.y * r + unit(rng) * s, dir.z * r + unit(rng) * s};
    t.error = 1e-15;
    t.id = static_cast<std::uint32_t>(i);
    out.push_back(t);
  }
  return out;
}

// Everything a grid answers for `directions`: point candidates with their
// bounds, region candidates, and the total it lists.
std::vector<double> answers(const CentralGrid& grid, const std::vector<Vec3d>& directions) {
  std::vector<double> out;
  std::vector<std::uint32_t> ids;
  for (const Vec3d& w : directions) {
    for (const CentralGrid::Entry& e : grid.candidates(w, 0.0)) {
      out.push_back(e.id);
      out.push_back(e.axis_lower_bound);
    }
    out.push_back(-1);
    out.push_back(grid.candidates_in(w, 0.02, ids) ? 1 : 0);
    out.insert(out.end(), ids.begin(), ids.end());
    out.push_back(-1);
  }
  out.push_back(static_cast<double>(grid.listed_entries()));
  return out;
}

TEST(VectorPool, GridInKeptStorageListsWhatAFreshGridLists) {
  std::mt19937 rng(3131);
  const Vec3d centre{0.5, -1.25, 2};
  const std::vector<CentralGrid::Triangle> triangles = shell(rng, centre, 500);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vec3d> directions;
  for (int k = 0; k < 800; ++k) directions.push_back({unit(rng), unit(rng), unit(rng)});
  std::vector<double> expected;
  {
    const ReuseSwitch reuse(false);
    expected = answers(CentralGrid(centre, 0.0, triangles), directions);
  }
  const ReuseSwitch reuse(true);
  for (int run = 0; run < 3; ++run) {
    SCOPED_TRACE("run " + std::to_string(run));
    // Other grids, larger and smaller, around other centres, give their
    // storage back first, their lists still in it.
    for (const int count : {1500, 200, 900}) {
      const Vec3d other{unit(rng) * 5, unit(rng) * 5, unit(rng) * 5};
      const CentralGrid grid(other, 0.0, shell(rng, other, count));
      EXPECT_GT(grid.listed_entries(), 0u);
    }
    const CentralGrid kept(centre, 0.0, triangles);
    EXPECT_EQ(answers(kept, directions), expected);
  }
}

// A camera path over a bundled mesh scene, frames sharing the setup caches
// (the eye side rebuilt at every move, in the storage of the frames before):
// every frame's reference and proven squares equal a fresh tracer's built in
// fresh storage.
TEST(VectorPool, CameraPathInKeptStorageEqualsFreshFrames) {
  const std::string base = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes";
  std::ifstream in(base + "/twisted.json");
  nlohmann::json j = nlohmann::json::parse(in);
  j["camera"]["width"] = 40;
  j["camera"]["height"] = 30;
  MeshCache meshes;
  LightSetupCache light_setups;
  EyeSetupCache eye_setups;
  auto proven = [](const PixelReferenceTracer& tracer) {
    const Camera& camera = tracer.scene().scene().camera;
    std::vector<std::optional<bool>> out;
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x)
        out.push_back(tracer.proven_status_over_square(crack_square_centre(x, y), 2 << kCrackDistanceShift, nullptr));
    return out;
  };
  const double eye_x = j["camera"]["eye"][0].get<double>();
  std::size_t shadowed = 0;
  for (int frame = 0; frame < 5; ++frame) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    j["camera"]["eye"][0] = eye_x + 0.07 * frame;
    const Scene scene = parse_scene(j.dump(), "frame", base, &meshes);
    const CameraSpaceScene cs(scene);
    PixelReference expected;
    std::vector<std::optional<bool>> expected_proven;
    {
      const ReuseSwitch reuse(false);
      const PixelReferenceTracer fresh(cs, 0);
      expected = compute_pixel_reference(fresh);
      expected_proven = proven(fresh);
    }
    const ReuseSwitch reuse(true);
    const PixelReferenceTracer kept(cs, 0, &light_setups, &eye_setups);
    const PixelReference got = compute_pixel_reference(kept);
    EXPECT_TRUE(test::same_reference(got, expected));
    EXPECT_EQ(proven(kept), expected_proven);
    for (const std::uint32_t s : got.stencil) shadowed += s != PixelReference::kNothingSeen && s > 0;
  }
  EXPECT_GT(shadowed, 0u) << "the frames have shadowed pixels";
  EXPECT_EQ(eye_setups.counts().builds, 5u);
}

}  // namespace
}  // namespace nearcap
