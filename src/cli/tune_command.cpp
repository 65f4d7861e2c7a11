// nearcap tune RESULTS.csv... --out policy.json: fits the switch policy's
// crack model on sweep rows (analysis/policy_fit.hpp) and writes the policy.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <system_error>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "nearcap/analysis/policy_fit.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/output_files.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

struct TuneOptions {
  std::vector<std::string> results;
  std::string out;
  std::string capped = "zpplus-corrected";
  std::string fallback = "zfail";
  std::string variant = "switch-clamp=clamp-far";
  bool plain = false;
  std::string features = "all";
  bool features_given = false;  // --features on the command line (else "all", "none" with --no-exact-zpass)
  gl::LightProjection light_projection = gl::LightProjection::Paper;
  bool no_exact_zpass = false;
  std::optional<gl::DepthFormat> depth;           // nullopt: not written
  std::optional<gl::DepthMapping> depth_mapping;  // nullopt: not written
  std::optional<gl::NearPlane> near_plane;        // nullopt: not written
};

// The command line that makes this fit again, written into the policy: the
// options that differ from their defaults.
std::string command_line(const TuneOptions& o) {
  std::string command = "nearcap tune";
  for (const std::string& r : o.results) command += " " + r;
  command += " --out " + o.out;
  if (o.capped != "zpplus-corrected") command += " --capped " + o.capped;
  if (o.fallback != "zfail") command += " --fallback " + o.fallback;
  if (o.variant != "switch-clamp=clamp-far") command += " --variant " + o.variant;
  if (o.plain) command += " --plain";
  if (o.features != "all") command += " --features " + o.features;
  if (o.light_projection != gl::LightProjection::Paper)
    command += " --light-projection " + std::string(name_of(o.light_projection));
  if (o.no_exact_zpass) command += " --no-exact-zpass";
  if (o.depth) command += " --depth " + std::string(name_of(*o.depth));
  if (o.depth_mapping) command += " --depth-mapping " + std::string(name_of(*o.depth_mapping));
  if (o.near_plane) command += " --near-plane " + std::string(name_of(*o.near_plane));
  return command;
}

// The emulation choices of the sweep variant named `label`: a label lists
// the choices that differ from the defaults ("default": none).
std::map<std::string, std::string> variant_choices(const std::string& label) {
  std::map<std::string, std::string> choices;
  for (const auto& [name, value] : emulation_option_values(EmulationOptions{})) choices[name] = value;
  if (label == "default") return choices;
  for (const std::string& part : comma_separated(label))
    if (const std::size_t eq = part.find('='); eq != std::string::npos)
      choices[part.substr(0, eq)] = part.substr(eq + 1);
  return choices;
}

// A crack model predicts the cracks of the frames its rows drew: a policy
// that carries one must draw with the rows' variant's cap and depth choices.
void refuse_choices_the_rows_lack(const TuneOptions& o) {
  const std::map<std::string, std::string> rows = variant_choices(o.variant);
  std::vector<std::pair<std::string, std::string>> policy{
      {"light-projection", std::string(name_of(o.light_projection))}};
  if (o.depth) policy.emplace_back("depth", std::string(name_of(*o.depth)));
  if (o.depth_mapping) policy.emplace_back("depth-mapping", std::string(name_of(*o.depth_mapping)));
  if (o.near_plane) policy.emplace_back("near-plane", std::string(name_of(*o.near_plane)));
  for (const auto& [name, value] : policy) {
    const auto drawn = rows.find(name);
    if (drawn != rows.end() && drawn->second != value)
      throw Error(ErrorKind::Usage, "--" + name + " " + value + ": the rows of variant '" + o.variant +
                                        "' were drawn with " + name + "=" + drawn->second +
                                        ", so a crack model fitted on them predicts other frames' cracks; tune on "
                                        "a variant with " +
                                        name + "=" + value + ", or add --features none");
  }
}

void run(const TuneOptions& given) {
  TuneOptions o = given;
  // The variant as the sweep labels its rows: its choices in the sweep's
  // order, whatever order --variant gives them in.
  if (o.variant != "default") o.variant = variant_label(with_variant(EmulationOptions{}, o.variant));
  // With --no-exact-zpass the decision reads no crack model: none is fitted
  // unless --features asks for one (refused below).
  if (o.no_exact_zpass && !o.features_given) o.features = "none";
  const std::string command = command_line(o);
  if (o.plain && o.features == "none")
    throw Error(ErrorKind::Usage, "--plain is read only when a crack model is fitted (not --features none)");
  for (const std::string& input : o.results) refuse_replacing_inputs(o.out, {{input, "sweep CSV"}});
  io::check_output_files({o.out});  // before the fits: a directory or a socket is refused now
  const auto capped = gl::shadow_method_from_string(o.capped);
  const auto fallback = gl::shadow_method_from_string(o.fallback);
  if (!capped || !gl::uses_near_cap(*capped))
    throw Error(ErrorKind::Usage, "--capped '" + o.capped + "' must be zpplus or zpplus-corrected");
  if (!fallback || (*fallback != gl::ShadowMethod::ZFail && *fallback != gl::ShadowMethod::Preload))
    throw Error(ErrorKind::Usage, "--fallback '" + o.fallback + "' must be zfail or preload");
  const bool crack_model = o.features != "none";
  const std::vector<std::string> given_features = comma_separated(o.features);
  if (o.features != "all" && o.features != "none") {
    for (const std::string& name : given_features) {
      if (name.empty()) throw Error(ErrorKind::Usage, "--features '" + o.features + "': an empty feature name");
      refuse_list_word("--features", name, {"all", "none"});
    }
    for (const std::string& name : given_features) {
      if (std::count(given_features.begin(), given_features.end(), name) > 1)
        throw Error(ErrorKind::Usage, "--features '" + o.features + "': '" + name + "' is named twice (each once)");
      if (std::find(analysis::kPolicyFeatures.begin(), analysis::kPolicyFeatures.end(), name) ==
          analysis::kPolicyFeatures.end()) {
        std::string names;
        for (std::string_view f : analysis::kPolicyFeatures) names += (names.empty() ? "" : ", ") + std::string(f);
        throw Error(ErrorKind::Usage,
                    "--features: '" + name + "' is not a policy feature (one of " + names + "; or all, or none)");
      }
    }
  }
  if (o.no_exact_zpass && o.light_projection != gl::LightProjection::ClippedSides)
    throw Error(ErrorKind::Usage,
                "--no-exact-zpass needs --light-projection clipped-sides (any other cap draws fragments where the "
                "near-cap is empty)");
  // Before the reading and the fit: a crack model asked for (--features)
  // that the decision would never read, or for frames its rows did not draw.
  if (crack_model && o.features_given) {
    if (o.no_exact_zpass)
      throw Error(ErrorKind::Usage,
                  "a crack model (--features " + o.features +
                      ") would never be read: with --no-exact-zpass every occluder gets the capped method and the "
                      "decision asks no model; add --features none, or drop --no-exact-zpass");
    refuse_choices_the_rows_lack(o);
  }
  const std::vector<analysis::PolicySample> samples =
      analysis::policy_samples(o.results, *capped, *fallback, o.variant);
  analysis::LogisticFitOptions fit;
  fit.robust = !o.plain;
  const std::vector<std::string> features =
      o.features != "all" && crack_model ? given_features : std::vector<std::string>{};
  analysis::SwitchPolicy policy =
      analysis::tune_policy(samples, *capped, *fallback, command, fit, features, crack_model);
  policy.light_projection = o.light_projection;
  if (o.no_exact_zpass) policy.exact_zpass = false;
  if (o.depth) policy.depth = o.depth;
  if (o.depth_mapping) policy.depth_mapping = o.depth_mapping;
  if (o.near_plane) policy.near_plane = o.near_plane;
  // The provenance holds the confusion tables; print them too.
  std::cout << "tune: " << samples.size() << " samples from " << o.results.size() << " file(s)\n";
  const nlohmann::json provenance = nlohmann::json::parse(policy.provenance_json);
  for (const auto& [side, label] : {std::pair<const char*, const char*>{"train", "train"}, {"held_out", "held out"}}) {
    const nlohmann::json& c = provenance.at(side);
    std::cout << "  " << label << ": " << c["samples"] << " (configuration, light) pairs, " << c["cracks"]
              << " where the capped method cracks more than the fallback; predicted " << c["cracks_predicted"]
              << " of them, " << c["false_alarms"] << " false alarms\n";
  }
  if (policy.crack_model.features.empty())
    std::cout << "  no crack model: "
              << (crack_model        ? "the capped method never cracked more than the fallback in training"
                  : o.features_given ? "none asked for (--features none)"
                                     : "none with --no-exact-zpass (the decision reads none)")
              << "\n";
  else
    std::cout << "  threshold " << policy.crack_model.threshold << "\n";
  // A model the policy's own switches bypass is not written: it would say
  // the policy decides by it.
  for (const std::string& unread : analysis::unread_policy_models(policy))
    throw Error(ErrorKind::Usage, "the policy would carry " + unread + ", which its decision never reads");
  // The default features fitted a model (a training crack): the same check.
  if (!policy.crack_model.features.empty()) refuse_choices_the_rows_lack(o);
  // What the written policy's decision reads of what was fitted here.
  if (policy.crack_model.features.empty()) {
    std::cout << "  fits the policy uses: none (every occluder that meets the light pyramid gets "
              << gl::to_string(policy.capped_method) << (policy.exact_zpass ? ", the others Z-pass" : "")
              << "; no cost model: the decision's costs are a device profile's, from nearcap calibrate)\n";
  } else {
    std::cout << "  fits the policy uses: the crack model (";
    for (std::size_t k = 0; k < policy.crack_model.features.size(); ++k)
      std::cout << (k ? ", " : "") << policy.crack_model.features[k];
    std::cout << "), asked for occluders that meet the light pyramid: " << gl::to_string(policy.fallback_method)
              << " where it predicts a crack; no cost model (the decision's costs are a device profile's, from "
                 "nearcap calibrate)\n";
  }
  io::write_output_files({{o.out, analysis::policy_to_json(policy)}});
  std::cout << "tune: wrote " << o.out << "\n";
}

}  // namespace

void register_tune(CLI::App& app) {
  auto [cmd, o] = add_subcommand<TuneOptions>(
      app, "tune",
      "fit the switch policy's crack model (Ceres) on sweep CSVs and write policy.json (docs/policy.md), printing "
      "which fits the policy's decision reads; the solver's own log goes to stderr with NEARCAP_SOLVER_LOG=1",
      run);
  cmd.add_option("results", o.results, "sweep CSV files with rows of both methods")->required();
  cmd.add_option("--out", o.out, "the policy file to write")->required();
  cmd.add_option("--capped", o.capped, "the method for occluders that meet the light pyramid")->capture_default_str();
  cmd.add_option("--fallback", o.fallback, "the method where a crack is predicted")->capture_default_str();
  cmd.add_option("--variant", o.variant,
                 "the sweep variant whose rows are used: the policy's switch clamp (the sweep's own choices, "
                 "or one of its --variant)")
      ->capture_default_str();
  cmd.add_flag("--plain", o.plain, "plain logistic regression (no robust loss)");
  add_choice_option(cmd, "--light-projection", o.light_projection,
                    "the capped ZP+'s near-cap, written to the policy (the rows' variant should have it): " +
                        names_joined<gl::LightProjection>(" or ") +
                        " (no light frustum; docs/findings/light-projection.md)");
  cmd.add_flag("--no-exact-zpass", o.no_exact_zpass,
               "no exact Z-pass test per occluder: the capped method everywhere (with --light-projection "
               "clipped-sides, which is Z-pass wherever its sides leave no cap in the viewport)");
  add_choice_option(cmd, "--depth", o.depth,
                    "the depth buffer the policy's frames use, written to the policy (the rows' variant should have "
                    "it): " +
                        names_joined<gl::DepthFormat>(" or ") + "; not given, the caller's");
  add_choice_option(cmd, "--depth-mapping", o.depth_mapping,
                    "the camera's depth mapping the policy's frames use, written to the policy: " +
                        names_joined<gl::DepthMapping>(" or ") +
                        " (with --depth float32: reversed-Z); not given, "
                        "the caller's");
  add_choice_option(cmd, "--near-plane", o.near_plane,
                    "the camera's near plane the policy's frames use, written to the policy: " +
                        names_joined<gl::NearPlane>(" or ") + "; not given, the caller's");
  cmd.add_option("--features", o.features,
                 "the model's features, comma-separated, from log_light_near_distance, log_l_far_over_width, "
                 "log_delta_over_width, log_skew (these four need no pass over the geometry), "
                 "log_cond_light_transform, log_cap_window_error_px, log_coordinate_over_size and "
                 "l_near_over_l_far (docs/policy.md); all, or none (no crack model); not given, all, or none with "
                 "--no-exact-zpass (whose decision reads none)")
      ->each([&given = o.features_given](const std::string&) { given = true; });
}

}  // namespace nearcap::cli
