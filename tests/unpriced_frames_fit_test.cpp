// The unpriced frames' fit (analysis/unpriced_frames_fit.hpp) on synthetic
// training rows: the threshold with the smallest total, each count's cheaper
// method, neighbours with the same method one tier, none where pricing every
// frame is cheapest, refused frames as Z-fail's.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "nearcap/analysis/unpriced_frames_fit.hpp"

namespace nearcap {
namespace {

using analysis::EvaluationRow;

// One (configuration, light)'s rows: the policy's (its end-to-end time and
// warm decision), always Z-fail's and always clipped's.
void add_frame(std::vector<EvaluationRow>& rows, const std::string& id, std::size_t triangles, double policy_ms,
               double zfail_ms, double clipped_ms, double warm_ms = 0.01) {
  for (const auto& [rule, ms] : {std::pair<std::string, double>{"policy", policy_ms},
                                 {"always-zfail", zfail_ms},
                                 {"always-clipped", clipped_ms},
                                 {"zfail", zfail_ms}}) {
    EvaluationRow r;
    r.set = "seed-1";
    r.configuration = id;
    r.rule = rule;
    r.end_to_end_ms = ms;
    r.occluder_triangles = triangles;
    if (rule == "policy") r.decision_warm_ms = warm_ms;
    rows.push_back(r);
  }
}

// Boxes where the priced decision loses its own time, tori where pricing pays.
std::vector<EvaluationRow> boxes_and_tori(double box_zfail_ms, double box_clipped_ms) {
  std::vector<EvaluationRow> rows;
  for (int k = 0; k < 4; ++k) add_frame(rows, "box" + std::to_string(k), 12, 1.0, box_zfail_ms, box_clipped_ms);
  for (int k = 0; k < 3; ++k) add_frame(rows, "torus" + std::to_string(k), 2304, 2.0, 2.5, 2.4);
  return rows;
}

// The tori's always-clipped frames at `ms`.
void set_tori_clipped(std::vector<EvaluationRow>& rows, double ms) {
  for (EvaluationRow& r : rows)
    if (r.configuration.rfind("torus", 0) == 0 && r.rule == "always-clipped") r.end_to_end_ms = ms;
}

// Always clipped on box2: refused (`broken` 0) or with a crack Z-fail lacks (1).
void break_box2_clipped(std::vector<EvaluationRow>& rows, int broken) {
  for (EvaluationRow& r : rows)
    if (r.configuration == "box2" && r.rule == "always-clipped") {
      if (broken == 0)
        r.refused = true;
      else
        r.cracks = 1;  // Z-fail's: none
    }
}

// The fit's tiers are these (bound, method).
void expect_tiers(const analysis::UnpricedFramesFit& fit,
                  const std::vector<std::pair<std::size_t, gl::ShadowMethod>>& tiers) {
  ASSERT_EQ(fit.unpriced.size(), tiers.size());
  for (std::size_t k = 0; k < tiers.size(); ++k) {
    EXPECT_EQ(fit.unpriced[k].max_occluder_triangles, tiers[k].first) << k;
    EXPECT_EQ(fit.unpriced[k].method.method, tiers[k].second) << k;
  }
}

TEST(UnpricedFramesFit, TheThresholdAndMethodWithTheSmallestTotal) {
  analysis::UnpricedFramesFit fit = analysis::fit_unpriced_frames(boxes_and_tori(0.9, 0.95), gl::ZPassFar::Infinite);
  ASSERT_EQ(fit.unpriced.size(), 1u);
  EXPECT_EQ(fit.unpriced[0].max_occluder_triangles, 12u);
  EXPECT_EQ(fit.unpriced[0].method.method, gl::ShadowMethod::ZFail);
  EXPECT_EQ(fit.frames, 7u);
  EXPECT_EQ(fit.unpriced_frames, 4u);
  EXPECT_DOUBLE_EQ(fit.priced_total_ms, 4 * 1.0 + 3 * 2.0);
  EXPECT_DOUBLE_EQ(fit.fitted_total_ms, 4 * (0.9 + 0.01) + 3 * 2.0);

  fit = analysis::fit_unpriced_frames(boxes_and_tori(0.95, 0.9), gl::ZPassFar::Infinite);
  ASSERT_EQ(fit.unpriced.size(), 1u);
  EXPECT_EQ(fit.unpriced[0].method.method, gl::ShadowMethod::ZPPlus);
  EXPECT_EQ(fit.unpriced[0].method.cap, gl::LightProjection::ClippedSides);
  EXPECT_EQ(fit.unpriced[0].method.name(), "zpplus-clipped-sides");
}

TEST(UnpricedFramesFit, NoneWherePricingEveryFrameIsCheapest) {
  // The unpriced frame's decision still costs: 0.995 + 0.01 is above 1.0.
  const analysis::UnpricedFramesFit fit =
      analysis::fit_unpriced_frames(boxes_and_tori(0.995, 1.2), gl::ZPassFar::Infinite);
  EXPECT_TRUE(fit.unpriced.empty());
  EXPECT_EQ(fit.unpriced_frames, 0u);
  EXPECT_DOUBLE_EQ(fit.fitted_total_ms, fit.priced_total_ms);
}

TEST(UnpricedFramesFit, EveryFrameUnpricedWhereThatIsCheapestEachCountWithItsMethod) {
  std::vector<EvaluationRow> rows = boxes_and_tori(0.9, 0.95);
  set_tori_clipped(rows, 1.5);
  const analysis::UnpricedFramesFit fit = analysis::fit_unpriced_frames(rows, gl::ZPassFar::Finite);
  // Z-fail on the boxes, the clipped-sides ZP+ on the tori: two tiers.
  expect_tiers(fit, {{12, gl::ShadowMethod::ZFail}, {2304, gl::ShadowMethod::ZPPlus}});
  ASSERT_EQ(fit.unpriced.size(), 2u);
  EXPECT_EQ(fit.unpriced[1].method.zpass_far, gl::ZPassFar::Finite);
  EXPECT_EQ(fit.unpriced_frames, 7u);
  EXPECT_DOUBLE_EQ(fit.fitted_total_ms, 4 * (0.9 + 0.01) + 3 * (1.5 + 0.01));
}

// The unpriced frames are those up to a threshold: a count where pricing
// gained a little lies below one where it lost more, and is unpriced with
// it; neighbouring counts with the same method make one tier, up to the
// larger count; counts above the threshold stay priced.
TEST(UnpricedFramesFit, UpToTheBestThresholdNeighboursWithOneMethodOneTier) {
  std::vector<EvaluationRow> rows;
  add_frame(rows, "a", 12, 1.0, 0.8, 0.9);    // Z-fail gains 0.19
  add_frame(rows, "b", 100, 1.0, 1.05, 1.2);  // pricing gains 0.06 (Z-fail 1.06)
  add_frame(rows, "c", 634, 2.0, 2.5, 1.5);   // clipped gains 0.49
  add_frame(rows, "d", 2304, 2.0, 2.5, 1.8);  // clipped gains 0.19
  add_frame(rows, "e", 6400, 2.0, 2.5, 2.2);  // pricing gains 0.21
  const analysis::UnpricedFramesFit fit = analysis::fit_unpriced_frames(rows, gl::ZPassFar::Infinite);
  expect_tiers(fit, {{100, gl::ShadowMethod::ZFail}, {2304, gl::ShadowMethod::ZPPlus}});
  EXPECT_EQ(fit.unpriced_frames, 4u);
  EXPECT_DOUBLE_EQ(fit.fitted_total_ms, 0.81 + 1.06 + 1.51 + 1.81 + 2.0);
}

// The clipped-sides ZP+ is no method for a triangle count where always
// clipped did not draw or is less right than Z-fail on one of its frames;
// it stays one for the other counts.
TEST(UnpricedFramesFit, ClippedOnlyWhereItDrewAndIsAsRightAsZFail) {
  for (int broken = 0; broken < 2; ++broken) {
    std::vector<EvaluationRow> rows = boxes_and_tori(0.995, 0.5);
    break_box2_clipped(rows, broken);
    const analysis::UnpricedFramesFit fit = analysis::fit_unpriced_frames(rows, gl::ZPassFar::Infinite);
    EXPECT_TRUE(fit.unpriced.empty()) << (broken == 0 ? "refused" : "a crack Z-fail lacks");
  }
  // Cheap on the tori too: the boxes get Z-fail, the tori the clipped-sides ZP+.
  for (int broken = 0; broken < 2; ++broken) {
    std::vector<EvaluationRow> rows = boxes_and_tori(0.95, 0.5);
    set_tori_clipped(rows, 1.5);
    break_box2_clipped(rows, broken);
    SCOPED_TRACE(broken);
    expect_tiers(analysis::fit_unpriced_frames(rows, gl::ZPassFar::Infinite),
                 {{12, gl::ShadowMethod::ZFail}, {2304, gl::ShadowMethod::ZPPlus}});
  }
  // A box frame the policy did not draw is left out.
  std::vector<EvaluationRow> rows = boxes_and_tori(0.9, 0.95);
  for (EvaluationRow& r : rows)
    if (r.configuration == "box0" && r.rule == "policy") r.refused = true;
  const analysis::UnpricedFramesFit fit = analysis::fit_unpriced_frames(rows, gl::ZPassFar::Infinite);
  EXPECT_EQ(fit.frames, 6u);
  EXPECT_EQ(fit.unpriced_frames, 3u);
}

// A threshold falls between triangle counts, never inside one: frames with
// the same count but different times are unpriced together.
TEST(UnpricedFramesFit, FramesOfOneCountShareTheirFate) {
  std::vector<EvaluationRow> rows;
  add_frame(rows, "a", 12, 1.0, 0.5, 2.0);  // Z-fail much cheaper here
  add_frame(rows, "b", 12, 1.0, 1.8, 2.0);  // and dearer here: together 2.32 against 2.0
  add_frame(rows, "c", 100, 1.0, 2.0, 2.0);
  const analysis::UnpricedFramesFit fit = analysis::fit_unpriced_frames(rows, gl::ZPassFar::Infinite);
  EXPECT_TRUE(fit.unpriced.empty()) << "frame a alone would gain, but b shares its count";
}

}  // namespace
}  // namespace nearcap
