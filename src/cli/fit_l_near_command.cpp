// nearcap fit-l-near: the l_near safety margin fitted with Ceres on a
// conditioning objective over hard cases of the sampler
// (analysis/l_near_fit.hpp).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "nearcap/analysis/l_near_fit.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/scene_file.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

struct FitOptions {
  SamplerOptions sampler;
  std::uint64_t samples = 2000;
  EmulationOptions emulation;
  std::string out;
};

// The emulation options the fit reads: those of the light frustum whose
// P_l M_l it conditions (its l_near scale is what it fits).
const std::vector<std::string> kFitEmulationOptions{"light-projection", "l-near"};

void run(const FitOptions& o) {
  if (o.samples == 0) throw Error(ErrorKind::Usage, "--samples must be at least 1");
  if (o.emulation.settings.light_frustum.projection == gl::LightProjection::ClippedSides)
    throw Error(ErrorKind::Usage,
                "--light-projection clipped-sides draws the near-cap without a light frustum: it has no l_near to "
                "fit");
  // The command that makes this fit again: every option it reads.
  std::string command = "nearcap fit-l-near --samples " + std::to_string(o.samples) + " --seed " +
                        std::to_string(o.sampler.seed) + " --kinds " + o.sampler.kinds + " --width " +
                        std::to_string(o.sampler.width) + " --height " + std::to_string(o.sampler.height);
  if (o.sampler.allow_bunny) command += " --allow-bunny";
  for (const auto& [name, value] : emulation_option_values(o.emulation))
    if (std::find(kFitEmulationOptions.begin(), kFitEmulationOptions.end(), name) != kFitEmulationOptions.end())
      command += " --" + name + " " + value;
  const analysis::SamplerSpec spec = sampler_spec(o.sampler);
  check_sampler_meshes(spec);
  if (!o.out.empty()) {  // before the fit
    refuse_replacing_inputs(o.out, sampler_inputs(spec), "--out");
    io::check_output_files({o.out});
  }
  const analysis::HardCaseSampler sampler(spec);
  std::vector<analysis::KnobConfiguration> configurations;
  for (std::uint64_t i = 0; i < o.samples; ++i) {
    const std::string id = "sample:" + std::to_string(o.sampler.seed) + ":" + std::to_string(i);
    try {
      const Scene s = parse_scene(sampler.sample(i).scene_json, id, ".");
      for (std::size_t l = 0; l < s.lights.size(); ++l) configurations.push_back({id, s, l});
    } catch (const Error&) {
      // the sweep's "rejected" configurations (a light inside an occluder)
    }
  }
  const gl::LightFrustumChoice choice = settings_from(o.emulation).light_frustum;
  const analysis::LightNearFit fit = analysis::fit_light_near_scale(configurations, choice);
  const nlohmann::json j{{"l_near_scale", fit.scale},
                         {"objective", "mean log10 cond(P_l M_l)"},
                         {"train",
                          {{"configuration_lights", fit.train},
                           {"at_fitted_scale", fit.train_objective},
                           {"at_scale_1", fit.train_objective_at_one}}},
                         {"held_out",
                          {{"configuration_lights", fit.held_out},
                           {"at_fitted_scale", fit.held_out_objective},
                           {"at_scale_1", fit.held_out_objective_at_one}}},
                         {"iterations", fit.iterations},
                         {"command", command}};
  std::cout << "fit-l-near: l_near scale " << fit.scale << " (" << fit.iterations << " iterations); mean log10 "
            << "cond(P_l M_l): train " << fit.train_objective << " (" << fit.train_objective_at_one << " at scale 1, "
            << fit.train << " (configuration, light) pairs), held out " << fit.held_out_objective << " ("
            << fit.held_out_objective_at_one << " at scale 1, " << fit.held_out << ")\n";
  if (!o.out.empty()) io::write_output_files({{o.out, json_file_text(j)}});
}

}  // namespace

void register_fit_l_near(CLI::App& app) {
  auto [cmd, o] =
      add_subcommand<FitOptions>(app, "fit-l-near",
                                 "fit the l_near safety margin (--l-near-scale) with Ceres, minimizing the mean "
                                 "log10 cond(P_l M_l) over hard cases of the sampler (docs/findings/l-near.md)",
                                 run);
  add_samples_option(cmd, o.samples, "this many configurations of the sampler", 1, kMaxFitSamples)
      ->capture_default_str();
  add_sampler_options(cmd, o.sampler, true);
  add_emulation_options(cmd, o.emulation, kFitEmulationOptions);
  cmd.add_option("--out", o.out, "write the fit as JSON here too");
}

}  // namespace nearcap::cli
