// A switch policy judged against an oracle (see policy_evaluation.hpp).
#include "nearcap/analysis/policy_evaluation.hpp"
#include "csv_field.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <utility>

#include "nearcap/analysis/frame_time_drift.hpp"

namespace nearcap::analysis {
namespace {

using GroupKey = std::pair<std::string, std::size_t>;  // configuration, light within a set

// The p-th quantile (0..1) of `v`, linear between order statistics.
double quantile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const double x = p * static_cast<double>(v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(x);
  return i + 1 < v.size() ? v[i] + (x - static_cast<double>(i)) * (v[i + 1] - v[i]) : v[i];
}

// One (configuration, light) of a set: its rows by rule.
struct Group {
  std::string configuration;
  int frame = -1;
  std::size_t light = 0;
  std::map<std::string, const EvaluationRow*, std::less<>> by_rule;
  const EvaluationRow* row(std::string_view rule) const {
    const auto it = by_rule.find(rule);
    return it == by_rule.end() ? nullptr : it->second;
  }
};

// The rules a set's totals list, in the table's order.
std::vector<std::string> table_rules() {
  std::vector<std::string> out{std::string(kOracleRule), "policy"};
  for (const EvaluationRuleInfo& r : kEvaluationRules)
    if (r.role == EvaluationRole::FixedRule) out.emplace_back(r.name);
  for (const EvaluationRuleInfo& r : kEvaluationRules)
    if (r.role == EvaluationRole::Candidate) out.emplace_back(r.name);
  return out;
}

std::string fixed(double v, int digits) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

bool as_right_as_zfail(const EvaluationRow& row, const EvaluationRow& zfail) {
  return row.wrong <= zfail.wrong && row.cracks <= zfail.cracks;
}

const RuleTotals* SetTable::find(std::string_view rule) const {
  for (const RuleTotals& r : rules)
    if (r.rule == rule) return &r;
  return nullptr;
}

EvaluationTable evaluate_rows(const std::vector<EvaluationRow>& rows) {
  std::vector<std::string> set_order;
  std::map<std::string, std::map<GroupKey, Group>> sets;
  for (const EvaluationRow& r : rows) {
    if (sets.find(r.set) == sets.end()) set_order.push_back(r.set);
    Group& g = sets[r.set][{r.configuration, r.light}];
    g.configuration = r.configuration;
    g.frame = r.frame;
    g.light = r.light;
    g.by_rule[r.rule] = &r;
  }
  const std::vector<std::string> listed = table_rules();
  EvaluationTable out;
  for (const std::string& name : set_order) {
    SetTable t;
    t.set = name;
    std::map<std::string, RuleTotals> totals;
    for (const std::string& rule : listed) totals[rule].rule = rule;
    std::vector<double> noise, predicted_error, predicted_ratio, profile_error, profile_ratio;
    double warm_decision_ms = 0, warm_frame_ms = 0;
    bool any_warm = false;
    WindowComparison window;
    for (const auto& [key, g] : sets[name]) {
      // Compared only where Z-fail, every fixed rule and the policy drew.
      bool complete = true;
      for (const EvaluationRuleInfo& info : kEvaluationRules) {
        if (info.role == EvaluationRole::Candidate && info.name != "zfail") continue;
        const EvaluationRow* r = g.row(info.name);
        complete = complete && r != nullptr && !r->refused;
      }
      if (!complete) {
        ++t.excluded;
        continue;
      }
      ++t.groups;
      const EvaluationRow& zfail = *g.row("zfail");
      // The oracle: the fastest right candidate (Z-fail always is).
      const EvaluationRow* best = nullptr;
      for (const EvaluationRuleInfo& info : kEvaluationRules) {
        if (!info.oracle_candidate) continue;
        const EvaluationRow* r = g.row(info.name);
        if (r == nullptr || r->refused || !r->applies || !as_right_as_zfail(*r, zfail)) continue;
        if (best == nullptr || r->choice_ms.value_or(r->end_to_end_ms) < best->choice_ms.value_or(best->end_to_end_ms))
          best = r;
      }
      EvaluationRow oracle = *best;
      oracle.rule = std::string(kOracleRule);
      oracle.chosen = best->rule;
      ++t.oracle_choices[best->rule];
      if (const EvaluationRow* policy = g.row("policy"); policy != nullptr && !policy->chosen.empty())
        ++t.policy_choices[policy->chosen];
      if (const EvaluationRow* policy = g.row("policy"); policy != nullptr && policy->frames_since_priced > 0)
        ++t.policy_kept;
      out.oracle_rows.push_back(oracle);
      for (const std::string& rule : listed) {
        const EvaluationRow* r = rule == kOracleRule ? &oracle : g.row(rule);
        if (r == nullptr || r->refused || !r->applies) {
          // A candidate that did not draw or does not apply here stands in as
          // Z-fail, which a renderer would draw instead.
          r = &zfail;
        }
        RuleTotals& s = totals[rule];
        s.end_to_end_ms += r->end_to_end_ms;
        s.cpu_ms += r->cpu_ms;
        s.decision_ms += r->decision_ms;
        s.wrong += r->wrong;
        s.cracks += r->cracks;
        if (!as_right_as_zfail(*r, zfail)) ++s.violations;
      }
      if (const EvaluationRow* again = g.row(kNoiseRule);
          again != nullptr && !again->refused && zfail.end_to_end_ms > 0)
        noise.push_back(again->end_to_end_ms / zfail.end_to_end_ms);
      if (const EvaluationRow* policy = g.row("policy"); policy->decision_warm_ms) {
        any_warm = true;
        warm_decision_ms += *policy->decision_warm_ms;
        warm_frame_ms += policy->end_to_end_ms - policy->decision_ms + *policy->decision_warm_ms;
      }
      if (const EvaluationRow* policy = g.row("policy"); policy->predicted_ms && policy->end_to_end_ms > 0) {
        predicted_error.push_back(std::abs(*policy->predicted_ms - policy->end_to_end_ms) / policy->end_to_end_ms);
        predicted_ratio.push_back(*policy->predicted_ms / policy->end_to_end_ms);
      }
      if (const EvaluationRow* policy = g.row("policy"); policy->profile_ms && policy->end_to_end_ms > 0) {
        profile_error.push_back(std::abs(*policy->profile_ms - policy->end_to_end_ms) / policy->end_to_end_ms);
        profile_ratio.push_back(*policy->profile_ms / policy->end_to_end_ms);
      }
      if (name == kWindowSet && g.frame >= kWindowFirstFrame && g.frame <= kWindowLastFrame) {
        double best_ms = zfail.end_to_end_ms;
        if (const EvaluationRow* zpass = g.row("zpass");
            zpass != nullptr && !zpass->refused && zpass->applies && as_right_as_zfail(*zpass, zfail))
          best_ms = std::min(best_ms, zpass->end_to_end_ms);
        ++window.groups;
        window.policy_ms += g.row("policy")->end_to_end_ms;
        window.best_ms += best_ms;
      }
    }
    const double oracle_ms = totals[std::string(kOracleRule)].end_to_end_ms;
    for (const std::string& rule : listed) {
      RuleTotals s = totals[rule];
      s.ratio_to_oracle = oracle_ms > 0 ? s.end_to_end_ms / oracle_ms : 0;
      t.rules.push_back(s);
    }
    const RuleTotals& policy = totals["policy"];
    t.decision_share = policy.end_to_end_ms > 0 ? policy.decision_ms / policy.end_to_end_ms : 0;
    if (any_warm) t.decision_warm_share = warm_frame_ms > 0 ? warm_decision_ms / warm_frame_ms : 0;
    t.noise_pairs = noise.size();
    if (!predicted_error.empty()) {
      t.predicted_median_error = quantile(predicted_error, 0.5);
      t.predicted_median_ratio = quantile(predicted_ratio, 0.5);
    }
    if (!profile_error.empty()) {
      t.profile_median_error = quantile(profile_error, 0.5);
      t.profile_median_ratio = quantile(profile_ratio, 0.5);
    }
    if (!noise.empty()) {
      t.noise_p05 = quantile(noise, 0.05);
      t.noise_p95 = quantile(noise, 0.95);
      std::vector<double> deviation;
      for (double x : noise) deviation.push_back(std::abs(x - 1));
      t.noise_median_deviation = quantile(deviation, 0.5);
    }
    if (window.groups > 0) t.window = window;
    out.sets.push_back(std::move(t));
  }
  return out;
}

std::string evaluation_csv_header() {
  return "set,configuration,frame,light,rule,refused,applies,wrong,cracks,decision_ms,cpu_ms,end_to_end_ms,choice_ms,"
         "chosen,decision_warm_ms,predicted_ms,profile_ms,occluder_triangles,frames_since_priced\n";
}

std::string evaluation_csv_line(const EvaluationRow& r) {
  std::ostringstream s;
  s << csv_field(r.set) << ',' << csv_field(r.configuration) << ',';
  if (r.frame >= 0) s << r.frame;
  s << ',' << r.light << ',' << csv_field(r.rule) << ',' << (r.refused ? 1 : 0) << ',' << (r.applies ? 1 : 0) << ','
    << r.wrong << ',' << r.cracks << ',' << fixed(r.decision_ms, 4) << ',' << fixed(r.cpu_ms, 4) << ','
    << fixed(r.end_to_end_ms, 4) << ',';
  if (r.choice_ms) s << fixed(*r.choice_ms, 4);
  s << ',' << csv_field(r.chosen) << ',';
  if (r.decision_warm_ms) s << fixed(*r.decision_warm_ms, 4);
  s << ',';
  if (r.predicted_ms) s << fixed(*r.predicted_ms, 4);
  s << ',';
  if (r.profile_ms) s << fixed(*r.profile_ms, 4);
  s << ',' << r.occluder_triangles << ',' << r.frames_since_priced << '\n';
  return s.str();
}

std::string evaluation_table_markdown(const EvaluationTable& table) {
  std::ostringstream s;
  for (const SetTable& t : table.sets) {
    s << "### " << t.set << "\n\n";
    s << t.groups << " (configuration, light) compared";
    if (t.excluded > 0) s << ", " << t.excluded << " left out (Z-fail, a fixed rule or the policy refused)";
    s << ".\n\n";
    s << "| rule | end-to-end ms | x oracle | cpu ms | wrong | cracks | not as right as Z-fail |\n";
    s << "|---|---:|---:|---:|---:|---:|---:|\n";
    for (const RuleTotals& r : t.rules)
      s << "| " << r.rule << " | " << fixed(r.end_to_end_ms, 2) << " | " << fixed(r.ratio_to_oracle, 3) << " | "
        << fixed(r.cpu_ms, 2) << " | " << r.wrong << " | " << r.cracks << " | " << r.violations << " |\n";
    s << "\n";
    s << "- oracle's choices:";
    const char* sep = " ";
    for (const auto& [rule, n] : t.oracle_choices) {
      s << sep << rule << " " << n;
      sep = ", ";
    }
    if (t.oracle_choices.empty()) s << " none";
    s << "\n";
    if (!t.policy_choices.empty()) {
      s << "- the policy's choices:";
      sep = " ";
      for (const auto& [methods, n] : t.policy_choices) {
        s << sep << methods << " " << n;
        sep = ", ";
      }
      s << "\n";
    }
    s << "- the policy's decision: " << fixed(100 * t.decision_share, 2)
      << "% of its end-to-end time, timed once per (configuration, light) after the exact reference and the other "
         "rules' frames (cold caches)";
    if (t.decision_warm_share)
      s << "; " << fixed(100 * *t.decision_warm_share, 2)
        << "% warm (the same decision repeated at once, as a renderer's frame loop that decides every frame pays it)";
    if (t.policy_kept > 0)
      s << "; in " << t.policy_kept << " of the " << t.groups
        << " its choice was kept from a frame priced before it (kept_choices.hpp), not priced";
    s << "\n";
    if (t.noise_pairs > 0)
      s << "- noise floor: Z-fail's frame timed twice, end-to-end again/first " << fixed(t.noise_p05, 3) << " to "
        << fixed(t.noise_p95, 3) << " (5th to 95th percentile, " << t.noise_pairs << " pairs; median |again/first - 1| "
        << fixed(100 * t.noise_median_deviation, 1) << "%)\n";
    if (!std::isnan(t.predicted_median_error)) {
      s << "- the policy's predicted frame time (before drawing: the device profile's price times the "
           "measured/priced of the set's earlier policy frames, along a path the last one's, else the median of the "
           "last "
        << FrameTimeDrift::kWindow << ", plus the decision's own time): median error "
        << fixed(100 * t.predicted_median_error, 1) << "% of the measured end-to-end time; predicted/measured median "
        << fixed(t.predicted_median_ratio, 3);
      if (!std::isnan(t.profile_median_error))
        s << "; the profile's price alone: median error " << fixed(100 * t.profile_median_error, 1)
          << "%, priced/measured median " << fixed(t.profile_median_ratio, 3);
      s << "\n";
    }
    if (t.noise_pairs == 0) s << "- noise floor: no pair timed\n";
    if (t.window) {
      const WindowComparison& w = *t.window;
      s << "- frames " << kWindowFirstFrame << "-" << kWindowLastFrame << ": policy " << fixed(w.policy_ms, 2)
        << " ms against min(Z-fail, Z-pass where right) " << fixed(w.best_ms, 2)
        << " ms: " << fixed(w.best_ms > 0 ? w.policy_ms / w.best_ms : 0, 3) << "x (" << w.groups << " frame-lights)\n";
    }
    s << "\n";
  }
  s << "x oracle: end-to-end time over the oracle's (the fastest candidate or exact-zpass mix as right as Z-fail, "
       "per configuration and light, in hindsight: chosen on some timing rounds, its time counted on the others). Not "
       "as right as Z-fail: (configuration, light) with more wrong "
       "pixels or more "
       "cracks than Z-fail's. A candidate that does not apply (Z-pass where the exact test finds a near-cap) or "
       "did not draw counts as Z-fail there.\n";
  return s.str();
}

}  // namespace nearcap::analysis
