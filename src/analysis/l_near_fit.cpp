// The l_near margin fitted on a conditioning objective (see l_near_fit.hpp).
#include "nearcap/analysis/l_near_fit.hpp"

#include <ceres/ceres.h>

#include <cmath>
#include <limits>

#include "ceres_solve.hpp"
#include "nearcap/analysis/conditioning.hpp"
#include "nearcap/analysis/policy_fit.hpp"
#include "nearcap/error.hpp"

namespace nearcap::analysis {
namespace {

// log10 cond(P_l M_l) of one configuration at one scale; NaN without a frustum.
double log_condition(const KnobConfiguration& k, gl::LightFrustumChoice choice, double scale) {
  choice.near_scale = scale;
  const gl::LightFrustum lf = gl::light_frustum(k.scene, k.light, choice);
  if (!lf.defined) return std::numeric_limits<double>::quiet_NaN();
  const double cond = light_transform_condition(lf);
  return std::isfinite(cond) && cond >= 1 ? std::log10(cond) : std::numeric_limits<double>::quiet_NaN();
}

// One configuration's residual: sqrt(log10 cond), so that the sum of squares
// is the sum of the objective.
struct Residual {
  Residual(const KnobConfiguration& k, gl::LightFrustumChoice c) : k_(k), c_(c) {}
  bool operator()(const double* scale, double* r) const {
    const double v = log_condition(k_, c_, scale[0]);
    if (!std::isfinite(v)) return false;
    r[0] = std::sqrt(v);
    return true;
  }
  const KnobConfiguration& k_;
  gl::LightFrustumChoice c_;
};

}  // namespace

double light_near_objective(const std::vector<const KnobConfiguration*>& configurations,
                            const gl::LightFrustumChoice& choice, double scale, std::size_t* counted) {
  double sum = 0;
  std::size_t n = 0;
  for (const KnobConfiguration* k : configurations) {
    const double v = log_condition(*k, choice, scale);
    if (!std::isfinite(v)) continue;
    sum += v;
    ++n;
  }
  if (counted) *counted = n;
  return n ? sum / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
}

LightNearFit fit_light_near_scale(const std::vector<KnobConfiguration>& configurations,
                                  const gl::LightFrustumChoice& choice) {
  // The configurations whose light frustum exists over the whole range.
  std::vector<const KnobConfiguration*> train, held;
  for (const KnobConfiguration& k : configurations) {
    if (!std::isfinite(log_condition(k, choice, 1.0)) || !std::isfinite(log_condition(k, choice, 1e-3))) continue;
    (held_out_configuration(k.id) ? held : train).push_back(&k);
  }
  if (train.empty()) throw Error(ErrorKind::Usage, "no configuration with a light frustum to fit l_near on");
  double scale = 1.0;
  ceres::Problem problem;
  for (const KnobConfiguration* k : train)
    problem.AddResidualBlock(
        new ceres::NumericDiffCostFunction<Residual, ceres::CENTRAL, 1, 1>(new Residual(*k, choice)), nullptr, &scale);
  problem.SetParameterLowerBound(&scale, 0, 1e-3);
  problem.SetParameterUpperBound(&scale, 0, 1.0);
  const ceres::Solver::Summary summary = solve_or_throw(problem, deterministic_solver_options(100), "l_near");
  LightNearFit fit;
  fit.scale = scale;
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.train_objective = light_near_objective(train, choice, scale, &fit.train);
  fit.train_objective_at_one = light_near_objective(train, choice, 1.0);
  fit.held_out_objective = light_near_objective(held, choice, scale, &fit.held_out);
  fit.held_out_objective_at_one = light_near_objective(held, choice, 1.0);
  return fit;
}

}  // namespace nearcap::analysis
