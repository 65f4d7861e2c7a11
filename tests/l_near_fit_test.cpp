// The l_near margin fitted on the conditioning objective (analysis/
// l_near_fit.hpp): Ceres finds the minimum that a grid of scales shows, and
// the held-out configurations are scored at the fitted scale.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>

#include "cli_support.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/analysis/l_near_fit.hpp"
#include "nearcap/analysis/policy_fit.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "support/sampled_scenes.hpp"

namespace nearcap {
namespace {

std::vector<analysis::KnobConfiguration> configurations(std::uint64_t seed, int count) {
  analysis::SamplerSpec spec = test::bundled_sampler_spec(seed);
  spec.kinds = {analysis::HardCaseKind::LightNearNearPlane, analysis::HardCaseKind::Straddling,
                analysis::HardCaseKind::EyeInShadow, analysis::HardCaseKind::Grazing};
  std::vector<analysis::KnobConfiguration> out;
  test::for_each_sampled_scene(analysis::HardCaseSampler(spec), static_cast<std::uint64_t>(count),
                               [&](const Scene& s, const analysis::HardCase& sample) {
                                 const std::string id =
                                     "sample:" + std::to_string(seed) + ":" + std::to_string(sample.index);
                                 for (std::size_t l = 0; l < s.lights.size(); ++l) out.push_back({id, s, l});
                               });
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
  // From the default start, inside the range: the solve moves (an iteration
  // past the start's) and ends where the grid's minimum is, on the bound at 1
  // (the objective falls with the scale on these configurations).
  EXPECT_GT(fit.iterations, 1);
  EXPECT_GT(fit.scale, 0.99);
}

// An objective with its minimum inside the range, from starts away from it
// (both bounds and the far side): the solve finds the minimum.  The terms
// are 1 + c_i (log10 s - log10 m_i)^2 with minima m_i at 0.05, 0.2 and 0.4;
// their mean is smallest at log10 s* = sum c_i log10 m_i / sum c_i.  The
// solve works in log10 s, where this mean is a parabola: Gauss-Newton on the
// square roots converges to s* to the solver's tolerance; 1e-3 relative is
// far looser than that and far tighter than any neighbouring grid point.
TEST(LightNearFit, FindsAnInteriorMinimumFromAStartAwayFromIt) {
  const double minima[] = {0.05, 0.2, 0.4}, weights[] = {1.0, 2.0, 3.0};
  std::vector<std::function<double(double)>> terms;
  double num = 0, den = 0;
  for (int i = 0; i < 3; ++i) {
    const double m = minima[i], c = weights[i];
    terms.emplace_back([m, c](double s) { return 1 + c * std::pow(std::log10(s) - std::log10(m), 2); });
    num += c * std::log10(m);
    den += c;
  }
  const double best = std::pow(10.0, num / den);
  ASSERT_GT(best, 0.1);
  ASSERT_LT(best, 0.4);
  for (double start : {1.0, 1e-3, 0.9, analysis::kLightNearScaleStart}) {
    const analysis::ScaleMinimum m = analysis::minimize_mean_over_scale(terms, 1e-3, 1.0, start);
    EXPECT_NEAR(m.scale, best, 1e-3 * best) << "start " << start;
    EXPECT_GT(m.iterations, 1) << "start " << start;
  }
  // A minimum beyond the range: the solve stops on the bound.
  const std::vector<std::function<double(double)>> falling{[](double s) { return 2 - std::log10(s) / 4; }};
  EXPECT_NEAR(analysis::minimize_mean_over_scale(falling, 1e-3, 1.0, 0.01).scale, 1.0, 1e-9);
  EXPECT_THROW(analysis::minimize_mean_over_scale(terms, 1e-3, 1.0, 2.0), Error);
}

// `nearcap fit-l-near --out`: the counts are (configuration, light) pairs,
// named so in the JSON and on stdout, the train count the same in both.
TEST(LightNearFit, TheCommandWritesItsCountsByName) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("nearcap_fit_l_near_" + std::to_string(::getpid()) + ".json");
  const test::CliResult r =
      test::run_cli("fit-l-near --samples 10 --kinds several-lights --out '" + out.string() + "'", "fit_l_near");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(test::slurp(out));
  std::filesystem::remove(out);
  const std::size_t train = j.at("train").at("configuration_lights").get<std::size_t>();
  const std::size_t held_out = j.at("held_out").at("configuration_lights").get<std::size_t>();
  EXPECT_GT(train + held_out, 10u);  // several lights per configuration
  EXPECT_NE(r.out.find(", " + std::to_string(train) + " (configuration, light) pairs)"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace nearcap
