// The crack distance (exact/crack_distance.hpp, judge/crack_distances.hpp)
// against brute force: every square a level claims constant is sampled
// densely through the exact reference (trace_at), and must show one shadow
// status; a square that holds a pixel of the other status is never proven.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "box_scene.hpp"
#include "cli_support.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/crack_distance.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_distances.hpp"
#include "nearcap/judge/crack_map.hpp"
#include "support/removed_files.hpp"
#include "support/sampled_scenes.hpp"

namespace nearcap {
namespace {

// The exact status at a window point: nothing when no surface is seen.
std::optional<bool> status_at(const PixelReferenceTracer& tracer, const WindowPoint& w) {
  const PixelSample s = tracer.trace_at(w, nullptr);
  if (!s.stencil) return std::nullopt;
  return *s.stencil > 0;
}

// Samples the square of level `level` around pixel (i, j) on a 9 x 9 grid
// (corners, edges and interior) and returns the statuses seen.
std::vector<std::optional<bool>> sample_square(const PixelReferenceTracer& tracer, int i, int j, int level) {
  constexpr int kShift = kCrackDistanceShift + 3;
  const std::int64_t half = kCrackDistanceRadiiFixed[static_cast<std::size_t>(level - 1)] << 3;
  const std::int64_t cx = (2 * std::int64_t{i} + 1) << (kShift - 1), cy = (2 * std::int64_t{j} + 1) << (kShift - 1);
  std::vector<std::optional<bool>> out;
  for (int a = 0; a <= 8; ++a)
    for (int b = 0; b <= 8; ++b)
      out.push_back(status_at(tracer, {cx + half * (a - 4) / 4, cy + half * (b - 4) / 4, kShift}));
  return out;
}

struct Tally {
  std::size_t checked = 0, cracks = 0, noise = 0, boundary = 0;
};

// Every pixel of interest of one (scene, light): the wrong pixels of Z-pass
// and Z-fail, the pixels next to an exact shadow boundary, and a spread of
// others.  Each level is checked by sampling; boundary pixels must stay below
// the r = 2 square, which holds their differing neighbour.
void check_scene(const Scene& scene, Tally& tally, std::size_t pixel_budget) {
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  const PixelReference ref = compute_pixel_reference(tracer);
  CrackDistances distances(tracer, ref);
  std::vector<std::pair<int, int>> pixels;
  for (gl::ShadowMethod m : {gl::ShadowMethod::ZPass, gl::ShadowMethod::ZFail}) {
    CrackReport report = judge_frame(gl::render_shadow_frame(scene, 0, m), ref);
    distances.measure(report);
    std::size_t bucket_total = 0;
    for (std::size_t n : *report.wrong_by_distance) bucket_total += n;
    EXPECT_EQ(bucket_total, report.wrong) << scene.source;
    for (std::size_t p = 0; p < report.verdict.size(); ++p)
      if (report.distance[p] >= 0)
        pixels.emplace_back(static_cast<int>(p % ref.width), static_cast<int>(p / ref.width));
  }
  std::vector<std::pair<int, int>> boundary;
  for (int j = 0; j + 1 < ref.height; ++j)
    for (int i = 0; i + 1 < ref.width; ++i)
      for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{0, 1}})
        if (ref.seen(i, j) && ref.seen(i + di, j + dj) && ref.shadowed(i, j) != ref.shadowed(i + di, j + dj))
          boundary.emplace_back(i, j);
  for (int j = 1; j < ref.height; j += 5)
    for (int i = 2; i < ref.width; i += 7) pixels.emplace_back(i, j);
  pixels.insert(pixels.end(), boundary.begin(), boundary.end());
  std::sort(pixels.begin(), pixels.end());
  pixels.erase(std::unique(pixels.begin(), pixels.end()), pixels.end());
  // A deterministic thinning to the budget.
  if (pixels.size() > pixel_budget) {
    std::vector<std::pair<int, int>> kept;
    const double step = static_cast<double>(pixels.size()) / static_cast<double>(pixel_budget);
    for (std::size_t k = 0; k < pixel_budget; ++k) kept.push_back(pixels[static_cast<std::size_t>(k * step)]);
    pixels = kept;
  }
  const std::vector<int> levels = distances.levels(pixels);
  for (std::size_t k = 0; k < pixels.size(); ++k) {
    const auto [i, j] = pixels[k];
    const int level = levels[k];
    ASSERT_GE(level, 0);
    ASSERT_LT(level, static_cast<int>(kCrackDistanceLevels));
    ++tally.checked;
    (level >= kCrackLevel ? tally.cracks : tally.noise)++;
    if (level == 0) continue;
    const auto statuses = sample_square(tracer, i, j, level);
    for (const auto& s : statuses) {
      ASSERT_TRUE(s.has_value()) << scene.source << " pixel " << i << "," << j << " level " << level
                                 << ": a sample sees nothing";
      ASSERT_EQ(*s, ref.shadowed(i, j)) << scene.source << " pixel " << i << "," << j << " level " << level
                                        << ": the exact status changes inside the square";
    }
  }
  for (const auto& [i, j] : boundary) {
    ++tally.boundary;
    // The square of half-width one pixel holds the neighbour of the other status.
    EXPECT_FALSE(tracer.proven_status_over_square(crack_square_centre(i, j), 1 << kCrackDistanceShift, nullptr))
        << scene.source << " pixel " << i << "," << j;
  }
}

analysis::SamplerSpec sampler_spec(std::uint64_t seed) {
  analysis::SamplerSpec s = test::bundled_sampler_spec(seed);
  s.width = 40;
  s.height = 30;
  return s;
}

TEST(CrackDistance, EveryClaimedSquareIsConstantUnderDenseSamplingOnSampledScenes) {
  Tally tally;
  std::size_t scenes = 0;
  for (std::uint64_t seed : {3u, 11u}) {
    scenes += test::for_each_sampled_scene(
                  analysis::HardCaseSampler(sampler_spec(seed)), 12,
                  [&](const Scene& scene, const analysis::HardCase&) { check_scene(scene, tally, 60); })
                  .scenes;
    if (HasFatalFailure()) return;
  }
  EXPECT_GE(scenes, 16u);
  // Both outcomes occur, so the brute force checked real claims.
  EXPECT_GT(tally.cracks, 50u);
  EXPECT_GT(tally.noise, 50u);
  EXPECT_GT(tally.boundary, 50u);
}

// Near the exact shadow boundaries, where a tile's proof or a pixel's own
// decides the level: every pixel within two pixels of a boundary, in frames
// large enough for tiles of 32 (on sample 16 of these a tile's edge lies
// within half a pixel of a boundary beyond it: a level claimed past the
// tile's edge holds the boundary).  Each level's square is constant under
// dense sampling (a tile's level claims no square beyond its tile), and
// below the crack level the level is the largest square proven (the next
// is not; level 0: not even the smallest).
TEST(CrackDistance, NearBoundariesEachLevelIsConstantAndBelowACrackTheLargestProven) {
  analysis::SamplerSpec spec = test::bundled_sampler_spec(11);
  spec.width = 96;
  spec.height = 72;
  std::size_t from_tiles = 0, from_pixels = 0;
  test::for_each_sampled_scene(analysis::HardCaseSampler(spec), 30, [&](const Scene& scene, const analysis::HardCase&) {
    const CameraSpaceScene cs(scene);
    const PixelReferenceTracer tracer(cs, 0);
    const PixelReference ref = compute_pixel_reference(tracer);
    std::vector<bool> near(static_cast<std::size_t>(ref.width) * static_cast<std::size_t>(ref.height), false);
    for (int j = 0; j + 1 < ref.height; ++j)
      for (int i = 0; i + 1 < ref.width; ++i)
        for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{0, 1}})
          if (ref.seen(i, j) && ref.seen(i + di, j + dj) && ref.shadowed(i, j) != ref.shadowed(i + di, j + dj))
            for (int y = std::max(0, j - 2); y <= std::min(ref.height - 1, j + dj + 2); ++y)
              for (int x = std::max(0, i - 2); x <= std::min(ref.width - 1, i + di + 2); ++x)
                near[ref.index(x, y)] = true;
    std::vector<std::pair<int, int>> pixels;
    for (int j = 0; j < ref.height; ++j)
      for (int i = 0; i < ref.width; ++i)
        if (near[ref.index(i, j)] && ref.seen(i, j)) pixels.emplace_back(i, j);
    CrackDistances distances(tracer, ref);
    const std::vector<int> levels = distances.levels(pixels);
    for (std::size_t k = 0; k < pixels.size(); ++k) {
      const auto [i, j] = pixels[k];
      const int level = levels[k];
      (level >= kCrackLevel ? from_tiles : from_pixels)++;
      if (level < kCrackLevel - 1) {
        ASSERT_FALSE(tracer.proven_status_over_square(
            crack_square_centre(i, j), kCrackDistanceRadiiFixed[static_cast<std::size_t>(level)], nullptr))
            << scene.source << " pixel " << i << "," << j << " level " << level << ": a larger square is proven";
      }
      if (level == 0) continue;
      for (const auto& status : sample_square(tracer, i, j, level))
        ASSERT_EQ(status, std::optional<bool>(ref.shadowed(i, j)))
            << scene.source << " pixel " << i << "," << j << " level " << level
            << ": the exact status changes inside the square";
    }
  });
  std::printf("%zu pixels near boundaries: %zu with a tile's level, %zu with a pixel's\n", from_tiles + from_pixels,
              from_tiles, from_pixels);
  EXPECT_GT(from_tiles, 100u);
  EXPECT_GT(from_pixels, 100u);
}

// Where the far plane cuts the ground, a seen pixel next to one that sees
// nothing (beyond the far plane) has no proven square that holds its
// neighbour's centre: a triangle is hit over a square only where it is in
// front of the far plane all over it.
TEST(CrackDistance, NoSquareIsProvenAcrossTheFarPlanesCut) {
  nlohmann::json j;
  j["camera"] = {{"eye", {0.1, 1, 6}}, {"target", {0, 0, 0}}, {"fovy_deg", 50}, {"near", 0.5},
                 {"far", 8},           {"width", 32},         {"height", 24}};
  j["lights"] = nlohmann::json::array({{{"position", {1, 5, 1}}}});
  j["objects"] = nlohmann::json::array(
      {{{"mesh", std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/ground.off"}, {"occluder", false}}});
  const Scene scene = parse_scene(j.dump(), "far cut", ".");
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  const PixelReference ref = compute_pixel_reference(tracer);
  std::size_t pairs = 0;
  for (int y = 0; y + 1 < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x)
      for (const auto& [seen, beyond] : {std::pair{y, y + 1}, std::pair{y + 1, y}})
        if (ref.seen(x, seen) && !ref.seen(x, beyond)) {  // the far cut between the two rows
          ++pairs;
          EXPECT_FALSE(
              tracer.proven_status_over_square(crack_square_centre(x, seen), 1 << kCrackDistanceShift, nullptr))
              << x << "," << seen;
        }
  EXPECT_GE(pairs, 32u) << "the far plane cuts the ground across the frame";
}

// A diamond (a square of two triangles, turned 45 degrees about the
// vertical; open, so no side face hides its edges) seen from above: four
// diagonal edges between it and nothing.  A square half a pixel wide with a
// corner off the diamond and one on it is never proven, whichever corner is
// off (the centres on a grid of 1/16 pixel, so that each corner alone is off
// the diamond for some of them).
TEST(CrackDistance, NoSquareIsProvenWithACornerOffTheSurface) {
  const std::filesystem::path mesh = test::temp_path("nearcap_diamond") += ".off";
  std::ofstream(mesh) << "OFF\n4 2 0\n0.7 0 0\n0 0 -0.7\n-0.7 0 0\n0 0 0.7\n3 0 1 2\n3 0 2 3\n";
  const test::RemovedFiles removed{mesh};
  nlohmann::json j;
  j["camera"] = {{"eye", {0, 5, 0}}, {"target", {0, 0, 0}}, {"up", {0, 0, -1}}, {"fovy_deg", 40},
                 {"near", 1},        {"far", 50},           {"width", 16},      {"height", 12}};
  j["lights"] = nlohmann::json::array({{{"position", {1, 5, 1}}}});
  j["objects"] = nlohmann::json::array({{{"mesh", mesh.string()}, {"occluder", false}}});
  const Scene scene = parse_scene(j.dump(), "diamond", ".");
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  constexpr std::int64_t kPixel = std::int64_t{1} << kCrackDistanceShift, kHalf = kPixel / 2, kStep = kPixel / 16;
  auto seen_at = [&](std::int64_t x, std::int64_t y) {
    return tracer.trace_at({x, y, kCrackDistanceShift}, nullptr).stencil.has_value();
  };
  std::array<std::size_t, 4> one_corner_off{};
  for (std::int64_t y = 2 * kPixel; y <= 10 * kPixel; y += kStep)
    for (std::int64_t x = 4 * kPixel; x <= 12 * kPixel; x += kStep) {
      const std::array<bool, 4> on{seen_at(x - kHalf, y - kHalf), seen_at(x + kHalf, y - kHalf),
                                   seen_at(x - kHalf, y + kHalf), seen_at(x + kHalf, y + kHalf)};
      const auto count = std::count(on.begin(), on.end(), true);
      if (count == 0 || count == 4) continue;
      if (count == 3) ++one_corner_off[static_cast<std::size_t>(std::find(on.begin(), on.end(), false) - on.begin())];
      ASSERT_FALSE(tracer.proven_status_over_square({x, y, kCrackDistanceShift}, kHalf, nullptr))
          << "centre (" << x << ", " << y << ")/" << kPixel << ", corners on the diamond " << count;
    }
  for (std::size_t k = 0; k < 4; ++k) EXPECT_GT(one_corner_off[k], 0u) << "corner " << k << " alone off the diamond";
}

// The same across a shadow's edge: a flat prism above the camera (out of its
// view) shadows the ground below it, a triangle whose three edges run in
// three directions across the frame.  A square half a pixel wide with one
// corner on the other side of the shadow's edge is never proven, whichever
// corner it is; the squares on one side are (the proof has its say).  Told
// the status at its centre, every square gets the same answer.
TEST(CrackDistance, NoSquareIsProvenWithACornerAcrossTheShadowsEdge) {
  const std::filesystem::path mesh = test::temp_path("nearcap_prism") += ".off";
  std::ofstream(mesh) << "OFF\n6 8 0\n-0.5 8 -0.4\n0.6 8 -0.15\n0 8 0.5\n-0.5 7.9 -0.4\n0.6 7.9 -0.15\n0 7.9 0.5\n"
                         "3 0 2 1\n3 3 4 5\n3 2 0 3\n3 2 3 5\n3 1 2 5\n3 1 5 4\n3 0 1 4\n3 0 4 3\n";
  const test::RemovedFiles removed{mesh};
  nlohmann::json j;
  j["camera"] = {{"eye", {0, 5, 0}}, {"target", {0, 0, 0}}, {"up", {0, 0, -1}}, {"fovy_deg", 40},
                 {"near", 1},        {"far", 50},           {"width", 16},      {"height", 12}};
  j["lights"] = nlohmann::json::array({{{"position", {0, 12, 0}}}});
  j["objects"] = nlohmann::json::array(
      {{{"mesh", std::string(NEARCAP_SOURCE_DIR) + "/data/meshes/ground.off"}, {"occluder", false}},
       {{"mesh", mesh.string()}, {"occluder", true}}});
  const Scene scene = parse_scene(j.dump(), "prism's shadow", ".");
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  constexpr std::int64_t kPixel = std::int64_t{1} << kCrackDistanceShift, kHalf = kPixel / 2, kStep = kPixel / 8;
  auto shadowed_at = [&](std::int64_t x, std::int64_t y) { return status_at(tracer, {x, y, kCrackDistanceShift}); };
  std::array<std::size_t, 4> one_corner_across{};
  std::size_t proven = 0;
  for (std::int64_t y = kPixel; y <= 11 * kPixel; y += kStep)
    for (std::int64_t x = kPixel; x <= 15 * kPixel; x += kStep) {
      // In the proof's corner order: (-,-), (+,-), (+,+), (-,+).
      const std::array<std::optional<bool>, 4> corner{
          shadowed_at(x - kHalf, y - kHalf), shadowed_at(x + kHalf, y - kHalf), shadowed_at(x + kHalf, y + kHalf),
          shadowed_at(x - kHalf, y + kHalf)};
      ASSERT_TRUE(corner[0] && corner[1] && corner[2] && corner[3]) << "the ground fills the frame";
      const auto in_shadow = std::count(corner.begin(), corner.end(), std::optional<bool>(true));
      const std::optional<bool> status = tracer.proven_status_over_square({x, y, kCrackDistanceShift}, kHalf, nullptr);
      ASSERT_EQ(tracer.proven_status_over_square({x, y, kCrackDistanceShift}, kHalf, nullptr, nullptr, nullptr,
                                                 shadowed_at(x, y)),
                status)
          << "centre (" << x << ", " << y << ")/" << kPixel << ", told its status";
      if (in_shadow == 0 || in_shadow == 4) {
        proven += status.has_value();
        continue;
      }
      for (std::size_t k = 0; k < 4; ++k)
        if (std::count(corner.begin(), corner.end(), corner[k]) == 1) ++one_corner_across[k];
      ASSERT_FALSE(status) << "centre (" << x << ", " << y << ")/" << kPixel << ", corners in shadow " << in_shadow;
    }
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_GT(one_corner_across[k], 0u) << "corner " << k << " alone across the shadow's edge";
  EXPECT_GT(proven, 1000u);
}

// A shadow's edge within rounding of a square's corner and on the far side
// of it: the float filters cannot tell that corner's side, so the proof
// decides it corner by corner in rationals.  The camera looks straight down
// at the origin of one large ground triangle, the light straight above; a
// flat prism's top edge runs along u x + v z = 2^-52 at y = 8 (u, v = +-1,
// every coordinate a double), so its shadow on the ground runs along
// u x + v z = 3 * 2^-52, the prism on the side u x + v z > 2^-52.  The
// window point (8, 6), the view's axis, sees the ground's origin: it is lit.
// In each of the four squares of half a pixel with a corner there, that
// corner is the lone lit one (the prism turned so the other three are in
// shadow), and the square is not proven.
TEST(CrackDistance, NoSquareIsProvenWithACornerJustAcrossTheShadowsEdge) {
  const std::filesystem::path ground = test::temp_path("nearcap_ground_triangle") += ".off";
  const std::filesystem::path prism = test::temp_path("nearcap_thin_prism") += ".off";
  std::ofstream(ground) << "OFF\n3 1 0\n-20 0 20\n20 0 20\n0 0 -20\n3 0 1 2\n";
  const test::RemovedFiles removed{ground, prism};
  constexpr double e = 0x1p-52;
  constexpr std::int64_t kPixel = std::int64_t{1} << kCrackDistanceShift, kHalf = kPixel / 2;
  struct Square {
    std::int64_t x2, y2;  // the centre, in half pixels
    double u, v;          // the prism's side: u x + v z > e
  };
  // Window x is world x, window y world -z: the other three corners of
  // corner k's square lie where u x + v z > 0.
  const std::array<Square, 4> squares{{{17, 13, 1, -1}, {15, 13, -1, -1}, {15, 11, -1, 1}, {17, 11, 1, 1}}};
  for (std::size_t lone = 0; lone < 4; ++lone) {
    const Square& sq = squares[lone];
    // Two points of the edge (u x + v z = e exactly: x = u (e - v z), z = +-1)
    // and one deep on the prism's side.
    const std::array<std::array<double, 2>, 3> top{
        {{sq.u * (e - sq.v), 1.0}, {sq.u * (e + sq.v), -1.0}, {2 * sq.u, 2 * sq.v}}};
    // The top face turned to face up (+y), the bottom down, the sides out.
    const double ny =
        (top[1][1] - top[0][1]) * (top[2][0] - top[0][0]) - (top[1][0] - top[0][0]) * (top[2][1] - top[0][1]);
    const std::array<int, 3> up = ny > 0 ? std::array<int, 3>{0, 1, 2} : std::array<int, 3>{0, 2, 1};
    {
      std::ofstream out(prism);
      out.precision(17);
      out << "OFF\n6 8 0\n";
      for (double y : {8.0, 7.9})
        for (const auto& q : top) out << q[0] << " " << y << " " << q[1] << "\n";
      out << "3 " << up[0] << " " << up[1] << " " << up[2] << "\n3 " << up[0] + 3 << " " << up[2] + 3 << " "
          << up[1] + 3 << "\n";
      for (int k = 0; k < 3; ++k) {
        const int i = up[static_cast<std::size_t>(k)], j = up[static_cast<std::size_t>((k + 1) % 3)];
        out << "3 " << j << " " << i << " " << i + 3 << "\n3 " << j << " " << i + 3 << " " << j + 3 << "\n";
      }
    }
    nlohmann::json j;
    j["camera"] = {{"eye", {0, 5, 0}}, {"target", {0, 0, 0}}, {"up", {0, 0, -1}}, {"fovy_deg", 40},
                   {"near", 1},        {"far", 50},           {"width", 16},      {"height", 12}};
    j["lights"] = nlohmann::json::array({{{"position", {0, 12, 0}}}});
    j["objects"] = nlohmann::json::array(
        {{{"mesh", ground.string()}, {"occluder", false}}, {{"mesh", prism.string()}, {"occluder", true}}});
    const Scene scene = parse_scene(j.dump(), "prism turned for corner " + std::to_string(lone), ".");
    const CameraSpaceScene cs(scene);
    const PixelReferenceTracer tracer(cs, 0);
    const std::int64_t cx = sq.x2 * kHalf, cy = sq.y2 * kHalf;
    const std::array<std::optional<bool>, 4> corner{status_at(tracer, {cx - kHalf, cy - kHalf, kCrackDistanceShift}),
                                                    status_at(tracer, {cx + kHalf, cy - kHalf, kCrackDistanceShift}),
                                                    status_at(tracer, {cx + kHalf, cy + kHalf, kCrackDistanceShift}),
                                                    status_at(tracer, {cx - kHalf, cy + kHalf, kCrackDistanceShift})};
    for (std::size_t k = 0; k < 4; ++k)
      ASSERT_EQ(corner[k], std::optional<bool>(k != lone)) << "corner " << k << " of corner " << lone << "'s square";
    FilterStats stats;
    EXPECT_FALSE(tracer.proven_status_over_square({cx, cy, kCrackDistanceShift}, kHalf, &stats))
        << "corner " << lone << " alone lit";
    EXPECT_GT(stats.exact[static_cast<int>(Predicate::ShadowCrossing)], 0u)
        << "corner " << lone << ": the shadow's edge is within the filters' error of the corner";
  }
}

TEST(CrackDistance, EyeInShadowZPassIsCracksAndZFailHasNone) {
  // The bundled eye-in-shadow scene: Z-pass inverts the whole shadow (README,
  // "What the methods get wrong"), a crack of the whole frame; Z-fail is right.
  const Scene scene = load_scene(std::string(NEARCAP_SOURCE_DIR) + "/data/scenes/eye_in_shadow.json");
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  const PixelReference ref = compute_pixel_reference(tracer);
  CrackDistances distances(tracer, ref);
  CrackReport zpass = judge_frame(gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZPass), ref);
  distances.measure(zpass);
  ASSERT_GT(zpass.wrong, 1000u);
  EXPECT_GT(*zpass.cracks, zpass.wrong * 9 / 10);
  EXPECT_LT(*zpass.cracks, zpass.wrong) << "pixels at the exact shadow's outline are noise";
  CrackReport zfail = judge_frame(gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZFail), ref);
  distances.measure(zfail);
  EXPECT_EQ(*zfail.cracks, 0u);
  Tally tally;
  check_scene(scene, tally, 150);
}

TEST(CrackDistance, AFaceInTheNearPlaneIsProvenSeen) {
  // The face fills the frame and is lit (the reference sees it: GL keeps a
  // face in the near plane).  ZP+'s near-cap counts that face, so its frame
  // is shadowed where the face is lit, a crack of the whole frame that the
  // square proofs can only show with the face proven seen over each square.
  const Scene scene = test::near_plane_face();
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  const PixelReference ref = compute_pixel_reference(tracer);
  CrackDistances distances(tracer, ref);
  CrackReport zpplus = judge_frame(gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZPPlus), ref);
  distances.measure(zpplus);
  ASSERT_GT(zpplus.wrong, 1000u);
  EXPECT_GT(*zpplus.cracks, zpplus.wrong * 9 / 10);
  Tally tally;
  check_scene(scene, tally, 150);
  EXPECT_GT(tally.cracks, tally.checked * 9 / 10) << "of the sampled pixels, proven constant over their squares";
}

TEST(CrackDistance, LevelsDoNotDependOnTheOrderOfMeasurement) {
  test::for_each_sampled_scene(
      analysis::HardCaseSampler(sampler_spec(5)), 6, [&](const Scene& scene, const analysis::HardCase& sample) {
        const CameraSpaceScene cs(scene);
        const PixelReferenceTracer tracer(cs, 0);
        const PixelReference ref = compute_pixel_reference(tracer);
        const CrackReport zpass = judge_frame(gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZPass), ref);
        const CrackReport zfail = judge_frame(gl::render_shadow_frame(scene, 0, gl::ShadowMethod::ZFail), ref);
        CrackDistances a(tracer, ref), b(tracer, ref);
        CrackReport a1 = zpass, a2 = zfail, b1 = zfail, b2 = zpass;
        a.measure(a1);
        a.measure(a2);
        b.measure(b1);
        b.measure(b2);
        EXPECT_EQ(a1.distance, b2.distance) << sample.index;
        EXPECT_EQ(a2.distance, b1.distance) << sample.index;
      });
}

// The light-triangle hint of proven_status_over_square changes no answer:
// on the bunny, whose shadow holds the eye (count 1 nearly everywhere, the
// shadowing triangles small and many), every pixel's squares of every radius
// are proven the same with no hint, with the hint carried from pixel to
// pixel as the crack distance carries it, and with a hint that is a
// different lit triangle at every call; the carried hint proves squares.
TEST(CrackDistance, ShadowerHintChangesNoAnswer) {
  const std::string base = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes";
  std::ifstream in(base + "/bunny.json");
  nlohmann::json j = nlohmann::json::parse(in);
  j["camera"]["width"] = 48;
  j["camera"]["height"] = 36;
  MeshCache meshes;
  const Scene scene = parse_scene(j.dump(), "bunny 48x36", base, &meshes);
  const CameraSpaceScene cs(scene);
  const PixelReferenceTracer tracer(cs, 0);
  const std::uint32_t lit = static_cast<std::uint32_t>(tracer.front_facing_triangles());
  ASSERT_GT(lit, 1000u);
  std::uint32_t carried = PixelReferenceTracer::kNoShadower;
  std::size_t shadowed = 0, by_hint = 0, compared = 0;
  std::uint32_t k = 0;
  for (int y = 0; y < scene.camera.height; ++y)
    for (int x = 0; x < scene.camera.width; ++x)
      for (const std::int64_t half_width : kCrackDistanceRadiiFixed) {
        const WindowPoint c = crack_square_centre(x, y);
        const std::optional<bool> plain = tracer.proven_status_over_square(c, half_width, nullptr);
        const std::uint32_t before = carried;
        const std::optional<bool> hinted = tracer.proven_status_over_square(c, half_width, nullptr, &carried);
        std::uint32_t arbitrary = (k++ * 7919u) % lit;
        const std::optional<bool> misled = tracer.proven_status_over_square(c, half_width, nullptr, &arbitrary);
        EXPECT_EQ(hinted, plain) << "pixel " << x << ", " << y << ", half-width " << half_width;
        EXPECT_EQ(misled, plain) << "pixel " << x << ", " << y << ", half-width " << half_width;
        ++compared;
        shadowed += plain == std::optional<bool>(true);
        by_hint +=
            hinted == std::optional<bool>(true) && before != PixelReferenceTracer::kNoShadower && carried == before;
      }
  EXPECT_EQ(compared, std::size_t{48 * 36 * 6});
  EXPECT_GT(shadowed, 1000u);
  EXPECT_GT(by_hint, 100u) << "the carried hint proved squares";
}

// A proof's candidate lists live in a buffer each thread keeps from proof to
// proof (crack_distance.cpp): what a proof answers must not depend on the
// proofs that ran before it on the thread.  Two frames of the bunny (the
// camera moved), each proven alone, pixel by pixel, and then the two
// interleaved, every proof of one frame right after one of the other, on this
// thread: the same answers.
TEST(CrackDistance, ProofsOfInterleavedFramesAnswerAsAlone) {
  const std::string base = std::string(NEARCAP_SOURCE_DIR) + "/data/scenes";
  std::ifstream in(base + "/bunny.json");
  nlohmann::json j = nlohmann::json::parse(in);
  j["camera"]["width"] = 32;
  j["camera"]["height"] = 24;
  MeshCache meshes;
  const Scene first = parse_scene(j.dump(), "bunny 32x24", base, &meshes);
  j["camera"]["eye"] = {0.6, -0.35, -0.4};
  const Scene second = parse_scene(j.dump(), "bunny 32x24, moved", base, &meshes);
  const CameraSpaceScene cs1(first), cs2(second);
  const PixelReferenceTracer t1(cs1, 0), t2(cs2, 0);
  using Answers = std::vector<std::optional<bool>>;
  auto prove = [&](const PixelReferenceTracer& t, int x, int y, std::int64_t half_width) {
    return t.proven_status_over_square(crack_square_centre(x, y), half_width, nullptr);
  };
  Answers alone1, alone2, mixed1, mixed2;
  for (const auto& [t, out] : {std::pair{&t1, &alone1}, std::pair{&t2, &alone2}})
    for (int y = 0; y < first.camera.height; ++y)
      for (int x = 0; x < first.camera.width; ++x)
        for (const std::int64_t half_width : kCrackDistanceRadiiFixed) out->push_back(prove(*t, x, y, half_width));
  for (int y = 0; y < first.camera.height; ++y)
    for (int x = 0; x < first.camera.width; ++x)
      for (const std::int64_t half_width : kCrackDistanceRadiiFixed) {
        mixed1.push_back(prove(t1, x, y, half_width));
        mixed2.push_back(prove(t2, x, y, half_width));
      }
  EXPECT_EQ(mixed1, alone1);
  EXPECT_EQ(mixed2, alone2);
  // The frames differ, and both prove squares of both statuses.
  EXPECT_NE(alone1, alone2);
  for (const Answers* a : {&alone1, &alone2}) {
    EXPECT_GT(std::count(a->begin(), a->end(), std::optional<bool>(true)), 100);
    EXPECT_GT(std::count(a->begin(), a->end(), std::optional<bool>(false)), 100);
  }
}

}  // namespace
}  // namespace nearcap
