// nearcap/analysis/policy_fit.hpp — fitting the switch policy's crack model
// (switch_policy.hpp) on sweep rows, with Ceres.
//
// A sample is one (configuration, light) of a sweep CSV with rows for both
// the policy's capped method (ZP+ corrected) and its fallback (Z-fail) in the
// variant the policy runs (by default "switch-clamp=clamp-far": the sweep's
// --switch-clamp clamp-far, the policy's own switch), and a light frustum
// where the capped method did not fall back: its features (kPolicyFeatures, from
// the row's conditioning columns) and its label, "the capped method cracks
// more than the fallback here".  The split is by configuration: a
// configuration is held out when the FNV-1a hash of its id is 0 mod 5 (about
// a fifth; the same configuration is on the same side in every sweep).
//
// The fit: logistic regression on standardized features (mean and scale from
// the training samples), Ceres minimizing sum_i rho(2 logloss_i) + sum_k
// (l2 w_k)^2 with rho Huber's loss (a few mislabeled frames, e.g. depth
// precision cracks, cannot drag the model; `robust = false` for plain
// logistic regression).  The threshold: the smallest predicted probability
// of a training positive, halved (every training crack predicted).
#pragma once

#include <string>
#include <vector>

#include "nearcap/analysis/switch_policy.hpp"

namespace nearcap::analysis {

struct PolicySample {
  std::string configuration;
  std::size_t light = 0;
  std::vector<double> x;  // one per kPolicyFeatures, all finite
  bool crack = false;
  bool held_out = false;
};

bool held_out_configuration(const std::string& configuration_id);

// Reads sweep CSVs (nearcap sweep --out); rows of other methods and variants
// are ignored.  Each file is read like a scene (io/input_files.hpp): only a
// regular file within NEARCAP_MAX_INPUT_MB, streamed line by line.  Every
// line must be UTF-8 with as many fields as the header; in the rows used,
// `light` and `cracks` are whole numbers, the conditioning columns numbers
// (nan and inf allowed: such a pair is not a sample).  Errors name the file,
// the line and the column: Io, Resource, Parse, NonFinite.
std::vector<PolicySample> policy_samples(const std::vector<std::string>& files, gl::ShadowMethod capped,
                                         gl::ShadowMethod fallback,
                                         const std::string& variant = "switch-clamp=clamp-far");
// The same on CSV text already in memory; `source` names it in errors.
std::vector<PolicySample> policy_samples_from_text(const std::string& csv, const std::string& source,
                                                   gl::ShadowMethod capped, gl::ShadowMethod fallback,
                                                   const std::string& variant = "switch-clamp=clamp-far");

struct LogisticFitOptions {
  bool robust = true;
  double huber_delta = 2.0;  // on 2 logloss: samples predicted below about exp(-2) of their label
  double l2 = 0.05;
};
struct LogisticFit {
  std::vector<double> mean, scale, weights;
  double bias = 0;
  int iterations = 0;
  double final_cost = 0;
};
// x: samples by features (all finite); y: 0 or 1.
LogisticFit fit_logistic(const std::vector<std::vector<double>>& x, const std::vector<int>& y,
                         const LogisticFitOptions& options = {});

// A method's work and emulated frame time in one sweep row.
struct CostSample {
  std::string configuration;
  double triangles = 0, fragments = 0, ms = 0;  // all passes
  bool held_out = false;
};
// Reads sweep CSVs as policy_samples does; in the rows used, the triangle and
// fragment counts and frame_ms must be finite and not negative (an infinite
// or NaN time is a NonFinite error naming the file, line and column).
std::vector<CostSample> cost_samples(const std::vector<std::string>& files, gl::ShadowMethod method,
                                     const std::string& variant = "switch-clamp=clamp-far");
std::vector<CostSample> cost_samples_from_text(const std::string& csv, const std::string& source,
                                               gl::ShadowMethod method,
                                               const std::string& variant = "switch-clamp=clamp-far");
// Least squares on the training samples (not held out) with a robust loss
// (Cauchy, scale 1 ms: times are noisy, the sweep runs configurations side by
// side); `robust = false` for plain least squares.
CostModel fit_cost_model(const std::vector<CostSample>& samples, bool robust = true);
// The median of |predicted - measured| / measured over one side of the split.
double median_relative_error(const CostModel& model, const std::vector<CostSample>& samples, bool held_out);

// How a model classifies a set of samples.
struct Confusion {
  std::size_t samples = 0, positives = 0, true_positives = 0, false_positives = 0;
};
Confusion confusion(const CrackModel& model, const std::vector<PolicySample>& samples, bool held_out);

// The whole tuning: the model fitted on the training samples, the threshold,
// and the provenance (counts, confusion on both sides, the command) in the
// returned policy.
// `features`: names from kPolicyFeatures, each once (all of them when empty).
// `crack_model` false: no fit, a model without features that never predicts
// a crack (for a policy whose switches never read one); the confusion
// tables still count the cracks.
// The policy carries no cost models: decide() reads none (the decision's
// costs are the device profile's, device_profile.hpp, which `nearcap
// calibrate` measures on the real GL instead of the emulation's CPU times).
SwitchPolicy tune_policy(const std::vector<PolicySample>& samples, gl::ShadowMethod capped, gl::ShadowMethod fallback,
                         const std::string& command, const LogisticFitOptions& options = {},
                         const std::vector<std::string>& features = {}, bool crack_model = true);

// The models a policy carries that decide() never reads given the policy's
// own switches, by their policy.json names: "crack_model" (with features)
// when the capped method draws no near-cap, or, without a device profile,
// when there is no exact Z-pass test (the model is asked only for occluders
// that test could not give Z-pass, before drawing ZP+), or, with one, when
// the light projection is clipped-sides (the model admits the paper-cap
// candidate only); "cost_models" when any (decide() reads none).  A device
// profile is always read (the cost decision).
// This restates decide()'s branches (switch_policy.cpp); the tests check it
// against decide() itself, so a change there that reads a model fails them
// until this says so.
std::vector<std::string> unread_policy_models(const SwitchPolicy& policy);

}  // namespace nearcap::analysis
