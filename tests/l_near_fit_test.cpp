// The l_near margin fitted on the conditioning objective (analysis/
// l_near_fit.hpp): Ceres finds the minimum that a grid of scales shows, and
// the held-out configurations are scored at the fitted scale.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/analysis/l_near_fit.hpp"
#include "nearcap/analysis/policy_fit.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap {
namespace {

std::vector<analysis::KnobConfiguration> configurations(std::uint64_t seed, int count) {
  analysis::SamplerSpec spec;
  spec.seed = seed;
  spec.kinds = {analysis::HardCaseKind::LightNearNearPlane, analysis::HardCaseKind::Straddling,
                analysis::HardCaseKind::EyeInShadow, analysis::HardCaseKind::Grazing};
  spec.mesh_directory = std::string(NEARCAP_SOURCE_DIR) + "/data/meshes";
  const analysis::HardCaseSampler sampler(spec);
  std::vector<analysis::KnobConfiguration> out;
  for (int i = 0; i < count; ++i) {
    try {
      const std::string id = "sample:" + std::to_string(seed) + ":" + std::to_string(i);
      const Scene s = parse_scene(sampler.sample(static_cast<std::uint64_t>(i)).scene_json, id, ".");
      for (std::size_t l = 0; l < s.lights.size(); ++l) out.push_back({id, s, l});
    } catch (const Error&) {
      // a sampled light inside an occluder: not a configuration
    }
  }
  return out;
}

TEST(LightNearFit, CeresFindsTheGridMinimum) {
  const auto all = configurations(12, 80);
  ASSERT_GT(all.size(), 50u);
  const gl::LightFrustumChoice choice;
  const analysis::LightNearFit fit = analysis::fit_light_near_scale(all, choice);
  EXPECT_GT(fit.train, 30u);
  EXPECT_GT(fit.held_out, 5u);
  EXPECT_GT(fit.scale, 0.0);
  EXPECT_LE(fit.scale, 1.0);
  // The same training set, on a grid: nothing below the fitted objective.
  std::vector<const analysis::KnobConfiguration*> train;
  for (const auto& k : all)
    if (std::isfinite(analysis::light_near_objective({&k}, choice, 1.0)) &&
        std::isfinite(analysis::light_near_objective({&k}, choice, 1e-3)) && !analysis::held_out_configuration(k.id))
      train.push_back(&k);
  ASSERT_EQ(train.size(), fit.train);
  for (double s : {0.001, 0.01, 0.05, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0})
    EXPECT_LE(fit.train_objective, analysis::light_near_objective(train, choice, s) + 1e-3) << "scale " << s;
  EXPECT_TRUE(std::isfinite(fit.held_out_objective));
}

}  // namespace
}  // namespace nearcap
