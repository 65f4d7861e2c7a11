// nearcap tune RESULTS.csv... --out policy.json: fits the switch policy's
// crack model on sweep rows (analysis/policy_fit.hpp) and writes the policy.
#include <iostream>

#include "cli_commands.hpp"
#include "nearcap/analysis/policy_fit.hpp"
#include "nearcap/error.hpp"

namespace nearcap::cli {
namespace {

struct TuneOptions {
  std::vector<std::string> results;
  std::string out;
  std::string capped = "zpplus-corrected";
  std::string fallback = "zfail";
  std::string variant = "switch-clamp=clamp-far";
  bool plain = false;
};

void print_side(const char* name, const analysis::Confusion& c) {
  std::cout << "  " << name << ": " << c.samples << " (configuration, light) pairs, " << c.positives
            << " where the capped method cracks more than the fallback; predicted " << c.true_positives << " of them, "
            << c.false_positives << " false alarms\n";
}

void run(const TuneOptions& o, const std::string& command) {
  const auto capped = gl::shadow_method_from_string(o.capped);
  const auto fallback = gl::shadow_method_from_string(o.fallback);
  if (!capped || !gl::uses_near_cap(*capped))
    throw Error(ErrorKind::Usage, "--capped '" + o.capped + "' must be zpplus or zpplus-corrected");
  if (!fallback || (*fallback != gl::ShadowMethod::ZFail && *fallback != gl::ShadowMethod::Preload))
    throw Error(ErrorKind::Usage, "--fallback '" + o.fallback + "' must be zfail or preload");
  const std::vector<analysis::PolicySample> samples =
      analysis::policy_samples(o.results, *capped, *fallback, o.variant);
  analysis::LogisticFitOptions fit;
  fit.robust = !o.plain;
  const analysis::SwitchPolicy policy = analysis::tune_policy(samples, *capped, *fallback, command, fit);
  // The provenance holds the confusion tables; print them too.
  std::cout << "tune: " << samples.size() << " samples from " << o.results.size() << " file(s)\n";
  print_side("train", analysis::confusion(policy.crack_model, samples, false));
  print_side("held out", analysis::confusion(policy.crack_model, samples, true));
  std::cout << "  threshold " << policy.crack_model.threshold << "\n";
  io::write_output_files({{o.out, analysis::policy_to_json(policy)}});
  std::cout << "tune: wrote " << o.out << "\n";
}

}  // namespace

void register_tune(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "tune",
      "fit the switch policy's crack model (Ceres) on sweep CSVs and write policy.json (README \"The switch policy\")");
  auto o = std::make_shared<TuneOptions>();
  cmd->add_option("results", o->results, "sweep CSV files with rows of both methods")->required();
  cmd->add_option("--out", o->out, "the policy file to write")->required();
  cmd->add_option("--capped", o->capped, "the method for occluders that meet the light pyramid")->capture_default_str();
  cmd->add_option("--fallback", o->fallback, "the method where a crack is predicted")->capture_default_str();
  cmd->add_option("--variant", o->variant,
                  "the sweep variant whose rows are used: the policy's switch clamp (the sweep's own choices, "
                  "or one of its --variant)")
      ->capture_default_str();
  cmd->add_flag("--plain", o->plain, "plain logistic regression (no robust loss)");
  cmd->callback([o] {
    std::string command = "nearcap tune";
    for (const std::string& r : o->results) command += " " + r;
    command += " --out " + o->out;
    if (o->capped != "zpplus-corrected") command += " --capped " + o->capped;
    if (o->fallback != "zfail") command += " --fallback " + o->fallback;
    if (o->variant != "switch-clamp=clamp-far") command += " --variant " + o->variant;
    if (o->plain) command += " --plain";
    run(*o, command);
  });
}

}  // namespace nearcap::cli
