// nearcap/nearcap.hpp — the front door: one header, one call per task, for a
// program that wants what the `nearcap` commands compute (a scene's exact
// near-cap, its exact per-pixel reference, a float method's frame judged
// against it, the switch policy's choice) without assembling the layers.
//
// Each call is a thin composition of the layers' own calls (named beside it),
// returns their own types, and throws what they throw: nearcap::Error
// (error.hpp), whose kind() and what() are the KIND and the MESSAGE of the
// command line's one line `nearcap: error (KIND): MESSAGE`.  A program
// that needs a choice this header does not offer calls the layer directly
// (docs/library.md lists them); the results are the same types.
//
// Costs are for one light; n is the scene's triangle count, P its pixels
// (width x height).  The exact parts use all cores (TBB).
//
//   task                          call                       cost
//   read a scene                  load_scene, parse_scene    reading the mesh files and validating them
//   the exact near-cap            exact_near_cap             O((c + k) log c): c curves, k crossings (exact)
//   the exact per-pixel reference exact_reference            grids O(n), then P exact traces
//   a frame, judged               judged_frame(s)            the reference, the frame (float32 raster), and the
//                                                            crack distance of each wrong pixel (exact)
//   the switch policy's choice    load_policy, decide_policy each occluder against the light pyramid, exact: O(n)
//   the policy's frame, judged    judged_policy_frame        its decision, then as judged_frame
//
// Every call takes a Scene as load_scene, parse_scene or SceneBuilder return
// it, and checks on entry what it can in microseconds (check_scene_fields,
// io/scene_builder.hpp: the camera, finite lights, each object's mesh and
// transform); a mesh or a light placement edited after loading is not
// checked again (rebuild the scene through SceneBuilder).  Memory that runs
// out is Error(Resource).
//
// In a judged frame the reference and the crack distances cost the most; the
// frame itself is a float32 rasterization of the scene and its volumes.
//
// Namespaces: the exact kernel, the scene and the judge are in nearcap::; the
// float GL emulation in nearcap::gl and the policy in nearcap::analysis.  The
// types of those two that this header hands out are declared here under
// nearcap:: too (ShadowMethod, DepthFormat, SwitchPolicy, ...).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/near_cap.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"
#include "nearcap/judge/crack_map.hpp"

namespace nearcap {

using analysis::PolicyDecision;
using analysis::SwitchPolicy;
using gl::DepthFormat;
using gl::DepthMapping;
using gl::LightProjection;
using gl::ShadowFrame;
using gl::ShadowMethod;

// ---- a scene ---------------------------------------------------------------
// load_scene(path): a scene file (docs/scene-format.md), its mesh paths
// relative to it.  parse_scene(json_text, source, base_directory): the same
// from JSON text, `source` naming it in messages, mesh paths relative to
// `base_directory`.  Both from io/scene_file.hpp, included above; both
// validate the scene completely (closed, outward occluders; finite,
// invertible transforms; lights strictly outside every occluder) or throw
// Error(Parse, Schema, Io, ...) naming the file, the element and the fault.

// ---- the exact kernel ------------------------------------------------------
// The exact near-cap of `light`: the near rectangle (camera space, z = -near)
// cut into faces of constant near-cap count, exact rationals
// (exact/near_cap.hpp: CameraSpaceScene, then NearCap::build).
// Throws Error(Usage) for a light the scene does not have, Error(Degenerate)
// for a light exactly in the near plane.
NearCap exact_near_cap(const Scene& scene, std::size_t light);

// The exact per-pixel reference of `light` at the scene camera's pixels: for
// each pixel centre (perturbed by nearcap's one rule, exact/perturbation.hpp)
// the near-cap count, the visible surface and its exact stencil count
// (exact/pixel_reference.hpp: CameraSpaceScene, then compute_pixel_reference).
// Throws Error(Usage) for a light the scene does not have.
PixelReference exact_reference(const Scene& scene, std::size_t light);

// ---- a float method's frame, judged ----------------------------------------
// The choices a frame is drawn with.  Every emulation choice not named here
// is gl::EmulationSettings' default, which is `nearcap cracks`' default too:
// a frame judged here is the frame `nearcap cracks SCENE --light L --method M`
// judges with the same options.
struct FrameSettings {
  ShadowMethod method = ShadowMethod::ZPPlusCorrected;  // zpass, zfail, zpplus, zpplus-corrected, preload, atomiczp
  std::size_t light = 0;                                // index into the scene's lights
  // The image in pixels; 0 keeps the scene camera's.  The frustum is the
  // scene's either way (a different aspect ratio stretches the pixels).
  int width = 0, height = 0;
  DepthFormat depth = DepthFormat::Fixed24;                   // --depth fixed24 | float32
  DepthMapping depth_mapping = DepthMapping::Standard;        // --depth-mapping standard | reversed
  LightProjection light_projection = LightProjection::Paper;  // --light-projection: how ZP+ forms its near-cap
};

// The layer's settings for these choices (gl::EmulationSettings, every other
// field at its default).  Throws Error(Usage) for a width or height outside
// [0, 16384] and for a depth, depth mapping or light projection outside its names.
gl::EmulationSettings emulation_settings(const FrameSettings& settings);

// A frame and its verdict against the exact reference.
struct JudgedFrame {
  ShadowFrame frame;  // the stencil, the visible objects, counters and times (gl/shadow_methods.hpp)
  // Wrong pixels and their kinds, and each wrong pixel's crack distance
  // (report.cracks, report.wrong_by_distance, report.distance: filled).
  CrackReport report;
};

// One method's frame, judged: the exact reference, the frame
// (gl::render_shadow_frame), judge_frame, then CrackDistances::measure on
// the wrong pixels.  The reference costs the most; to judge several methods
// of one scene, judged_frames computes it once.  Throws Error(Usage) for a
// light the scene does not have, Error(Range) for float32 transforms too
// degenerate to draw.
JudgedFrame judged_frame(const Scene& scene, const FrameSettings& settings = {});

// Each of `methods` drawn with `settings` (settings.method is not used) and
// judged against one reference, in the order given: one reference, one
// depth pre-pass per projection (gl::ShadowFrameBatch), each frame judged.
std::vector<JudgedFrame> judged_frames(const Scene& scene, const std::vector<ShadowMethod>& methods,
                                       const FrameSettings& settings = {});

// ---- the switch policy -----------------------------------------------------
// load_policy(path) (analysis/switch_policy.hpp): a policy file such as the
// shipped data/policy.json (`nearcap tune` writes one); Error(Io, Parse,
// Schema) naming the file and the key.
using analysis::load_policy;

// The policy's decision for settings.light (settings.method is not used):
// a method per occluder and why (PolicyDecision::object_methods, reason),
// and the emulation settings its frame is drawn with, built from `settings`
// with the changes the policy makes (its switch clamp, Z-pass far plane,
// depth format, ...).  analysis::decide on the scene made exact.  Throws
// Error(Usage) for a light the scene does not have.
PolicyDecision decide_policy(const SwitchPolicy& policy, const Scene& scene, const FrameSettings& settings = {});

// The frame the policy draws (decide_policy, then one frame with a method per
// occluder: gl::ShadowFrameBatch::render), judged as judged_frame judges;
// its report's method is "policy".  What `nearcap cracks --method policy`
// judges.
JudgedFrame judged_policy_frame(const SwitchPolicy& policy, const Scene& scene, const FrameSettings& settings = {});

}  // namespace nearcap
