// nearcap/analysis/work_estimate.hpp — what a frame will draw, per occluder
// and method, estimated before drawing: the work (device_profile.hpp's
// FrameWork) that the switch policy's cost decision prices with a device
// profile, and that `nearcap calibrate` can pair with the passes it times so
// that the profile is fitted against the estimate (predicted time =
// profile(estimate)).
//
// Per occluder (camera space, double, from the scene's exact doubles):
//   triangles          the mesh's;
//   silhouette edges   facing from the object-space face planes, sign of
//                      n . (l - a) (gl::engine_silhouette decides the same sign
//                      in float32: the two agree except on faces within
//                      rounding of edge-on to the light);
//   light-facing       the light cap's triangles (the dark cap: the others);
//   near-plane work    the triangles the clipped-sides cap builder tests (0
//                      where it skips the occluder: its bounds on one side of
//                      the near plane, or certainly outside the light pyramid)
//                      and, of those, the ones that straddle the near plane
//                      (the cap's fan has about one triangle per such one);
//   coverage           the pixels each pass covers (screen_coverage.hpp):
//                      the projected areas, clipped to the view volume, of
//                      the light-facing triangles (the light cap), of the
//                      others as directions from the light (the dark cap)
//                      and of the silhouette's quads (the sides; depth-
//                      clamped, AtomicZP's, not clipped by the near plane),
//                      and the near plane's section of the volume, each
//                      pixel times the layers that hold it (the near-cap;
//                      0 where the clipped-sides cap is not built);
//   triangles in view  per pass, of the sampled triangles (quads), the
//                      pieces a near-plane clipper makes of them whose
//                      bounds meet the viewport: what a GL sets up and bins
//                      (gl::DrawCounters::in_view), against the triangles
//                      it is given and rejects at the clip test; for the
//                      clipped-sides cap's fan, the straddling triangles
//                      whose section of the near plane meets its rectangle.
// A mesh of more than kCoverageSamples faces is sampled: every k-th face,
// k = faces / kCoverageSamples, from the k/2-th, its area times k; the
// sides likewise, k = silhouette edges / kSideSamples (a rough sum: their
// areas are uneven).
// Each pass draws its triangles with both facings and no culling, so its
// fragments are its triangles' coverage, up to the rasterizer's sampling of
// pixel centres; the near-cap's fan can draw more where it cannot avoid
// overdraw (gl/near_plane_cap.hpp), the paper's cap a little more or less
// (tests/cost_decision_test.cpp compares each with the emulation's counters).
//
// Triangle counts equal the emulation's submitted triangles (DrawCounters::
// triangles) where the method's draws are known before drawing: the depth
// pre-pass, Z-pass's and ZP+'s sides, Z-fail's closed volume, the paper
// near-cap pass.  ZP+ corrected's corrective quads and case-D switches and
// the clipped-sides cap's fan are decided while drawing: estimates.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "nearcap/analysis/device_profile.hpp"
#include "nearcap/analysis/occluder_facing.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::analysis {

// The faces (silhouette edges) a cap's (the sides') coverage sum reads at
// most per mesh.
inline constexpr std::size_t kCoverageSamples = 256, kSideSamples = 128;
// A sampled near-cap with fewer covering faces than this (a narrow view
// from the light, few faces covering much each) is summed over every face.
inline constexpr std::size_t kCoverageMinHits = 16;

// One candidate of the cost decision: a method and, for a ZP+ method, its
// near-cap (LightProjection::ClippedSides, or the paper's light frustum;
// Composed counts as the paper's).
struct CandidateMethod {
  gl::ShadowMethod method = gl::ShadowMethod::ZFail;
  gl::LightProjection cap = gl::LightProjection::Paper;
  // Z-pass's and ZP+'s far plane (EmulationSettings::zpass_far): a finite
  // one clips their sides' vertices at infinity, and so adds pieces in
  // view; Z-fail's is always infinite.
  gl::ZPassFar zpass_far = gl::ZPassFar::Finite;
  std::string name() const;  // "zpass", "zfail", "zpplus-paper", "zpplus-clipped-sides", "zpplus-corrected-paper"
};

// What the estimate reads of one occluder under one light (see above).
struct OccluderWorkInputs {
  std::size_t object = 0;  // scene object index
  double triangles = 0;
  double silhouette_edges = 0;
  double light_facing = 0;
  // The occluder's volume's bounds reach the near plane: the clipped-sides
  // cap builder gets past its box test (and then runs the pyramid cull).
  bool reaches_near_plane = false;
  double clipped_cap_tested = 0;     // triangles the clipped-sides cap builder visits
  double near_plane_straddling = 0;  // of those, the ones with vertices on both sides of the near plane
  double light_cap_pixels = 0, dark_cap_pixels = 0, sides_pixels = 0, sides_clamped_pixels = 0;
  double near_cap_pixels = 0;
  // The same passes' triangles in view (gl::DrawCounters::in_view): of the
  // sampled faces (quads), the pieces a near-plane clipper makes whose
  // bounds meet the viewport (ScreenCoverage::in_view_pieces), times the
  // sampling stride; the paper near-cap's as the light sees them.  0 where
  // the coverage is not computed.
  double light_cap_in_view = 0, dark_cap_in_view = 0, sides_in_view = 0, sides_clamped_in_view = 0;
  double near_cap_in_view = 0;
  double sides_finite_far_in_view = 0;  // the sides clipped at a finite far plane (ZPassFar::Finite)
  // Of the straddling triangles, those whose section of the near plane
  // meets the near rectangle: the clipped-sides cap's fan pieces in view.
  double near_cap_fan_in_view = 0;
  // gl::certainly_misses_light_pyramid: the near-cap is certainly empty, so
  // Z-pass is exact without the exact test.  Run only where
  // `pyramid_cull_run` (else false: not known).
  bool certainly_misses_light_pyramid = false;
  bool pyramid_cull_run = true;
  // The faces that cull tested one by one (its faces_examined; 0 where it
  // did not run).
  double pyramid_cull_examined = 0;
};

// What occluder_work_inputs computes beyond the counts.
struct WorkInputsOptions {
  // The light-pyramid cull everywhere (else only where the clipped-sides
  // cap's work depends on it).
  bool pyramid_cull = true;
  // The sides' coverage and triangles in view (sides_pixels,
  // sides_clamped_pixels and their _in_view counts; else 0): every
  // candidate but AtomicZP draws the same sides (at an infinite far plane),
  // so a choice among the others does not need it.
  bool sides_coverage = true;
  // Where given, the facing and the silhouette's edges come from it
  // (occluder_facing.hpp), else they are computed.
  FacingCache* facings = nullptr;
};

// Occluder `object` under scene.lights[light].  The object must be an
// occluder with adjacency (validate_occluder) and face planes.
// The light-pyramid cull (the dearest input on a mesh near the pyramid) runs
// where the clipped-sides cap's work depends on it (the volume reaches the
// near plane), and everywhere with options.pyramid_cull; every other field
// is the same either way (tests/cost_decision_test.cpp).  Allocates the
// faces the light's view of the near rectangle may hold.
OccluderWorkInputs occluder_work_inputs(const Scene& scene, std::size_t object, std::size_t light,
                                        const WorkInputsOptions& options = {});

// The work of one occluder drawn with `c`, CPU included (its clipped-sides
// cap's construction, one run of CpuTaskWork), shared passes and
// silhouettes excluded.  The exact test is per light: exact_test_work.
FrameWork occluder_work(const OccluderWorkInputs& in, const CandidateMethod& c);

// The counts of the clipped-sides cap's construction for one occluder (one
// run; device_profile.hpp, CpuTaskWork).
CpuTaskWork clipped_cap_work(const OccluderWorkInputs& in);

// The counts of one run of the exact empty-near-cap test (all occluders of
// one light; CpuTaskWork), from every occluder's inputs; `tested` counts
// the occluders whose float pyramid cull ran and did not settle them.
CpuTaskWork exact_test_work(const std::vector<OccluderWorkInputs>& occluders);

// What every method of the frame pays once: the depth pre-pass and the lit
// pass over every object, and every occluder's silhouette; without
// `with_coverage`, their fragments 0 (the same for every candidate: a
// choice does not need them).
FrameWork shared_frame_work(const Scene& scene, bool with_coverage = true);

// The estimate of a whole frame drawn as ShadowFrameBatch(scene, light,
// settings).render(object_methods) draws it (the cap kind from
// settings.light_frustum.projection; the exact test not counted): what
// calibration pairs with the frame's measured passes.
FrameWork estimate_frame_work(const Scene& scene, std::size_t light,
                              const std::vector<gl::ShadowMethod>& object_methods,
                              const gl::EmulationSettings& settings);

}  // namespace nearcap::analysis
