// nearcap/analysis/sweep.hpp — one configuration through the exact reference
// and the float methods, as rows a sweep aggregates.
//
// A configuration is a scene file's text plus where it came from (a camera
// path's frame, or a hard-case sampler's index) and how to replay it.  For
// every light of the scene and every chosen method it gives one SweepRow:
// the exact and float case counts, the judge's counts with their crack
// distances, the conditioning features (conditioning.hpp), the work per pass
// (vertices in, fragments, and how many passed the depth test: Z-pass counts
// on passing fragments and Z-fail on failing ones, which is when one is
// slower than the other) and the time per pass, with Z-pass's frame timed
// twice to show how noisy those times are.  Rows are data: CSV with a
// fixed header (csv_header), one line per row (csv_line).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nearcap/analysis/conditioning.hpp"
#include "nearcap/analysis/engine_policies.hpp"
#include "nearcap/analysis/switch_policy.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/crack_distance.hpp"
#include "nearcap/exact/light_setup.hpp"
#include "nearcap/exact/quad_case.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/io/scene_file.hpp"

namespace nearcap::analysis {

struct SweepConfiguration {
  std::string id;          // unique in a sweep: "path:eye_in_shadow:12", "sample:7:103"
  std::string source;      // the path file, or "sampler"
  std::string kind;        // the sampler's kind, or the path's name
  std::string detail;      // the sampler's parameters, or "frame F of N"
  std::string scene_json;  // a scene file's text (mesh paths absolute)
  std::string replay;      // shell commands that write this configuration to c.json
  // Why no scene could be made (a camera path's keyframes that interpolate
  // past double's range), in place of scene_json: the configuration is
  // rejected with it, as a scene that does not load is.
  std::optional<Error> scene_error;
};

struct PassWork {
  std::uint64_t triangles = 0, fragments = 0, depth_passed = 0;
  double ms = 0;
};

struct SweepRow {
  std::string configuration, source, kind, detail, replay;
  std::size_t light = 0;
  std::string method;
  std::string variant = "default";
  std::array<std::size_t, kQuadCaseCount> exact_cases{};  // all occluders, this light
  std::array<std::size_t, kQuadCaseCount> float_cases{};  // the engine's (never degenerate)
  std::size_t case_disagreements = 0;
  std::size_t pixels_seen = 0, wrong = 0, wrong_lit = 0, wrong_shadowed = 0, count_mismatch = 0;
  std::size_t cracks = 0;                                             // wrong at crack distance >= 1/2 pixel
  std::array<std::size_t, kCrackDistanceLevels> wrong_by_distance{};  // exact/crack_distance.hpp
  long long cap_mismatch = -1;                                        // -1: the method has no whole-scene near-cap pass
  std::size_t visibility_mismatch = 0;
  std::string fallback;           // why the light fell back to Z-fail, or "" (the refusal, when refused)
  bool refused = false;           // the float pipeline refused the frame (its float32 transforms are
                                  // degenerate: error (range)); the row's counts are then all 0
  std::size_t zfail_objects = 0;  // occluders switched to Z-fail (case D)
  // Per occluder, Z-pass against Z-fail: the occluders, those for which Z-pass
  // is wrong (the exact near-cap of the occluder covers a pixel centre), and,
  // for the rows that choose per occluder (zpass, zfail, preload and the
  // engine policies; -1 for the ZP+ methods), the occluders given Z-pass
  // where it is wrong (false negatives) and Z-fail where Z-pass is right
  // (false positives).
  std::size_t occluders = 0, zpass_wrong_occluders = 0;
  long long false_negatives = -1, false_positives = -1;
  PassWork setup, depth, near_cap, volume;
  double reference_ms = 0;  // the exact reference for this light (shared by its methods)
  // Its two parts: building the tracer (the light side, reused across frames
  // when the objects and the light stay put, and the eye side: light_setup.hpp)
  // and tracing the pixels.
  double reference_setup_ms = 0, reference_trace_ms = 0;
  double decide_ms = 0;          // the switch policy's decision (its row only)
  double crack_distance_ms = 0;  // measuring this method's wrong pixels not measured before
  // Z-pass's rows: the same frame timed a second time, in a batch of its own
  // (silhouettes, depth pre-pass and all recomputed) after the light's other
  // methods, so that frame_ms and this differ only by timing noise: the
  // report's noise floor.  Empty on other rows and on a refused frame.
  std::optional<double> frame_again_ms;
  ConditioningFeatures features;  // this (frame, light), the same for every method
  // The row's frame is depth-limited (conditioning.hpp, kDepthLimitedStep)
  // with its own near plane, depth format and mapping: no method is
  // guaranteed right there.
  bool depth_limited = false;
};

// A named set of the float pipeline's choices (P_l formulation, l_near scale,
// Z-fail far mode, sub-pixel bits, depth format, FMA, ...): every method runs
// under each variant of a sweep.
struct SweepVariant {
  std::string name = "default";  // "default", or the choices that differ ("light-projection=glfrustum")
  gl::EmulationSettings settings;
};

struct SweepOptions {
  std::vector<gl::ShadowMethod> methods{gl::kAllShadowMethods.begin(), gl::kAllShadowMethods.end()};
  std::vector<SweepVariant> variants{SweepVariant{}};
  // Engine rules run beside the methods, one row each (method = their name).
  std::vector<EnginePolicy> policies;
  // The switch policy, one row (method "policy") when given.
  std::optional<SwitchPolicy> switch_policy;
  MeshCache* meshes = nullptr;  // shared by the configurations (a path's frames read their mesh once)
  // Shared by the configurations: the exact reference's light side, built
  // once while the objects and the light stay put (a camera path's frames).
  LightSetupCache* light_setups = nullptr;
};

// Loads the configuration's scene and runs every light, variant and method.  Throws
// nearcap::Error when the scene does not load (a sampler's light inside an
// occluder, say): the caller records the configuration as rejected.
std::vector<SweepRow> sweep_configuration(const SweepConfiguration& configuration, const SweepOptions& options);

std::string csv_header();
std::string csv_line(const SweepRow& row);  // with the trailing newline

}  // namespace nearcap::analysis
