// The A-D classification: the truth table of quad_case_from_sides, and hand-made
// scenes (camera at the origin looking down -z, near plane z = -1) for every
// case and each kind of degeneracy.
#include <gtest/gtest.h>

#include "nearcap/exact/classification.hpp"
#include "nearcap/io/scene_file.hpp"
#include "random_scene.hpp"

namespace nearcap {
namespace {

constexpr Sign kSigns[3] = {Sign::Negative, Sign::Zero, Sign::Positive};

// An independent reading of the definitions: which edges of Q the plane meets.
std::optional<QuadCase> expected_case(const QuadSides& s) {
  if (s.a == Sign::Zero || s.d == Sign::Zero || s.a_inf == Sign::Zero || s.d_inf == Sign::Zero)
    return QuadCase::Degenerate;
  const bool e_m = s.a != s.d, i2 = s.d != s.d_inf, e_inf = s.d_inf != s.a_inf, i1 = s.a_inf != s.a;
  const int met = e_m + i2 + e_inf + i1;
  if (met == 4) return std::nullopt;  // needs the light on both sides of the plane: impossible
  if (met == 0) return QuadCase::A;
  EXPECT_EQ(met, 2);
  if (i1 && i2) return QuadCase::B;
  if (e_m && e_inf) return QuadCase::D;
  if (e_m) return QuadCase::C1;  // with one of I1, I2
  return QuadCase::C2;           // E_inf with one of I1, I2
}

TEST(QuadCase, TruthTable) {
  int checked = 0;
  for (Sign a : kSigns)
    for (Sign d : kSigns)
      for (Sign ai : kSigns)
        for (Sign di : kSigns) {
          const QuadSides s{a, d, ai, di};
          const auto want = expected_case(s);
          if (!want) continue;
          EXPECT_EQ(quad_case_from_sides(s), *want)
              << "sides " << int(a) << " " << int(d) << " " << int(ai) << " " << int(di);
          ++checked;
        }
  EXPECT_EQ(checked, 81 - 2);  // the two alternating patterns are impossible
}

TEST(QuadCase, SwappingAAndDChangesNothing) {
  for (Sign a : kSigns)
    for (Sign d : kSigns)
      for (Sign ai : kSigns)
        for (Sign di : kSigns) {
          if (!expected_case({a, d, ai, di})) continue;
          EXPECT_EQ(quad_case_from_sides({a, d, ai, di}), quad_case_from_sides({d, a, di, ai}));
        }
}

// One unit box (scaled, translated) and one light; camera at the origin.
SceneClassification classify_box(const std::array<double, 3>& centre, double scale, const std::array<double, 3>& light,
                                 double near = 1.0) {
  nlohmann::json j;
  j["camera"] = {
      {"view", {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}},
      {"frustum", {{"left", -near}, {"right", near}, {"bottom", -near}, {"top", near}, {"near", near}, {"far", 100}}},
      {"width", 8},
      {"height", 8}};
  j["lights"] = nlohmann::json::array({{{"position", light}}});
  j["objects"] = nlohmann::json::array({{{"mesh", test::unit_box_path()}, {"translate", centre}, {"scale", scale}}});
  static std::vector<std::unique_ptr<Scene>> keep;  // CameraSpaceScene keeps a pointer
  keep.push_back(std::make_unique<Scene>(parse_scene(j.dump(), "hand-made", ".")));
  const CameraSpaceScene cs(*keep.back());
  return classify_scene(cs);
}

std::size_t count(const SceneClassification& s, QuadCase c) {
  return s.lights.at(0).objects.at(0).case_counts[static_cast<std::size_t>(c)];
}
std::size_t edges(const SceneClassification& s) { return s.lights.at(0).objects.at(0).edges.size(); }

TEST(QuadCase, AllAWhenTheBoxIsFarBeyondTheNearPlane) {
  // The light nearer to the camera than the box: every ray leaves away from it.
  const auto s = classify_box({0, 0, -5}, 1, {0, 4, -2});
  ASSERT_GT(edges(s), 0u);
  EXPECT_EQ(count(s, QuadCase::A), edges(s));
}

TEST(QuadCase, AllBWhenTheBoxSitsBetweenCameraAndNearPlaneLitFromBehind) {
  // Box z in [-5/8, -3/8] (camera side of z = -1), light behind the camera.
  const auto s = classify_box({0, 0, -0.5}, 0.25, {0.25, 0.5, 2});
  ASSERT_GT(edges(s), 0u);
  EXPECT_EQ(count(s, QuadCase::B), edges(s));
}

TEST(QuadCase, C1WhereAnEdgeCrossesTheNearPlane) {
  // Box z in [-1.5, -0.5] straddles z = -1; light far behind the camera.
  const auto s = classify_box({0.125, 0.25, -1}, 1, {0.5, 1.5, 8});
  EXPECT_GT(count(s, QuadCase::C1), 0u);
  EXPECT_EQ(count(s, QuadCase::D) + count(s, QuadCase::C2), 0u);
}

TEST(QuadCase, C2WhenTheLightIsAtTheBoxsDepthOnTheCameraSide) {
  // Box z in [-5/8, -3/8], light beside it at z = -1/2: directions A - l and
  // D - l point to both sides of the plane, the edge does not cross it.
  const auto s = classify_box({0, 0, -0.5}, 0.25, {2, 0.25, -0.5 + 1.0 / 64});
  EXPECT_GT(count(s, QuadCase::C2), 0u);
  EXPECT_EQ(count(s, QuadCase::C1) + count(s, QuadCase::D), 0u);
}

TEST(QuadCase, DWhenTheLightSitsJustBehindTheNearPlaneBesideAStraddlingBox) {
  const auto s = classify_box({0, 0, -1.125}, 0.75, {1.5, 0.25, -0.875}, 1.0);
  EXPECT_GT(count(s, QuadCase::D), 0u);
}

TEST(QuadCase, DegenerateWhenAVertexLiesOnTheNearPlane) {
  // Box z in [-1, 0]: its back vertices lie exactly on z = -1.
  const auto s = classify_box({3, 0, -0.5}, 1, {3, 5, -0.25});
  EXPECT_GT(count(s, QuadCase::Degenerate), 0u);
}

TEST(QuadCase, DegenerateWhenAnInfiniteEdgeIsParallelToTheNearPlane) {
  // Light at z = -2, the depth of the box's front vertices (box z in [-3, -2]).
  const auto s = classify_box({0, 0, -2.5}, 1, {3, 0.25, -2});
  EXPECT_GT(count(s, QuadCase::Degenerate), 0u);
  EXPECT_FALSE(s.lights[0].light_in_near_plane);
}

TEST(QuadCase, LightInTheNearPlaneGivesOnlyAAndD) {
  const auto s = classify_box({0, 0, -1.25}, 1, {3, 0.25, -1});
  EXPECT_TRUE(s.lights[0].light_in_near_plane);
  ASSERT_GT(edges(s), 0u);
  for (const ClassifiedEdge& e : s.lights[0].objects[0].edges)
    EXPECT_TRUE(e.exact == QuadCase::A || e.exact == QuadCase::D || e.exact == QuadCase::Degenerate)
        << to_string(e.exact);
}

}  // namespace
}  // namespace nearcap
