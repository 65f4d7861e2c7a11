// The measured-to-priced frame time ratio of the last frames (see
// frame_time_drift.hpp).
#include "nearcap/analysis/frame_time_drift.hpp"

#include <algorithm>
#include <cmath>

namespace nearcap::analysis {

FrameTimeDrift::FrameTimeDrift(std::size_t window) : window_(std::clamp<std::size_t>(window, 1, kWindow)) {}

void FrameTimeDrift::observe(double priced_ms, double measured_ms) {
  if (!(std::isfinite(priced_ms) && std::isfinite(measured_ms) && priced_ms > 0 && measured_ms > 0)) return;
  log_ratio_[observed_ % kWindow] = std::log(measured_ms / priced_ms);
  ++observed_;
}

double FrameTimeDrift::scale() const {
  const std::size_t n = std::min(observed_, window_);
  if (n == 0) return 1.0;
  std::array<double, kWindow> r{};  // the last n ratios
  for (std::size_t k = 0; k < n; ++k) r[k] = log_ratio_[(observed_ - 1 - k) % kWindow];
  std::sort(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(n));
  const double mid = n % 2 == 1 ? r[n / 2] : 0.5 * (r[n / 2 - 1] + r[n / 2]);
  return std::exp(mid);
}

}  // namespace nearcap::analysis
