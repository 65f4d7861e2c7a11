// nearcap/analysis/device_profile.hpp — what a frame costs on one GL: a
// device cost profile, per pass kind and per unit of CPU work, measured by
// `nearcap calibrate` and read by the switch policy's decision.
//
// A frame's predicted end-to-end time is the sum of its passes' GL times and
// its CPU work:
//   time = sum over pass kinds k of (intercept_k [if the pass is drawn]
//            + a_k * triangles_k + v_k * in_view_k + b_k * fragments_k)
//        + the same for AtomicZP's eye-count pass, where the profile has
//          its row (`eye_count`, optional: without it the decision does
//          not offer AtomicZP): a compute dispatch over the counted
//          occluders' triangles, once per frame, and the count's write into
//          the stencil, one fragment per pixel of the viewport
//        + with the profile's optional `frame` row: frame.intercept_ms once
//          per frame, less frame.ms_saved_per_pass for every pass drawn
//          (the eye-count pass among them)
//        + cpu.ms_per_ktriangle_silhouette * silhouette_triangles / 1000
//        + cpu.clipped_cap.ms(clipped_cap) + cpu.exact_test.ms(exact_test)
// with a_k in ms per million triangles submitted, v_k per million of them
// in view (set up and not culled, bounds meeting the viewport: the
// clipped polygons' fan pieces counted each) and b_k in ms per million
// fragments.  A GL pays for every triangle it is given (the vertex stage,
// the clip test) and much more for each one it sets up and bins: on
// llvmpipe the depth pass of a room whose 12,000-triangle torus is in view
// takes several times what it takes with the torus behind the eye
// (docs/findings/in-view-triangles.md).  So the triangles in view are a
// term of their own;
// and each of the two dear CPU tasks linear in counts of its work:
//   ms = intercept_ms * runs + (ms_per_ktriangle * triangles
//        + ms_per_kreaching * reaching + ms_per_ktested * tested
//        + ms_per_kstraddling * straddling + ms_per_kexamined * examined)
//        / 1000.
// A task's cost follows how much of the mesh the near plane and the light
// pyramid involve, not the mesh's size: the clipped-sides cap is nearly free
// where the occluder's volume does not reach the near plane, and the exact
// test scans only occluders its float cull cannot settle.  The counts
// (CpuTaskWork) are ones the decision computes anyway (work_estimate.hpp),
// so pricing them costs no extra work per decision.
// The work (FrameWork) is what the decision can compute before drawing
// (triangle counts, silhouette size, cheap bounds on each pass's screen
// area) or, when calibrating, what the frame really drew.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nearcap/gl/pass_kind.hpp"

namespace nearcap::analysis {

// The passes a frame draws, each timed on its own when calibrating: the
// gl layer's kinds (pass_kind.hpp), by which the emulation names its draws.
using gl::kPassKindCount;
using gl::kPassKindNames;
using gl::PassKind;

// The largest cost coefficient a profile holds, in milliseconds (per pass,
// per million or thousand of a count, per frame): a quarter of an hour.  The
// decision sums and compares costs in double, and a coefficient near 10^16
// would swallow the others' milliseconds; the profile's reader refuses a
// larger one and the fit stays within it.
inline constexpr double kMaxCostCoefficientMs = 1e6;

// The eye-count pass's row in a profile's `passes` (optional).
inline constexpr std::string_view kEyeCountPassName = "eye_count";

struct PassCost {
  double intercept_ms = 0;      // per pass drawn (state changes, the draw call)
  double ms_per_mtriangle = 0;  // per million triangles submitted
  double ms_per_mfragment = 0;  // per million fragments rasterized
  // Per million triangles in view (gl::DrawCounters::in_view); a profile
  // without it (0) prices every work as the two-count sum.
  double ms_per_mtriangle_in_view = 0;
  // A drawn pass's time: its intercept and its counts' terms.
  double ms(double triangles, double fragments, double in_view) const {
    return intercept_ms + ms_per_mtriangle * triangles * 1e-6 + ms_per_mfragment * fragments * 1e-6 +
           ms_per_mtriangle_in_view * in_view * 1e-6;
  }
};

// What a frame drawn whole costs beside its passes timed each on its own.
// Calibration times every pass between two glFinish calls, so each pass
// kind's intercept holds one synchronisation with the GL; a frame drawn
// without those waits pays one at its end, and its passes overlap the
// driver's work.  Fitted on whole frames timed end to end (`nearcap
// calibrate`'s frame rows): a frame's GL time is its passes' predictions,
// less ms_saved_per_pass per pass drawn, plus intercept_ms.
// ms_saved_per_pass is at most the smallest pass intercept of the profile.
struct FrameCost {
  double intercept_ms = 0;       // once per frame (its one glFinish, what no pass holds)
  double ms_saved_per_pass = 0;  // per pass drawn: its share of a pass intercept a whole frame does not pay
};

// The counts one of the two dear CPU tasks is priced by, summed over its
// runs.  What each count is, per task:
//   clipped_cap (building the clipped-sides near-cap, one run per occluder
//   drawn with it; gl/shadow_methods.cpp, clipped_sides_cap):
//     triangles   the side triangles, two per silhouette edge;
//     reaching    the occluder's triangles where its volume's bounds reach
//                 the near plane (the builder then runs the light-pyramid
//                 cull and, unless it culls, the near-plane distance of
//                 every vertex); 0 where the box test skips it;
//     tested      the triangles the builder tests against the near plane
//                 (OccluderWorkInputs::clipped_cap_tested);
//     straddling  of those, the ones with vertices on both sides (the
//                 extrusion program, the clipping and the fan run on them);
//     examined    the faces the float light-pyramid cull tested one by one
//                 (gl/light_pyramid_cull.hpp, faces_examined): 0 where its
//                 mesh and chunk boxes decide, up to every face where it
//                 finds a face in the pyramid late or not at all.
//   exact_test (the exact empty-near-cap test of every occluder under one
//   light, one run per light; exact/light_pyramid.hpp,
//   occluders_meeting_light_pyramid):
//     triangles   every occluder's;
//     reaching    the triangles of the occluders whose volume reaches the
//                 near plane;
//     tested      the triangles of the occluders the float light-pyramid
//                 cull leaves undecided (those the test scans face by face);
//     straddling  the occluders' near-plane straddling triangles;
//     examined    0 (its float cull runs in the decision's estimate, whose
//                 cost the decision's time holds).
struct CpuTaskWork {
  double runs = 0, triangles = 0, reaching = 0, tested = 0, straddling = 0, examined = 0;
  CpuTaskWork& operator+=(const CpuTaskWork& o) {
    runs += o.runs;
    triangles += o.triangles;
    reaching += o.reaching;
    tested += o.tested;
    straddling += o.straddling;
    examined += o.examined;
    return *this;
  }
};

// A CPU task's cost, linear in its counts: ms per run, and ms per thousand
// of each count.  All finite and not negative.  ms_per_kexamined is added
// last: a profile without it (0) prices every work to the same bits as the
// four-count sum.
struct CpuTaskCost {
  double intercept_ms = 0;
  double ms_per_ktriangle = 0, ms_per_kreaching = 0, ms_per_ktested = 0, ms_per_kstraddling = 0;
  double ms_per_kexamined = 0;
  double ms(const CpuTaskWork& w) const {
    return intercept_ms * w.runs +
           (ms_per_ktriangle * w.triangles + ms_per_kreaching * w.reaching + ms_per_ktested * w.tested +
            ms_per_kstraddling * w.straddling + ms_per_kexamined * w.examined) *
               1e-3;
  }
};

struct CpuCost {
  double ms_per_ktriangle_silhouette = 0;  // finding an occluder's silhouette, per thousand occluder triangles
  CpuTaskCost clipped_cap;                 // building the clipped-sides near-cap (CpuTaskWork)
  CpuTaskCost exact_test;                  // the exact empty-near-cap test (CpuTaskWork)
};

// AtomicZP's eye-count pass in a frame's work: drawn once per frame,
// its triangles the counted occluders' (one invocation each), its fragments
// the stencil write's (the viewport's pixels, once per frame).
struct EyeCountWork {
  bool drawn = false;
  double triangles = 0, fragments = 0;
};

// One frame's (or one occluder's) work, by pass kind and CPU task.
struct FrameWork {
  std::array<bool, kPassKindCount> drawn{};
  std::array<double, kPassKindCount> triangles{}, fragments{};
  std::array<double, kPassKindCount> in_view{};  // set-up triangles meeting the viewport (PassCost)
  EyeCountWork eye_count;
  double silhouette_triangles = 0;
  CpuTaskWork clipped_cap, exact_test;
  FrameWork& operator+=(const FrameWork& o) {
    for (std::size_t k = 0; k < kPassKindCount; ++k) {
      drawn[k] = drawn[k] || o.drawn[k];
      triangles[k] += o.triangles[k];
      fragments[k] += o.fragments[k];
      in_view[k] += o.in_view[k];
    }
    eye_count.drawn = eye_count.drawn || o.eye_count.drawn;
    eye_count.triangles += o.eye_count.triangles;
    eye_count.fragments += o.eye_count.fragments;
    silhouette_triangles += o.silhouette_triangles;
    clipped_cap += o.clipped_cap;
    exact_test += o.exact_test;
    return *this;
  }
};

struct DeviceProfile {
  std::string gl_renderer;  // GL_RENDERER of the GL it was measured on ("" when written by hand)
  std::string origin;       // "calibrated", "hand" or "scaled"
  std::array<PassCost, kPassKindCount> passes{};
  // AtomicZP's eye-count pass (EyeCountWork); absent: not measured, and
  // the decision does not offer AtomicZP (a work's eye count then costs 0).
  std::optional<PassCost> eye_count;
  // The whole frame's row (FrameCost); absent: a frame costs its passes'
  // sum, as each pass was timed.
  std::optional<FrameCost> frame;
  CpuCost cpu;
  double gl_ms(const FrameWork& w) const {
    double t = 0;
    std::size_t drawn = 0;
    for (std::size_t k = 0; k < kPassKindCount; ++k) {
      t += (w.drawn[k] ? passes[k].intercept_ms : 0.0) + passes[k].ms_per_mtriangle * w.triangles[k] * 1e-6 +
           passes[k].ms_per_mfragment * w.fragments[k] * 1e-6 +
           passes[k].ms_per_mtriangle_in_view * w.in_view[k] * 1e-6;
      drawn += w.drawn[k] ? 1 : 0;
    }
    if (eye_count) {
      t += (w.eye_count.drawn ? eye_count->intercept_ms : 0.0) +
           eye_count->ms_per_mtriangle * w.eye_count.triangles * 1e-6 +
           eye_count->ms_per_mfragment * w.eye_count.fragments * 1e-6;
      drawn += w.eye_count.drawn ? 1 : 0;
    }
    if (frame && drawn > 0) t += frame->intercept_ms - frame->ms_saved_per_pass * static_cast<double>(drawn);
    return t;
  }
  double cpu_ms(const FrameWork& w) const {
    return cpu.ms_per_ktriangle_silhouette * w.silhouette_triangles * 1e-3 + cpu.clipped_cap.ms(w.clipped_cap) +
           cpu.exact_test.ms(w.exact_test);
  }
  double predict_ms(const FrameWork& w) const { return gl_ms(w) + cpu_ms(w); }
};

// What `nearcap calibrate` measures: one pass of one frame, timed on its own
// (glFinish before and after), with the work it really drew.
struct PassObservation {
  std::string frame;  // configuration and light, e.g. "near_plane_sweep:42:light0:zfail"
  PassKind kind = PassKind::Depth;
  double triangles = 0, fragments = 0, ms = 0;
  double in_view = 0;  // set-up triangles meeting the viewport (gl::DrawCounters::in_view)
};
// AtomicZP's eye-count pass of one light frame, timed on its own (the
// compute dispatch and the count's write into the stencil, glFinish after):
// its triangles (the counted occluders') and fragments (the viewport's).
struct EyeCountObservation {
  std::string frame;  // configuration and light, e.g. "sample:1:7:light0:atomiczp"
  double triangles = 0, fragments = 0, ms = 0;
};
// One method's whole lit frame of one configuration (every light), drawn
// again at once without the per-pass timing, timed end to end (up to
// glFinish, uploads included).  Its passes are the pass and eye-count
// observations whose frame is `frame`, or `frame` with ":lightK" inserted
// before its last component (frame_of_pass, device_profile_fit.hpp).
struct FrameObservation {
  std::string frame;  // configuration and method, e.g. "sample:1:7:zfail"
  double ms = 0;
};
// One CPU task, timed on its own, with its counts: for the silhouette the
// occluder's triangles; for the clipped-sides cap and the exact test one
// run's CpuTaskWork (runs = 1).
enum class CpuTask { Silhouette, ClippedCap, ExactTest };
struct CpuObservation {
  std::string frame;
  CpuTask task = CpuTask::Silhouette;
  double triangles = 0, ms = 0;
  double reaching = 0, tested = 0, straddling = 0;  // 0 for the silhouette
  double examined = 0;                              // the clipped-sides cap's; 0 for the others
  CpuTaskWork work() const { return {1, triangles, reaching, tested, straddling, examined}; }
};

// The same profile with its GL passes `gl_factor` times as fast and its CPU
// work `cpu_factor` times as fast (origin "scaled"): what a GPU would
// change, the CPU kept.  Factors must be finite and positive, and no scaled
// cost may exceed kMaxCostCoefficientMs (else an error, usage, naming the
// field).  In the core library (switch_policy.cpp), beside the profile's
// reader and writer.
DeviceProfile scaled_profile(const DeviceProfile& p, double gl_factor, double cpu_factor = 1.0);

}  // namespace nearcap::analysis
