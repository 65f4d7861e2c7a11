#include "nearcap/analysis/unpriced_frames_fit.hpp"

#include <algorithm>
#include <map>
#include <string>
#include <tuple>
#include <utility>

namespace nearcap::analysis {

namespace {

// One (configuration, light) of the training rows.
struct TrainingFrame {
  std::size_t occluder_triangles = 0;
  double policy_ms = 0;
  double unpriced_decision_ms = 0;
  double zfail_ms = 0, clipped_ms = 0;  // the fixed rules' end-to-end times
  // Always clipped drew this frame and is as right as Z-fail here: only
  // then may the clipped-sides ZP+ be the unpriced method at or above it.
  bool clipped_right = false;
};

}  // namespace

UnpricedFramesFit fit_unpriced_frames(const std::vector<EvaluationRow>& rows, gl::ZPassFar zpass_far) {
  using Key = std::tuple<std::string, std::string, std::size_t>;
  std::map<Key, std::map<std::string, const EvaluationRow*>> groups;
  for (const EvaluationRow& r : rows) groups[{r.set, r.configuration, r.light}][r.rule] = &r;
  std::vector<TrainingFrame> frames;
  for (const auto& [key, by_rule] : groups) {
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
  for (const TrainingFrame& f : frames) fit.priced_total_ms += f.policy_ms;
  fit.fitted_total_ms = fit.priced_total_ms;
  const CandidateMethod zfail{gl::ShadowMethod::ZFail, gl::LightProjection::Paper, zpass_far};
  const CandidateMethod clipped{gl::ShadowMethod::ZPPlus, gl::LightProjection::ClippedSides, zpass_far};
  // Frames [0, k) unpriced: the running sums over the sorted frames, a
  // threshold where the triangle count changes (or after the last frame).
  double zfail_sum = 0, clipped_sum = 0, policy_sum = 0;
  bool clipped_right = true;  // on every frame so far
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const TrainingFrame& f = frames[k];
    zfail_sum += f.zfail_ms + f.unpriced_decision_ms;
    clipped_sum += f.clipped_ms + f.unpriced_decision_ms;
    clipped_right = clipped_right && f.clipped_right;
    policy_sum += f.policy_ms;
    if (k + 1 < frames.size() && frames[k + 1].occluder_triangles == f.occluder_triangles) continue;
    const double rest = fit.priced_total_ms - policy_sum;
    for (const auto& [method, sum] : {std::pair{zfail, zfail_sum}, std::pair{clipped, clipped_sum}}) {
      if (method.method != gl::ShadowMethod::ZFail && !clipped_right) continue;
      if (!(sum + rest < fit.fitted_total_ms)) continue;
      fit.fitted_total_ms = sum + rest;
      fit.unpriced = UnpricedFrames{f.occluder_triangles, method};
      fit.unpriced_frames = k + 1;
    }
  }
  return fit;
}

}  // namespace nearcap::analysis
