// The l_near margin fitted on a conditioning objective (see l_near_fit.hpp).
#include "nearcap/analysis/l_near_fit.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <functional>
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

// One term's residual at u = log10(scale): sqrt(term), so that the sum of
// squares is the sum of the terms; its derivative a central difference with
// a fixed step in u (Ceres' numeric differences scale the step with |u|,
// which vanishes at scale 1, where the step would fall below float32
// rounding in the matrices).
class ScaleTerm : public ceres::SizedCostFunction<1, 1> {
 public:
  static constexpr double kStep = 1e-3;  // in log10(scale): 0.23 % of the scale
  explicit ScaleTerm(const std::function<double(double)>& term) : term_(term) {}
  bool Evaluate(double const* const* parameters, double* residual, double** jacobians) const override {
    const double u = parameters[0][0];
    double here = 0, up = 0, down = 0;
    if (!root(u, here)) return false;
    residual[0] = here;
    if (jacobians && jacobians[0]) {
      if (!root(u + kStep, up) || !root(u - kStep, down)) return false;
      jacobians[0][0] = (up - down) / (2 * kStep);
    }
    return true;
  }

 private:
  bool root(double u, double& out) const {
    const double v = term_(std::pow(10.0, u));
    if (!std::isfinite(v) || v < 0) return false;
    out = std::sqrt(v);
    return true;
  }
  const std::function<double(double)>& term_;
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

ScaleMinimum minimize_mean_over_scale(const std::vector<std::function<double(double)>>& terms, double lower,
                                      double upper, double start) {
  if (!(lower > 0 && lower < upper && start >= lower && start <= upper))
    throw Error(ErrorKind::Usage, "the scale fit needs 0 < lower < upper and a start between them");
  if (terms.empty()) throw Error(ErrorKind::Usage, "the scale fit has no term to minimize");
  double u = std::log10(start);
  ceres::Problem problem;
  for (const std::function<double(double)>& term : terms) problem.AddResidualBlock(new ScaleTerm(term), nullptr, &u);
  problem.SetParameterLowerBound(&u, 0, std::log10(lower));
  problem.SetParameterUpperBound(&u, 0, std::log10(upper));
  const ceres::Solver::Summary summary = solve_or_throw(problem, deterministic_solver_options(100), "l_near");
  ScaleMinimum m;
  m.scale = std::clamp(std::pow(10.0, u), lower, upper);
  m.iterations = static_cast<int>(summary.iterations.size());
  return m;
}

LightNearFit fit_light_near_scale(const std::vector<KnobConfiguration>& configurations,
                                  const gl::LightFrustumChoice& choice, double start) {
  // The configurations whose light frustum exists over the whole range.
  std::vector<const KnobConfiguration*> train, held;
  for (const KnobConfiguration& k : configurations) {
    if (!std::isfinite(log_condition(k, choice, 1.0)) || !std::isfinite(log_condition(k, choice, 1e-3))) continue;
    (held_out_configuration(k.id) ? held : train).push_back(&k);
  }
  if (train.empty()) throw Error(ErrorKind::Usage, "no configuration with a light frustum to fit l_near on");
  std::vector<std::function<double(double)>> terms;
  for (const KnobConfiguration* k : train)
    terms.emplace_back([k, &choice](double scale) { return log_condition(*k, choice, scale); });
  const ScaleMinimum minimum = minimize_mean_over_scale(terms, 1e-3, 1.0, start);
  const double scale = minimum.scale;
  LightNearFit fit;
  fit.scale = scale;
  fit.iterations = minimum.iterations;
  fit.train_objective = light_near_objective(train, choice, scale, &fit.train);
  fit.train_objective_at_one = light_near_objective(train, choice, 1.0);
  fit.held_out_objective = light_near_objective(held, choice, scale, &fit.held_out);
  fit.held_out_objective_at_one = light_near_objective(held, choice, 1.0);
  return fit;
}

}  // namespace nearcap::analysis
