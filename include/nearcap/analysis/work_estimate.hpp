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
//   footprints         pixel centres of the viewport in the projected convex
//                      hull's bounding box of: the occluder's box, clipped to
//                      the near plane; its shadow volume (the box's corners and
//                      their directions from the light), clipped likewise; and
//                      that volume's section by the near plane (the near-cap
//                      can cover no more), each grown by a pixel for the
//                      rasterizer's snapping.
// The fragment estimates are footprints times layers: 2 for a closed surface
// (front and back), 1 for the paper's near-cap pass (one facing culled).
// For a convex occluder (a line meets its surface, and its convex shadow
// volume's, at most twice) each is an upper bound on the fragments the pass
// rasterizes; for others an estimate whose scale the fitted profile absorbs
// (tests/cost_decision_test.cpp checks the bounds and the counts against the
// emulation's draw counters).
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
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::analysis {

// One candidate of the cost decision: a method and, for a ZP+ method, its
// near-cap (LightProjection::ClippedSides, or the paper's light frustum;
// Composed counts as the paper's).
struct CandidateMethod {
  gl::ShadowMethod method = gl::ShadowMethod::ZFail;
  gl::LightProjection cap = gl::LightProjection::Paper;
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
  double occluder_pixels = 0, volume_pixels = 0, near_cap_pixels = 0;
  // gl::certainly_misses_light_pyramid: the near-cap is certainly empty, so
  // Z-pass is exact without the exact test.  Run only where
  // `pyramid_cull_run` (else false: not known).
  bool certainly_misses_light_pyramid = false;
  bool pyramid_cull_run = true;
  // The faces that cull tested one by one (its faces_examined; 0 where it
  // did not run).
  double pyramid_cull_examined = 0;
};

// Occluder `object` under scene.lights[light].  The object must be an
// occluder with adjacency (validate_occluder) and face planes.
// The light-pyramid cull (the dearest input on a mesh near the pyramid) runs
// where the clipped-sides cap's work depends on it (the volume reaches the
// near plane), and everywhere with `pyramid_cull`; every other field is the
// same either way (tests/cost_decision_test.cpp).  Allocates only the
// per-face facing and, where the cap's work is counted, per-vertex distances.
OccluderWorkInputs occluder_work_inputs(const Scene& scene, std::size_t object, std::size_t light,
                                        bool pyramid_cull = true);

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
// pass over every object, and every occluder's silhouette.
FrameWork shared_frame_work(const Scene& scene);

// The estimate of a whole frame drawn as ShadowFrameBatch(scene, light,
// settings).render(object_methods) draws it (the cap kind from
// settings.light_frustum.projection; the exact test not counted): what
// calibration pairs with the frame's measured passes.
FrameWork estimate_frame_work(const Scene& scene, std::size_t light,
                              const std::vector<gl::ShadowMethod>& object_methods,
                              const gl::EmulationSettings& settings);

}  // namespace nearcap::analysis
