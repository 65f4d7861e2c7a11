#include "nearcap/analysis/unpriced_frames_fit.hpp"

#include <algorithm>
#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace nearcap::analysis {

namespace {

// One (configuration, light) of the training rows.
struct TrainingFrame {
  std::size_t occluder_triangles = 0;
  double policy_ms = 0;
  double unpriced_decision_ms = 0;
  double zfail_ms = 0, clipped_ms = 0;  // the fixed rules' end-to-end times
  // Always clipped drew this frame and is as right as Z-fail here: only
  // then may the clipped-sides ZP+ be its group's unpriced method.
  bool clipped_right = false;
};

}  // namespace

UnpricedFramesFit fit_unpriced_frames(const std::vector<EvaluationRow>& rows, gl::ZPassFar zpass_far) {
  using Key = std::tuple<std::string, std::string, std::size_t>;
  std::map<Key, std::map<std::string, const EvaluationRow*>> frame_rows;
  for (const EvaluationRow& r : rows) frame_rows[{r.set, r.configuration, r.light}][r.rule] = &r;
  std::vector<TrainingFrame> frames;
  for (const auto& [key, by_rule] : frame_rows) {
    const auto policy = by_rule.find("policy");
    const auto zfail = by_rule.find("always-zfail");
    // A frame the policy or Z-fail did not draw is left out, as the table leaves it out.
    if (policy == by_rule.end() || zfail == by_rule.end() || policy->second->refused || zfail->second->refused)
      continue;
    TrainingFrame f;
    f.occluder_triangles = policy->second->occluder_triangles;
    f.policy_ms = policy->second->end_to_end_ms;
    f.unpriced_decision_ms = policy->second->decision_warm_ms.value_or(0);
    f.zfail_ms = zfail->second->end_to_end_ms;
    const auto clipped = by_rule.find("always-clipped");
    f.clipped_right = clipped != by_rule.end() && !clipped->second->refused && clipped->second->applies &&
                      as_right_as_zfail(*clipped->second, *zfail->second);
    f.clipped_ms = f.clipped_right ? clipped->second->end_to_end_ms : 0;
    frames.push_back(f);
  }
  std::sort(frames.begin(), frames.end(),
            [](const TrainingFrame& a, const TrainingFrame& b) { return a.occluder_triangles < b.occluder_triangles; });
  UnpricedFramesFit fit;
  fit.frames = frames.size();
  const CandidateMethod zfail{gl::ShadowMethod::ZFail, gl::LightProjection::Paper, zpass_far};
  const CandidateMethod clipped{gl::ShadowMethod::ZPPlus, gl::LightProjection::ClippedSides, zpass_far};
  // The frames of one triangle count, unpriced with the cheaper method or priced.
  struct Group {
    std::size_t triangles = 0, frames = 0;
    double policy_ms = 0, unpriced_ms = 0;
    CandidateMethod method;
  };
  std::vector<Group> groups;
  for (std::size_t k = 0; k < frames.size();) {
    Group g;
    g.triangles = frames[k].occluder_triangles;
    double zfail_sum = 0, clipped_sum = 0;
    bool clipped_right = true;  // on every frame of the group
    for (; k < frames.size() && frames[k].occluder_triangles == g.triangles; ++k) {
      const TrainingFrame& f = frames[k];
      zfail_sum += f.zfail_ms + f.unpriced_decision_ms;
      clipped_sum += f.clipped_ms + f.unpriced_decision_ms;
      clipped_right = clipped_right && f.clipped_right;
      g.policy_ms += f.policy_ms;
      ++g.frames;
    }
    const bool take_clipped = clipped_right && clipped_sum < zfail_sum;
    g.method = take_clipped ? clipped : zfail;
    g.unpriced_ms = take_clipped ? clipped_sum : zfail_sum;
    fit.priced_total_ms += g.policy_ms;
    groups.push_back(g);
  }
  // Groups [0, k] unpriced: the running sums over the ascending groups.
  fit.fitted_total_ms = fit.priced_total_ms;
  std::size_t unpriced_groups = 0;
  double unpriced_sum = 0, policy_sum = 0;
  for (std::size_t k = 0; k < groups.size(); ++k) {
    unpriced_sum += groups[k].unpriced_ms;
    policy_sum += groups[k].policy_ms;
    const double total = unpriced_sum + (fit.priced_total_ms - policy_sum);
    if (!(total < fit.fitted_total_ms)) continue;
    fit.fitted_total_ms = total;
    unpriced_groups = k + 1;
  }
  // Neighbouring groups with the same method: one tier, up to the last one's count.
  for (std::size_t k = 0; k < unpriced_groups; ++k) {
    const Group& g = groups[k];
    fit.unpriced_frames += g.frames;
    const bool same = !fit.unpriced.empty() && fit.unpriced.back().method.method == g.method.method &&
                      fit.unpriced.back().method.cap == g.method.cap;
    if (same)
      fit.unpriced.back().max_occluder_triangles = g.triangles;
    else
      fit.unpriced.push_back(UnpricedFrames{g.triangles, g.method});
  }
  return fit;
}

}  // namespace nearcap::analysis
