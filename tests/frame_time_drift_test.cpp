// The measured-to-priced frame time ratio of a renderer's last frames
// (analysis/frame_time_drift.hpp): 1 before any frame, the median of the
// last kWindow ratios after, deaf to frames that are not two positive
// finite times, and a price scaled by it follows a device whose speed moves.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "nearcap/analysis/frame_time_drift.hpp"

namespace nearcap {
namespace {

using analysis::FrameTimeDrift;

TEST(FrameTimeDrift, IsOneBeforeAnyFrame) {
  const FrameTimeDrift drift;
  EXPECT_EQ(drift.scale(), 1.0);
  EXPECT_EQ(drift.observed(), 0u);
}

TEST(FrameTimeDrift, IsTheMedianRatioOfTheLastFrames) {
  FrameTimeDrift drift;
  drift.observe(2, 3);  // 1.5
  EXPECT_NEAR(drift.scale(), 1.5, 1e-12);
  drift.observe(1, 4);  // 4: the middle two of {1.5, 4}, geometrically
  EXPECT_NEAR(drift.scale(), std::sqrt(1.5 * 4), 1e-12);
  drift.observe(4, 2);  // 0.5: {0.5, 1.5, 4}
  EXPECT_NEAR(drift.scale(), 1.5, 1e-12);
  // A frame far off moves the median by one place, not by its size.
  drift.observe(1, 1000);  // {0.5, 1.5, 4, 1000}
  EXPECT_NEAR(drift.scale(), std::sqrt(1.5 * 4), 1e-12);
}

TEST(FrameTimeDrift, ForgetsFramesOlderThanItsWindow) {
  FrameTimeDrift drift;
  for (std::size_t k = 0; k < FrameTimeDrift::kWindow; ++k) drift.observe(1, 2);
  EXPECT_NEAR(drift.scale(), 2.0, 1e-12);
  // A window's worth of frames at another speed: the first are forgotten.
  for (std::size_t k = 0; k < FrameTimeDrift::kWindow; ++k) drift.observe(1, 0.75);
  EXPECT_NEAR(drift.scale(), 0.75, 1e-12);
  EXPECT_EQ(drift.observed(), 2 * FrameTimeDrift::kWindow);
}

// A shorter window: the median of the last `window` ratios, in the order
// observed across the buffer's wrap; a path's window is the last ratio.
TEST(FrameTimeDrift, AShorterWindowIsTheMedianOfTheLastRatios) {
  FrameTimeDrift three(3);
  EXPECT_EQ(three.window(), 3u);
  for (double r : {5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 0.5, 1000.0, 2.0}) three.observe(1, r);
  EXPECT_NEAR(three.scale(), 2.0, 1e-12) << "the median of {0.5, 1000, 2}";
  FrameTimeDrift path(FrameTimeDrift::kPathWindow);
  EXPECT_EQ(path.scale(), 1.0);
  for (double r : {5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 0.5}) {
    path.observe(2, 2 * r);
    EXPECT_NEAR(path.scale(), r, 1e-12);
  }
  EXPECT_EQ(FrameTimeDrift(0).window(), 1u);
  EXPECT_EQ(FrameTimeDrift(100).window(), FrameTimeDrift::kWindow);
}

TEST(FrameTimeDrift, IgnoresFramesThatAreNotTwoPositiveTimes) {
  FrameTimeDrift drift;
  drift.observe(1, 3);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (auto [priced, measured] :
       std::vector<std::pair<double, double>>{{0, 1}, {1, 0}, {-1, 2}, {1, -2}, {nan, 1}, {1, nan}, {inf, 1}, {1, inf}})
    drift.observe(priced, measured);
  EXPECT_EQ(drift.observed(), 1u);
  EXPECT_NEAR(drift.scale(), 3.0, 1e-12);
}

// A device that runs a third faster from frame 40 on, the profile's price
// of each frame off by a scatter of +-10% around the true time: the price
// scaled by the drift errs by that scatter, the price alone by the speed.
TEST(FrameTimeDrift, AScaledPriceFollowsTheDevicesSpeed) {
  FrameTimeDrift drift;
  double raw_error = 0, scaled_error = 0;
  for (int frame = 0; frame < 80; ++frame) {
    const double true_ms = 5 + (frame % 7);
    const double scatter = 1 + 0.1 * std::sin(1.7 * frame);
    const double speed = frame < 40 ? 1.0 : 0.75;
    const double priced = true_ms * scatter, measured = true_ms * speed;
    if (frame >= 48) {  // the window refilled at the new speed
      raw_error = std::max(raw_error, std::fabs(priced - measured) / measured);
      scaled_error = std::max(scaled_error, std::fabs(priced * drift.scale() - measured) / measured);
    }
    drift.observe(priced, measured);
  }
  EXPECT_GT(raw_error, 0.3);
  EXPECT_LT(scaled_error, 0.25);
}

}  // namespace
}  // namespace nearcap
