// nearcap/analysis/l_near_fit.hpp — the l_near safety margin fitted with
// Ceres by minimizing a smooth conditioning objective.
//
// The knob: l_near = scale * (the rule's l_near), scale in (0, 1] (the
// emulation's --l-near-scale; above 1 the cap could clip the occluder).  The
// objective: the mean over configurations of log10 cond(P_l M_l), the 2-norm
// condition number of the light transform the near-cap pass multiplies every
// vertex by (analysis/conditioning.hpp): to first order, the relative
// rounding error of the cap's clip coordinates is bounded by cond times the
// float32 unit roundoff (pbrt's gamma(n) argument), so a smaller cond is a
// smaller bound.  Ceres minimizes it over the training configurations
// (numeric derivatives: the matrices are float32), bounded to [1e-3, 1]; the
// held-out ones are evaluated at the fitted scale and at 1.  Whether the
// bound's optimum is an optimum of wrong pixels and cracks is then checked
// by a sweep (docs/findings/l-near.md).
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "nearcap/gl/light_frustum.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::analysis {

struct KnobConfiguration {
  std::string id;  // decides the split (held_out_configuration, policy_fit.hpp)
  Scene scene;
  std::size_t light = 0;
};

// The default start: the geometric middle of [1e-3, 1].
inline const double kLightNearScaleStart = std::sqrt(1e-3);

struct LightNearFit {
  double scale = 1;
  std::size_t train = 0, held_out = 0;  // (configuration, light) pairs with a light frustum at the fitted scale
  double train_objective = 0, train_objective_at_one = 0;
  double held_out_objective = 0, held_out_objective_at_one = 0;
  int iterations = 0;
};

// The mean log10 cond(P_l M_l) of the configurations at this scale (those
// whose light frustum is undefined at it are skipped; `counted` says how many).
double light_near_objective(const std::vector<const KnobConfiguration*>& configurations,
                            const gl::LightFrustumChoice& choice, double scale, std::size_t* counted = nullptr);

// Ceres minimizes the training configurations' mean objective over the
// scale in [1e-3, 1], from `start` (in that range).  The default starts at
// the range's geometric middle, away from both bounds: a start on a bound
// where the objective falls outward would end the solve at once, and a
// solve that never moved says nothing of where the minimum is.  On the
// sampler's configurations the objective falls all the way to scale 1 (a
// larger l_near is a better conditioned light projection), so the fit ends
// on that bound after a few iterations.
LightNearFit fit_light_near_scale(const std::vector<KnobConfiguration>& configurations,
                                  const gl::LightFrustumChoice& choice, double start = kLightNearScaleStart);

// The solve fit_light_near_scale runs, on any objective: minimizes
// mean_i term_i(scale) over scale in [lower, upper] from `start`, with each
// term >= 0 where finite (a term that is not finite at a trial scale refuses
// the step).  The unknown is log10(scale), so that the three decades of the
// range are equally easy to cross, and the derivatives are central
// differences of 0.001 in it (0.23 % of the scale): far above float32
// rounding in the matrices, far below the objective's curvature.  Needs
// 0 < lower < upper, lower <= start <= upper and a term (else an error,
// usage).  `iterations` counts Ceres' iterations, the start's included.
struct ScaleMinimum {
  double scale = 1;
  int iterations = 0;
};
ScaleMinimum minimize_mean_over_scale(const std::vector<std::function<double(double)>>& terms, double lower,
                                      double upper, double start);

}  // namespace nearcap::analysis
