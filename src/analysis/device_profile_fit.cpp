// Fitting a device cost profile with Ceres (see device_profile_fit.hpp).
//
// Each pass kind is one small problem: ms ~ intercept + a * Mtriangles +
// v * Min_view + b * Mfragments, four non-negative unknowns (three where
// no training observation has a triangle in view: the eye-count pass); the silhouette one unknown,
// ms ~ c * ktriangles; the clipped-sides cap and the exact test six,
// ms ~ intercept + the five counts' (CpuTaskWork) coefficients.  The arrangement, and why:
// - The residual is log(predicted) - log(measured).  Timings scatter in
//   proportion to their size (a frame of twice the work varies twice as
//   much), so an absolute residual would let the largest frames decide and
//   leave the small ones, where the intercept matters, badly predicted; the
//   log residual weighs every frame by its relative error, which is what the
//   report and the decision compare.  It is symmetric: a frame preempted to
//   10x its time and a timer that read 1/10 of it pull equally.
// - The loss is Huber's, in two solves: the first with delta = 0.1 (a 10 %
//   timing scatter, a prior that only sets which residuals count as gross),
//   the second with delta = 1.345 sigma, sigma the residuals' scatter after
//   the first (1.4826 times their median absolute value, the normal's MAD
//   factor), 1.345 being Huber's 95 %-efficiency constant.  Huber's loss is
//   convex in the residual, so the fit has no spurious minimum to fall into.
// - The unknowns are scaled to be of order 1: the prediction is
//   m (theta_0 + theta_1 t / s_t + theta_2 f / s_f), with m the kind's median
//   training time and s_t, s_f the mean training triangle and fragment
//   counts; a ms-per-million-fragments slope and an intercept in ms would
//   otherwise differ by orders of magnitude and the trust region would see a
//   badly conditioned problem.  Non-negativity is a bound on each theta.
#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "ceres_solve.hpp"
#include "nearcap/analysis/device_profile_fit.hpp"
#include "nearcap/analysis/policy_fit.hpp"
#include "nearcap/error.hpp"

namespace nearcap::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// log(theta . x) - y; an evaluation at a non-positive prediction is refused
// (Ceres then shortens the step).
template <int N>
struct LogResidual {
  LogResidual(const std::array<double, N>& x, double y) : x_(x), y_(y) {}
  template <class T>
  bool operator()(const T* theta, T* residual) const {
    T predicted = T(0);
    for (int j = 0; j < N; ++j) predicted += theta[j] * x_[static_cast<std::size_t>(j)];
    if (!(predicted > T(0))) return false;
    using std::log;
    residual[0] = log(predicted) - T(y_);
    return true;
  }
  std::array<double, N> x_;
  double y_;
};

// A whole frame's log residual (fit_frame_cost): log(passes - s n + f) -
// y, the unknowns (s, f) and the passes' sum in units of the frames'
// median time.
struct FrameResidual {
  FrameResidual(double passes, double drawn, double y) : passes_(passes), drawn_(drawn), y_(y) {}
  template <class T>
  bool operator()(const T* saved, const T* intercept, T* residual) const {
    const T predicted = T(passes_) - saved[0] * T(drawn_) + intercept[0];
    if (!(predicted > T(0))) return false;
    using std::log;
    residual[0] = log(predicted) - T(y_);
    return true;
  }
  double passes_, drawn_, y_;
};

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// A fitted coefficient in milliseconds per unit of its count: theta, in
// units of the training median time m per `scale` (the count's training
// mean; 1 for an intercept), is m theta / scale.  A count a handful of
// observations hold a few of (a dark cap of one fragment in a 32x24 frame)
// can ask for more than a profile holds; the fit keeps theta within
// theta_bound, and the rounding of m theta / scale is taken off here.
double coefficient_ms(double m, double theta, double scale) {
  return std::min(kMaxCostCoefficientMs, m * theta / scale);
}
double theta_bound(double m, double scale) { return kMaxCostCoefficientMs * scale / m; }

// Minimizes sum rho(log(theta . x_i) - y_i) over 0 <= theta <= upper from
// `theta` (a start above a bound starts on it).
template <int N>
void solve_log_linear(const std::vector<std::array<double, N>>& x, const std::vector<double>& y, bool robust,
                      const std::string& what, const std::array<double, N>& upper, std::array<double, N>& theta) {
  for (std::size_t j = 0; j < static_cast<std::size_t>(N); ++j) theta[j] = std::min(theta[j], upper[j]);
  auto solve = [&](double delta) {
    ceres::Problem problem;
    for (std::size_t i = 0; i < x.size(); ++i)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LogResidual<N>, 1, N>(new LogResidual<N>(x[i], y[i])),
                               robust ? new ceres::HuberLoss(delta) : nullptr, theta.data());
    for (int j = 0; j < N; ++j) {
      problem.SetParameterLowerBound(theta.data(), j, 0.0);
      problem.SetParameterUpperBound(theta.data(), j, upper[static_cast<std::size_t>(j)]);
    }
    solve_or_throw(problem, deterministic_solver_options(200), what);
  };
  solve(0.1);
  if (!robust) return;
  std::vector<double> abs_residual;
  for (std::size_t i = 0; i < x.size(); ++i) {
    double predicted = 0;
    for (std::size_t j = 0; j < static_cast<std::size_t>(N); ++j) predicted += theta[j] * x[i][j];
    abs_residual.push_back(std::fabs(std::log(predicted) - y[i]));
  }
  const double sigma = 1.4826 * median(abs_residual);
  solve(1.345 * std::clamp(sigma, 1e-3, 1.0));
}

void check_measure(double v, const char* what, const std::string& frame, const char* observation) {
  if (!std::isfinite(v))
    throw Error(ErrorKind::NonFinite, std::string("device profile fit: the ") + observation + " of frame '" + frame +
                                          "': " + what + " is not finite");
  if (v < 0)
    throw Error(ErrorKind::Usage, std::string("device profile fit: the ") + observation + " of frame '" + frame +
                                      "': " + what + " is negative");
}

struct Side {
  std::vector<double> errors;
  std::size_t count = 0;
};

// Median |predicted - measured| / measured of the observations with a
// positive measured time; NaN without any.
double median_error(const Side& s) { return median(s.errors); }

// One pass row's (intercept, a, b) fitted on `train`, and its median
// relative error on each side (see fit_device_profile).
PassCost fit_pass_cost(const std::vector<const PassObservation*>& train,
                       const std::vector<const PassObservation*>& held, const ProfileFitOptions& options,
                       const std::string& what, double& train_error, std::size_t& train_count, double& held_error,
                       std::size_t& held_count) {
  PassCost cost;
  std::vector<double> times;
  double mean_t = 0, mean_f = 0, mean_v = 0;
  for (const PassObservation* o : train) {
    times.push_back(o->ms);
    mean_t += o->triangles * 1e-6 / static_cast<double>(train.size());
    mean_f += o->fragments * 1e-6 / static_cast<double>(train.size());
    mean_v += o->in_view * 1e-6 / static_cast<double>(train.size());
  }
  const double m = median(times);
  if (m > 0) {
    const double s_t = mean_t > 0 ? mean_t : 1.0, s_f = mean_f > 0 ? mean_f : 1.0;
    std::vector<double> y;
    for (const PassObservation* o : train) y.push_back(std::log(std::max(o->ms, 1e-3 * m) / m));
    // A count that is 0 in every training observation leaves its coefficient
    // at its start, multiplying nothing: 0.
    if (mean_v > 0) {
      std::vector<std::array<double, 4>> x;
      for (const PassObservation* o : train)
        x.push_back({1.0, o->triangles * 1e-6 / s_t, o->fragments * 1e-6 / s_f, o->in_view * 1e-6 / mean_v});
      std::array<double, 4> theta{0.4, 0.2, 0.2, 0.2};
      solve_log_linear<4>(x, y, options.robust, what,
                          {theta_bound(m, 1.0), theta_bound(m, s_t), theta_bound(m, s_f), theta_bound(m, mean_v)},
                          theta);
      cost.intercept_ms = coefficient_ms(m, theta[0], 1.0);
      cost.ms_per_mtriangle = mean_t > 0 ? coefficient_ms(m, theta[1], s_t) : 0.0;
      cost.ms_per_mfragment = mean_f > 0 ? coefficient_ms(m, theta[2], s_f) : 0.0;
      cost.ms_per_mtriangle_in_view = coefficient_ms(m, theta[3], mean_v);
    } else {
      std::vector<std::array<double, 3>> x;
      for (const PassObservation* o : train) x.push_back({1.0, o->triangles * 1e-6 / s_t, o->fragments * 1e-6 / s_f});
      std::array<double, 3> theta{0.4, 0.3, 0.3};
      solve_log_linear<3>(x, y, options.robust, what, {theta_bound(m, 1.0), theta_bound(m, s_t), theta_bound(m, s_f)},
                          theta);
      cost.intercept_ms = coefficient_ms(m, theta[0], 1.0);
      cost.ms_per_mtriangle = mean_t > 0 ? coefficient_ms(m, theta[1], s_t) : 0.0;
      cost.ms_per_mfragment = mean_f > 0 ? coefficient_ms(m, theta[2], s_f) : 0.0;
    }
  }
  for (const auto& [side, error, count] :
       {std::tuple{&train, &train_error, &train_count}, std::tuple{&held, &held_error, &held_count}}) {
    Side s;
    s.count = side->size();
    for (const PassObservation* o : *side)
      if (o->ms > 0) {
        const double predicted = cost.ms(o->triangles, o->fragments, o->in_view);
        s.errors.push_back(std::fabs(predicted - o->ms) / o->ms);
      }
    *error = median_error(s);
    *count = s.count;
  }
  return cost;
}

}  // namespace

std::optional<PassCost> fit_eye_count_pass(const std::vector<EyeCountObservation>& observations,
                                           EyeCountFitReport* report, const ProfileFitOptions& options) {
  std::vector<PassObservation> as_passes;
  for (const EyeCountObservation& o : observations) {
    check_measure(o.triangles, "the triangle count", o.frame, "eye-count observation");
    check_measure(o.fragments, "the fragment count", o.frame, "eye-count observation");
    check_measure(o.ms, "the time", o.frame, "eye-count observation");
    as_passes.push_back({o.frame, PassKind::Depth, o.triangles, o.fragments, o.ms});
  }
  std::vector<const PassObservation*> train, held;
  for (const PassObservation& o : as_passes) (held_out_configuration(o.frame) ? held : train).push_back(&o);
  EyeCountFitReport r;
  const PassCost cost = fit_pass_cost(train, held, options, "eye-count pass cost", r.train_median_relative_error,
                                      r.train_count, r.held_out_median_relative_error, r.held_out_count);
  if (report) *report = r;
  if (train.empty()) return std::nullopt;
  return cost;
}

std::string frame_of_pass(const std::string& pass_frame) {
  const std::size_t last = pass_frame.rfind(':');
  if (last == std::string::npos || last == 0 || last + 1 == pass_frame.size()) return pass_frame;
  const std::size_t before = pass_frame.rfind(':', last - 1);
  const std::size_t start = before == std::string::npos ? 0 : before + 1;
  const std::string_view light = std::string_view(pass_frame).substr(start, last - start);
  if (light.size() <= 5 || light.substr(0, 5) != "light") return pass_frame;
  for (char c : light.substr(5))
    if (c < '0' || c > '9') return pass_frame;
  // "C:lightK:M" -> "C:M"; "lightK:M" -> "M".
  return pass_frame.substr(0, start == 0 ? 0 : start - 1) +
         (start == 0 ? pass_frame.substr(last + 1) : pass_frame.substr(last));
}

std::optional<FrameCost> fit_frame_cost(const std::vector<FrameObservation>& frames,
                                        const std::vector<PassObservation>& passes,
                                        const std::vector<EyeCountObservation>& eye_count, const DeviceProfile& profile,
                                        FrameFitReport* report, const ProfileFitOptions& options) {
  // Each frame's passes: the sum of their predictions (each priced with its
  // own counts, its intercept included) and how many were drawn.
  struct Passes {
    double ms = 0, drawn = 0;
  };
  std::map<std::string, Passes> by_frame;
  auto add = [&by_frame](const std::string& frame, const PassCost& c, double triangles, double fragments,
                         double in_view) {
    Passes& p = by_frame[frame_of_pass(frame)];
    p.ms += c.ms(triangles, fragments, in_view);
    p.drawn += 1;
  };
  for (const PassObservation& o : passes)
    add(o.frame, profile.passes[static_cast<std::size_t>(o.kind)], o.triangles, o.fragments, o.in_view);
  if (profile.eye_count)
    for (const EyeCountObservation& o : eye_count) add(o.frame, *profile.eye_count, o.triangles, o.fragments, 0);
  double smallest_intercept = INFINITY;
  for (const PassCost& c : profile.passes) smallest_intercept = std::min(smallest_intercept, c.intercept_ms);
  if (profile.eye_count) smallest_intercept = std::min(smallest_intercept, profile.eye_count->intercept_ms);
  struct Frame {
    Passes passes;
    double ms = 0;
  };
  std::vector<Frame> train, held;
  for (const FrameObservation& o : frames) {
    check_measure(o.ms, "the time", o.frame, "frame observation");
    const auto p = by_frame.find(o.frame);
    if (p == by_frame.end() || !(o.ms > 0)) continue;
    (held_out_configuration(o.frame) ? held : train).push_back({p->second, o.ms});
  }
  FrameCost cost;
  std::vector<double> times;
  for (const Frame& f : train) times.push_back(f.ms);
  const double m = median(times);
  if (!train.empty() && m > 0) {
    // In units of m: s' = s / m in [0, smallest intercept / m], f' = f / m >= 0.
    // The start is inside the bounds: half the largest saving, a tenth of
    // the median frame; each pass's prediction is at least its intercept,
    // so the start predicts every frame positive.
    const bool can_save = smallest_intercept > 0;
    std::array<double, 1> saved{can_save ? 0.5 * smallest_intercept / m : 0.0},
        intercept{std::min(0.1, theta_bound(m, 1.0))};
    auto solve = [&](double delta) {
      ceres::Problem problem;
      for (const Frame& f : train)
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<FrameResidual, 1, 1, 1>(
                                     new FrameResidual(f.passes.ms / m, f.passes.drawn, std::log(f.ms / m))),
                                 options.robust ? new ceres::HuberLoss(delta) : nullptr, saved.data(),
                                 intercept.data());
      if (can_save) {
        problem.SetParameterLowerBound(saved.data(), 0, 0.0);
        problem.SetParameterUpperBound(saved.data(), 0, smallest_intercept / m);
      } else {
        problem.SetParameterBlockConstant(saved.data());
      }
      problem.SetParameterLowerBound(intercept.data(), 0, 0.0);
      problem.SetParameterUpperBound(intercept.data(), 0, theta_bound(m, 1.0));
      solve_or_throw(problem, deterministic_solver_options(200), "whole frame cost");
    };
    solve(0.1);
    if (options.robust) {
      std::vector<double> abs_residual;
      for (const Frame& f : train)
        abs_residual.push_back(
            std::fabs(std::log(f.passes.ms / m - saved[0] * f.passes.drawn + intercept[0]) - std::log(f.ms / m)));
      solve(1.345 * std::clamp(1.4826 * median(abs_residual), 1e-3, 1.0));
    }
    cost.ms_saved_per_pass = std::min(m * saved[0], smallest_intercept);
    cost.intercept_ms = coefficient_ms(m, intercept[0], 1.0);
  }
  FrameFitReport r;
  for (const auto& [side, with, without, count] :
       {std::tuple{&train, &r.train_median_relative_error, &r.train_without_row, &r.train_count},
        std::tuple{&held, &r.held_out_median_relative_error, &r.held_out_without_row, &r.held_out_count}}) {
    std::vector<double> e_with, e_without;
    for (const Frame& f : *side) {
      const double predicted = f.passes.ms - cost.ms_saved_per_pass * f.passes.drawn + cost.intercept_ms;
      e_with.push_back(std::fabs(predicted - f.ms) / f.ms);
      e_without.push_back(std::fabs(f.passes.ms - f.ms) / f.ms);
    }
    *with = median(e_with);
    *without = median(e_without);
    *count = side->size();
  }
  if (report) *report = r;
  if (train.empty() || !(m > 0)) return std::nullopt;
  return cost;
}

DeviceProfile fit_device_profile(const std::vector<PassObservation>& passes, const std::vector<CpuObservation>& cpu,
                                 const std::string& gl_renderer, ProfileFitReport* report,
                                 const ProfileFitOptions& options) {
  for (const PassObservation& o : passes) {
    check_measure(o.triangles, "the triangle count", o.frame, "pass observation");
    check_measure(o.fragments, "the fragment count", o.frame, "pass observation");
    check_measure(o.in_view, "the in-view triangle count", o.frame, "pass observation");
    check_measure(o.ms, "the time", o.frame, "pass observation");
  }
  for (const CpuObservation& o : cpu) {
    check_measure(o.triangles, "the triangle count", o.frame, "CPU observation");
    check_measure(o.reaching, "the reaching count", o.frame, "CPU observation");
    check_measure(o.tested, "the tested count", o.frame, "CPU observation");
    check_measure(o.straddling, "the straddling count", o.frame, "CPU observation");
    check_measure(o.examined, "the examined count", o.frame, "CPU observation");
    check_measure(o.ms, "the time", o.frame, "CPU observation");
  }
  DeviceProfile profile;
  profile.gl_renderer = gl_renderer;
  profile.origin = "calibrated";
  ProfileFitReport r;

  for (std::size_t k = 0; k < kPassKindCount; ++k) {
    std::vector<const PassObservation*> train, held;
    for (const PassObservation& o : passes)
      if (static_cast<std::size_t>(o.kind) == k) (held_out_configuration(o.frame) ? held : train).push_back(&o);
    profile.passes[k] = fit_pass_cost(train, held, options, std::string(kPassKindNames[k]) + " pass cost",
                                      r.train_median_relative_error[k], r.train_count[k],
                                      r.held_out_median_relative_error[k], r.held_out_count[k]);
  }

  // The silhouette: one unknown, ms per thousand occluder triangles.
  // The clipped-sides cap and the exact test: CpuTaskCost's six, each
  // count scaled by its training mean (a count that is 0 in every training
  // observation keeps its coefficient at 0).
  static constexpr std::array<const char*, 3> kTaskNames{"silhouette CPU cost", "clipped cap CPU cost",
                                                         "exact test CPU cost"};
  constexpr std::size_t kCounts = 6;
  auto counts = [](const CpuObservation& o) -> std::array<double, kCounts> {
    return {1.0, o.triangles * 1e-3, o.reaching * 1e-3, o.tested * 1e-3, o.straddling * 1e-3, o.examined * 1e-3};
  };
  for (std::size_t task = 0; task < 3; ++task) {
    const bool silhouette = task == static_cast<std::size_t>(CpuTask::Silhouette);
    std::vector<const CpuObservation*> train, held;
    for (const CpuObservation& o : cpu)
      if (static_cast<std::size_t>(o.task) == task && (!silhouette || o.triangles > 0))
        (held_out_configuration(o.frame) ? held : train).push_back(&o);
    std::vector<double> times;
    std::array<double, kCounts> mean{};
    for (const CpuObservation* o : train) {
      times.push_back(o->ms);
      const std::array<double, kCounts> c = counts(*o);
      for (std::size_t j = 0; j < kCounts; ++j) mean[j] += c[j] / static_cast<double>(train.size());
    }
    const double m = median(times);
    CpuTaskCost cost;  // the silhouette's per-ktriangle cost in ms_per_ktriangle
    if (m > 0) {
      std::vector<double> y;
      for (const CpuObservation* o : train) y.push_back(std::log(std::max(o->ms, 1e-3 * m) / m));
      if (silhouette) {
        std::vector<std::array<double, 1>> x;
        for (const CpuObservation* o : train) x.push_back({o->triangles * 1e-3 / mean[1]});
        std::array<double, 1> theta{1.0};
        solve_log_linear<1>(x, y, options.robust, kTaskNames[task], {theta_bound(m, mean[1])}, theta);
        cost.ms_per_ktriangle = coefficient_ms(m, theta[0], mean[1]);
      } else {
        std::vector<std::array<double, kCounts>> x;
        for (const CpuObservation* o : train) {
          const std::array<double, kCounts> c = counts(*o);
          std::array<double, kCounts>& row = x.emplace_back();
          for (std::size_t j = 0; j < kCounts; ++j) row[j] = mean[j] > 0 ? c[j] / mean[j] : 0.0;
        }
        std::array<double, kCounts> theta{0.2, 0.2, 0.2, 0.2, 0.2, 0.2}, upper{};
        for (std::size_t j = 0; j < kCounts; ++j) upper[j] = theta_bound(m, mean[j] > 0 ? mean[j] : 1.0);
        solve_log_linear<static_cast<int>(kCounts)>(x, y, options.robust, kTaskNames[task], upper, theta);
        std::array<double, kCounts> coefficient{};
        for (std::size_t j = 0; j < kCounts; ++j)
          coefficient[j] = mean[j] > 0 ? coefficient_ms(m, theta[j], mean[j]) : 0.0;
        cost = {coefficient[0], coefficient[1], coefficient[2], coefficient[3], coefficient[4], coefficient[5]};
      }
    }
    if (silhouette)
      profile.cpu.ms_per_ktriangle_silhouette = cost.ms_per_ktriangle;
    else
      (task == static_cast<std::size_t>(CpuTask::ClippedCap) ? profile.cpu.clipped_cap : profile.cpu.exact_test) = cost;
    for (const auto& [side, error, count] :
         {std::tuple{&train, &r.cpu_train_median_relative_error[task], &r.cpu_train_count[task]},
          std::tuple{&held, &r.cpu_held_out_median_relative_error[task], &r.cpu_held_out_count[task]}}) {
      Side s;
      s.count = side->size();
      for (const CpuObservation* o : *side)
        if (o->ms > 0) {
          const double predicted = silhouette ? cost.ms_per_ktriangle * o->triangles * 1e-3 : cost.ms(o->work());
          s.errors.push_back(std::fabs(predicted - o->ms) / o->ms);
        }
      *error = median_error(s);
      *count = s.count;
    }
  }
  if (report) *report = r;
  return profile;
}

}  // namespace nearcap::analysis
