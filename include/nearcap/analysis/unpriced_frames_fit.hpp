// nearcap/analysis/unpriced_frames_fit.hpp — which frames the cost decision
// should not price (switch_policy.hpp, UnpricedFrames: tiers by the largest
// occluder's triangles), fitted on training frames that `nearcap evaluate
// --fit-unpriced` has drawn and timed.
//
// Per (configuration, light) with a policy row, the training rows give the
// policy's end-to-end time (its cold decision included) and each fixed
// rule's.  An unpriced frame would draw what "always-zfail" or
// "always-clipped" draws and pay a decision that prices nothing: charged
// the policy's warm decision time (decision_warm_ms: the camera-space scene
// and a decision whose code and data are cached), which a measured unpriced
// decision does not exceed by more than a few microseconds.  The frames
// are grouped by their largest occluder's triangles (occluder_triangles),
// ascending.  The unpriced frames are the groups up to a threshold T among
// those counts, each group drawn with the cheaper of the two methods there
// (the clipped-sides ZP+ only where always clipped drew every frame of the
// group and was as right as Z-fail on each: as many wrong pixels and cracks
// at most); the total for T is
//   sum over groups at or below T of (that method's end-to-end times +
//   decision_warm_ms)  +  sum over the others of the policy's end-to-end time;
// the fit keeps the T with the smallest total, none where pricing every
// frame is not above it, and merges neighbouring groups with the same
// method into one tier whose bound is the larger group's count: a frame
// between two groups falls in the tier above it.  A frame the policy or
// always Z-fail did not draw is left out, as the evaluation's table leaves
// it out.  The fixed rules' frames are drawn with `nearcap evaluate`'s
// settings, the policy's unpriced frames with the policy's (its tight near
// plane on a depth-limited frame): the fit prices them as the former.
#pragma once

#include <cstddef>
#include <vector>

#include "nearcap/analysis/policy_evaluation.hpp"
#include "nearcap/analysis/switch_policy.hpp"

namespace nearcap::analysis {

struct UnpricedFramesFit {
  std::vector<UnpricedFrames> unpriced;  // the tiers; empty: pricing every frame was the cheapest
  std::size_t frames = 0;                // (configuration, light) with a policy row
  std::size_t unpriced_frames = 0;       // of those, at or below the threshold
  double priced_total_ms = 0;            // every frame priced (the policy's rows)
  double fitted_total_ms = 0;            // with `unpriced`
};

// `zpass_far`: the policy's, which the method's candidate carries.
UnpricedFramesFit fit_unpriced_frames(const std::vector<EvaluationRow>& rows, gl::ZPassFar zpass_far);

}  // namespace nearcap::analysis
