// nearcap/analysis/device_profile_fit.hpp — fitting a device cost profile
// (device_profile.hpp) to what `nearcap calibrate` measured, with Ceres.
//
// In the tuning library (nearcap_tuning, src/analysis/device_profile_fit.cpp):
// part of the build tree, not installed, so that a consumer of nearcap needs
// no Ceres.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "nearcap/analysis/device_profile.hpp"

namespace nearcap::analysis {

// The whole frame a pass observation's frame belongs to: "C:lightK:M" (K
// digits) is "C:M"; any other name is its own.
std::string frame_of_pass(const std::string& pass_frame);

// How well a fitted profile predicts: median |predicted - measured| /
// measured over the observations, by pass kind and CPU task, on the
// observations it was fitted on and on those held out.
struct ProfileFitReport {
  std::array<double, kPassKindCount> train_median_relative_error{}, held_out_median_relative_error{};
  std::array<std::size_t, kPassKindCount> train_count{}, held_out_count{};
  std::array<double, 3> cpu_train_median_relative_error{}, cpu_held_out_median_relative_error{};
  std::array<std::size_t, 3> cpu_train_count{}, cpu_held_out_count{};  // by CpuTask
  // The median errors are NaN on a side without observations.
};

// The fit's loss: `robust` (the default) is Huber's on the log residual,
// scaled to the data; false is plain least squares on the same residual,
// which a few gross timing outliers pull off (the tests show how far).
struct ProfileFitOptions {
  bool robust = true;
};

// Fits each pass kind's (intercept, a, v, b), the silhouette's cost per
// thousand triangles and the clipped-sides cap's and the exact test's
// CpuTaskCost with Ceres, a robust loss and non-negative coefficients (a
// coefficient whose count is 0 in every training observation stays 0); observations whose frame hashes into the
// held-out fifth (FNV-1a(frame) % 5 == 0) only measure the error.  Kinds or tasks with no observation keep 0 and are
// reported as such. The residual is log(predicted) - log(measured): timing noise is multiplicative (a frame twice the
// work scatters twice as far), and the target is a relative error.  Measured times below a thousandth of the kind's
// median training time are read as that floor (a timer's zero). Silhouette observations of no triangles are skipped
// (that model has no intercept). A negative or non-finite count or time is an error (non-finite) naming the
// observation's frame.
DeviceProfile fit_device_profile(const std::vector<PassObservation>& passes, const std::vector<CpuObservation>& cpu,
                                 const std::string& gl_renderer, ProfileFitReport* report = nullptr,
                                 const ProfileFitOptions& options = {});

// The eye-count pass's row (DeviceProfile::eye_count), fitted as a pass
// kind's is, on the same held-out split; nothing when no observation is in
// the training side.  Calibrated at one viewport size, its fragments are
// the same in every observation: the split between the intercept and the
// per-fragment term is then the fit's, and only their sum at that size is
// measured.
struct EyeCountFitReport {
  double train_median_relative_error = 0, held_out_median_relative_error = 0;  // NaN on a side without observations
  std::size_t train_count = 0, held_out_count = 0;
};
std::optional<PassCost> fit_eye_count_pass(const std::vector<EyeCountObservation>& observations,
                                           EyeCountFitReport* report = nullptr, const ProfileFitOptions& options = {});

// The whole frame's row (DeviceProfile::frame), fitted on the frames
// whose frame hashes into the training side (FNV-1a(frame) % 5 != 0) with
// `profile`'s pass rows (and eye-count row) held fixed: a frame's predicted
// GL time is the sum of its passes' predictions (each observed pass priced
// with its observed counts) plus intercept_ms, less ms_saved_per_pass per
// pass, with 0 <= ms_saved_per_pass <= the smallest intercept among the
// profile's pass rows, intercept_ms >= 0, on the log residual with Huber's
// loss as the pass rows are.  A frame without a pass observation is
// skipped.  Nothing when no frame is on the training side.  The report
// gives the median relative error of the frame prediction, with the row and
// without it (the passes' sum alone), on each side.
struct FrameFitReport {
  double train_median_relative_error = 0, held_out_median_relative_error = 0;  // NaN on a side without frames
  double train_without_row = 0, held_out_without_row = 0;                      // the passes' sum alone
  std::size_t train_count = 0, held_out_count = 0;
};
std::optional<FrameCost> fit_frame_cost(const std::vector<FrameObservation>& frames,
                                        const std::vector<PassObservation>& passes,
                                        const std::vector<EyeCountObservation>& eye_count, const DeviceProfile& profile,
                                        FrameFitReport* report = nullptr, const ProfileFitOptions& options = {});

}  // namespace nearcap::analysis
