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

struct LightNearFit {
  double scale = 1;
  std::size_t train = 0, held_out = 0;  // configurations with a light frustum at every scale tried
  double train_objective = 0, train_objective_at_one = 0;
  double held_out_objective = 0, held_out_objective_at_one = 0;
  int iterations = 0;
};

// The mean log10 cond(P_l M_l) of the configurations at this scale (those
// whose light frustum is undefined at it are skipped; `counted` says how many).
double light_near_objective(const std::vector<const KnobConfiguration*>& configurations,
                            const gl::LightFrustumChoice& choice, double scale, std::size_t* counted = nullptr);

LightNearFit fit_light_near_scale(const std::vector<KnobConfiguration>& configurations,
                                  const gl::LightFrustumChoice& choice);

}  // namespace nearcap::analysis
