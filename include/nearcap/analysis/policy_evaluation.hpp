// nearcap/analysis/policy_evaluation.hpp — a switch policy judged against an
// oracle on held-out data: from the rows `nearcap evaluate` measures (one per
// configuration, light and rule) to the table of totals per held-out set.
//
// The rules, spelled once in kEvaluationRules:
//   candidates  every method that can be right wherever Z-fail is right, one
//               method for every occluder of the (configuration, light):
//                 zpass             Z-pass, a candidate only where the exact
//                                   test (the light pyramid, exact/light_pyramid.hpp)
//                                   finds every occluder's near-cap empty; the
//                                   test's time counts as its decision
//                 zfail             Z-fail, infinite far plane
//                 zpplus-paper      ZP+ with the paper's light-frustum cap
//                 zpplus-clipped    ZP+ with the clipped-sides cap
//                 zpplus-corrected  ZP+ corrected (section 5), paper cap
//                 atomiczp          AtomicZP (depth-clamped Z-pass and the
//                                   frame's eye count, docs/atomiczp.md)
//   fixed rules always-zfail, always-clipped (the zfail and zpplus-clipped
//               candidates' own frames and measurements), exact-zpass+zfail,
//               exact-zpass+clipped (Z-pass where the exact test finds the
//               occluder's near-cap empty, the other method elsewhere, per
//               occluder), doom3 and doom3-bfg (engine_policies.hpp)
//   policy      the policy file under test
//   oracle      derived: per (configuration, light) the fastest frame in
//               hindsight (end-to-end time) among the candidates and the two
//               exact-zpass mixes (oracle_candidate) that drew, apply, and are
//               as right as Z-fail.  The oracle is per frame and light, not per
//               occluder: beyond those two mixes, a frame that mixes methods per
//               occluder (an engine rule, a policy) can beat it.  It chooses
//               by choice_ms and counts end_to_end_ms, times of disjoint rounds.
// "As right as Z-fail" (as_right_as_zfail): no more wrong pixels than Z-fail's
// and no more cracks (so none where Z-fail has none).  A rule that is not, in
// a (configuration, light), is a violation there.
//
// Wrong pixels and cracks are the emulated frame's against the exact
// reference (judge/crack_map.hpp), as a sweep's rows: the frame whose
// recorded draws the real GL replays.  Times are milliseconds of wall clock
// on the real GL: cpu_ms is the CPU's work (decision, silhouettes, the
// clipped-sides cap, as the emulation's batch measured it once per rule;
// uploads), end_to_end_ms that work plus the GL's passes up to glFinish.  The noise floor is Z-fail's
// frame drawn a second time after the others (rule "zfail#again"): the
// spread of the ratio again / first.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nearcap::analysis {

enum class EvaluationRole { Candidate, FixedRule, Policy };

struct EvaluationRuleInfo {
  std::string_view name;
  EvaluationRole role;
  bool oracle_candidate;  // among the frames the oracle chooses from
  std::string_view description;
};

inline constexpr std::array<EvaluationRuleInfo, 13> kEvaluationRules{{
    {"zpass", EvaluationRole::Candidate, true, "Z-pass, where the exact test finds every near-cap empty"},
    {"zfail", EvaluationRole::Candidate, true, "Z-fail, infinite far plane"},
    {"zpplus-paper", EvaluationRole::Candidate, true, "ZP+, the paper's light-frustum cap"},
    {"zpplus-clipped", EvaluationRole::Candidate, true, "ZP+, the clipped-sides cap"},
    {"zpplus-corrected", EvaluationRole::Candidate, true, "ZP+ corrected, the paper's cap"},
    {"atomiczp", EvaluationRole::Candidate, true, "AtomicZP: depth-clamped Z-pass and the frame's eye count"},
    {"always-zfail", EvaluationRole::FixedRule, false, "Z-fail for every occluder"},
    {"always-clipped", EvaluationRole::FixedRule, false, "clipped-sides ZP+ for every occluder"},
    {"exact-zpass+zfail", EvaluationRole::FixedRule, true, "exact Z-pass test, Z-fail elsewhere"},
    {"exact-zpass+clipped", EvaluationRole::FixedRule, true, "exact Z-pass test, clipped-sides ZP+ elsewhere"},
    {"doom3", EvaluationRole::FixedRule, false, "Doom 3's rule"},
    {"doom3-bfg", EvaluationRole::FixedRule, false, "Doom 3 BFG's rule"},
    {"policy", EvaluationRole::Policy, false, "the policy under test"},
}};
inline constexpr std::string_view kOracleRule = "oracle";
inline constexpr std::string_view kNoiseRule = "zfail#again";  // Z-fail's frame timed a second time
// The window of near_plane_sweep where the policy is also held against the
// faster of Z-fail and Z-pass-where-right, frame by frame.
inline constexpr std::string_view kWindowSet = "near_plane_sweep";
inline constexpr int kWindowFirstFrame = 40, kWindowLastFrame = 59;

// One (configuration, light, rule) as measured.
struct EvaluationRow {
  std::string set;            // the held-out set: "seed-S" or the path file's stem
  std::string configuration;  // unique within the set
  int frame = -1;             // the path's frame; -1 for a sampler's configuration
  std::size_t light = 0;
  std::string rule;       // a name of kEvaluationRules, kOracleRule or kNoiseRule
  bool refused = false;   // the float pipeline or the GL could not draw it
  bool applies = true;    // false: not a candidate here (zpass where the exact test finds a near-cap)
  std::size_t wrong = 0;  // wrong pixels against the exact reference
  std::size_t cracks = 0;
  double decision_ms = 0, cpu_ms = 0, end_to_end_ms = 0;  // decision_ms is part of cpu_ms
  // The end-to-end time of other rounds of the same frame, which the oracle
  // chooses by (absent: end_to_end_ms).  The minimum of noisy times is
  // biased low (the winner's curse): choosing on some rounds and counting
  // the chosen frame's time of the others is not.
  std::optional<double> choice_ms;
  // The policy's rows (absent without a device profile): the profile's
  // price of the frame it chose (price_decision's predicted_ms), and the
  // end-to-end time predicted before drawing: that price times the
  // FrameTimeDrift scale of the set's earlier policy frames
  // (frame_time_drift.hpp: measured over priced, the decision's own time
  // left out), plus decision_ms, spent by then.
  std::optional<double> profile_ms;
  std::optional<double> predicted_ms;
  // The policy's rows: the same decision made again right after the first
  // (decision_ms), its code and data still in the caches: what a renderer's
  // frame loop that decides every frame pays (`nearcap evaluate`: the median
  // of three such calls, against a preemption).  decision_ms is the
  // first call, made after the exact reference and the other rules'
  // decisions of the (configuration, light) evicted them: cold.  Neither
  // counts the other; cpu_ms and end_to_end_ms hold decision_ms.  Both
  // include building the exact camera-space scene the decision reads
  // (CameraSpaceScene), timed once per configuration, as `nearcap render`
  // counts it in its decision_ms: a frame loop whose camera moves builds it
  // every frame.  The decision timed is its choice (switch_policy.hpp,
  // DecisionPricing::ChoiceOnly), with the occluders' facings kept from one
  // configuration to the next; predicted_ms is priced after it.
  std::optional<double> decision_warm_ms;
  std::string chosen;  // oracle rows: the candidate it is; the policy's: its occluders' methods, "+"-joined
  // The configuration's largest occluder's triangles (every row), which
  // UnpricedFrames is fitted against (unpriced_frames_fit.hpp).
  std::size_t occluder_triangles = 0;
  // The policy's rows: 0 where its choice was priced on this frame; k > 0
  // where it was the choice of the frame priced k frames before, kept
  // (kept_choices.hpp).
  int frames_since_priced = 0;
};

// No more wrong pixels and no more cracks than Z-fail's row of the same
// (configuration, light).
bool as_right_as_zfail(const EvaluationRow& row, const EvaluationRow& zfail);

struct RuleTotals {
  std::string rule;
  double end_to_end_ms = 0, cpu_ms = 0, decision_ms = 0;
  std::size_t wrong = 0, cracks = 0;
  std::size_t violations = 0;  // (configuration, light) where it is not as right as Z-fail
  double ratio_to_oracle = 0;  // end_to_end_ms / the oracle's
};

// The policy against min(Z-fail, Z-pass where it applies and is right), frame
// by frame, over kWindowFirstFrame..kWindowLastFrame of kWindowSet.
struct WindowComparison {
  std::size_t groups = 0;
  double policy_ms = 0, best_ms = 0;
};

struct SetTable {
  std::string set;
  std::size_t groups = 0;    // (configuration, light) compared
  std::size_t excluded = 0;  // left out: Z-fail, a fixed rule or the policy refused (or missing)
  // The oracle, the policy, the fixed rules, then the candidates.
  std::vector<RuleTotals> rules;
  std::map<std::string, std::size_t> oracle_choices;  // candidate -> (configuration, light) it won
  std::map<std::string, std::size_t> policy_choices;  // the policy's methods -> (configuration, light)
  double decision_share = 0;                          // the policy's decision_ms / its end_to_end_ms
  std::size_t policy_kept = 0;  // compared groups whose policy row has a kept choice (frames_since_priced > 0)
  // The policy's frames with their warm decision instead of the first:
  // sum decision_warm_ms / sum (end_to_end_ms - decision_ms +
  // decision_warm_ms), over the compared groups whose policy row has one
  // (absent where none has).
  std::optional<double> decision_warm_share;
  std::size_t noise_pairs = 0;          // Z-fail timed twice in a compared group
  double noise_p05 = 0, noise_p95 = 0;  // again / first, 5th and 95th percentiles
  // Median |x - 1| of those ratios, and the median |predicted - measured| /
  // measured of the policy's frame time (NaN without a profile), and the
  // median predicted / measured: near 1 where the error is scatter, away
  // from it where the profile's scale is off.  The same two of the
  // profile's price alone (profile_ms against end_to_end_ms).
  double noise_median_deviation = 0;
  double predicted_median_error = std::numeric_limits<double>::quiet_NaN();
  double predicted_median_ratio = std::numeric_limits<double>::quiet_NaN();
  double profile_median_error = std::numeric_limits<double>::quiet_NaN();
  double profile_median_ratio = std::numeric_limits<double>::quiet_NaN();
  std::optional<WindowComparison> window;  // kWindowSet only
  const RuleTotals* find(std::string_view rule) const;
};

struct EvaluationTable {
  std::vector<SetTable> sets;  // in the order the rows name them
  // One row per compared (configuration, light): the oracle's, named kOracleRule,
  // its figures the chosen candidate's.
  std::vector<EvaluationRow> oracle_rows;
};

// The table from the measured rows (any order).  Pure: no GL, no files.
EvaluationTable evaluate_rows(const std::vector<EvaluationRow>& rows);

// evaluation.csv: a header and one line per row (set, configuration, frame,
// light, rule, refused, applies, wrong, cracks, decision_ms, cpu_ms,
// end_to_end_ms, choice_ms (empty when absent), chosen, decision_warm_ms,
// predicted_ms and profile_ms (these two empty when absent: every row but
// the policy's, and its own without a device profile), occluder_triangles).
std::string evaluation_csv_header();
std::string evaluation_csv_line(const EvaluationRow& row);

// The table as Markdown, one section per set (table.md, and stdout).
std::string evaluation_table_markdown(const EvaluationTable& table);

}  // namespace nearcap::analysis
