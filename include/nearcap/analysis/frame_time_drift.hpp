// nearcap/analysis/frame_time_drift.hpp — a device profile's price of a
// frame set against what the device takes for it now.
//
// A device profile (device_profile.hpp) is calibrated once; the device's
// speed is not fixed: a shared or power-managed machine runs the same frames
// tens of percent faster or slower from one hour to the next, and the
// profile's prices are then off by that factor for every frame
// (docs/findings/policy-oracle.md, "What it says").  A renderer
// measures each frame it draws, so it can keep the ratio of measured to
// priced over its last frames and scale the next frame's price by it.  The
// ratio scales every candidate's price alike, so it changes no decision:
// it corrects the predicted frame time.
#pragma once

#include <array>
#include <cstddef>

namespace nearcap::analysis {

class FrameTimeDrift {
 public:
  // The frames whose ratio the scale is the median of: few, so that it
  // follows the device's speed now and the scene the frames show.  Along a
  // camera path, whose frames differ little from one to the next, the last
  // frame's ratio alone (kPathWindow); across unrelated configurations (a
  // sampler's), the median of the last kWindow.  Both chosen on the
  // shipped policy's training data: the bundled paths its profile was
  // calibrated on and seed 100's configurations
  // (docs/findings/policy-oracle.md).
  static constexpr std::size_t kWindow = 8;
  static constexpr std::size_t kPathWindow = 1;

  // The median over the last `window` frames (1 to kWindow).
  explicit FrameTimeDrift(std::size_t window = kWindow);

  // One drawn frame: the profile's price of the work it drew (`priced_ms`,
  // price_decision's predicted_ms before any scaling) and its measured time
  // for the same part (the decision's own time left out).  A pair that is
  // not two positive finite numbers is ignored.
  void observe(double priced_ms, double measured_ms);
  // The median of measured / priced over the last window() frames observed
  // (the geometric mean of the middle two of an even count); 1 before any.
  double scale() const;
  std::size_t observed() const { return observed_; }
  std::size_t window() const { return window_; }

 private:
  std::size_t window_;
  std::array<double, kWindow> log_ratio_{};
  std::size_t observed_ = 0;
};

}  // namespace nearcap::analysis
