// nearcap/analysis/hard_case_sampler.hpp — seeded, replayable hard
// configurations for sweeps and stress tests.
//
// Each configuration is a scene (JSON text that `nearcap cracks` accepts, so
// any row of a sweep can be written out and replayed alone) of one kind:
//   light-near-plane     the light 2^-k from the camera's near plane (k in
//                        [1, 40]), on either side
//   light-in-near-plane  the light exactly in the near plane (ZP+ has no light frustum)
//   grazing              the light level with an axis-aligned box's face: edge-on
//                        triangles, silhouettes along the light's plane
//   eye-in-shadow        an occluder between the eye and the light
//   far-from-origin      everything moved 2^20 m or 10^6 m from the origin
//   tiny-near            near planes from 2^-10 down to 10^-6
//   straddling           an occluder cut by the near plane
//   several-occluders    two to four occluders (boxes and tori)
//   several-lights       two or three lights
//   real-mesh            a bundled real mesh (eight, knot1; bunny when allowed)
// Every coordinate is a dyadic rational or an integer (exact doubles; a
// translation by them is exact), the camera looks down -z with a
// translation-only view, and a receiver slab lies under everything.
// Configuration `index` of seed `seed` depends on those two numbers alone
// (its generator is seeded from both), so any configuration replays without
// the ones before it, and a sweep can be split across processes by index.
// Some configurations put a light inside an occluder; loading one then fails
// with Error(Light): callers count those as rejected.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "nearcap/named_values.hpp"

namespace nearcap::analysis {

enum class HardCaseKind {
  LightNearNearPlane,
  LightInNearPlane,
  Grazing,
  EyeInShadow,
  FarFromOrigin,
  TinyNear,
  Straddling,
  SeveralOccluders,
  SeveralLights,
  RealMesh,
  // AtomicZP's eye count (gl/eye_count.hpp) where it is hard: the eye a
  // signed 2^-18 .. 2^-40 (or 0) from a plane its tests use (the ray from the
  // light through a box corner, or through an edge's midpoint), near the
  // light, or with the box behind it on the segment to the light.  Not
  // among all_hard_case_kinds(), so that adding it leaves every seed's
  // configurations of the default kinds as they are; asked for by name.
  EyeNearVolume,
  // A light 10^2 .. 10^8 (or 2^7 .. 2^27) away in a direction above the
  // scene, a sun-like light: either the common configuration's box, or a box
  // placed from the eye towards the light so that the eye stands in or at
  // the edge of its shadow.  Asked for by name only, as EyeNearVolume.
  FarLight,
};
// The kinds' names (named_values.hpp), in the enum's order.
inline constexpr NamedValue<HardCaseKind> kHardCaseKindTable[] = {
    {HardCaseKind::LightNearNearPlane, "light-near-plane", "the light 2^-k from the camera's near plane"},
    {HardCaseKind::LightInNearPlane, "light-in-near-plane", "the light exactly in the near plane"},
    {HardCaseKind::Grazing, "grazing", "the light level with a box's face"},
    {HardCaseKind::EyeInShadow, "eye-in-shadow", "an occluder between the eye and the light"},
    {HardCaseKind::FarFromOrigin, "far-from-origin", "everything moved 2^20 m or 10^6 m from the origin"},
    {HardCaseKind::TinyNear, "tiny-near", "near planes from 2^-10 down to 10^-6"},
    {HardCaseKind::Straddling, "straddling", "an occluder cut by the near plane"},
    {HardCaseKind::SeveralOccluders, "several-occluders", "two to four occluders"},
    {HardCaseKind::SeveralLights, "several-lights", "two or three lights"},
    {HardCaseKind::RealMesh, "real-mesh", "a bundled real mesh"},
    {HardCaseKind::EyeNearVolume, "eye-near-volume", "the eye next to a plane of AtomicZP's eye count"},
    {HardCaseKind::FarLight, "far-light", "the light about 10^2 to 10^8 away, sun-like"},
};
constexpr const auto& named_values(HardCaseKind) { return kHardCaseKindTable; }
static_assert(names_are_unique<HardCaseKind>());
inline constexpr int kHardCaseKindCount = static_cast<int>(named_count<HardCaseKind>());
std::string_view to_string(HardCaseKind kind);
// The kinds a sweep samples by default: every kind but those asked for by
// name only (asked_for_by_name_only).
std::vector<HardCaseKind> all_hard_case_kinds();
// EyeNearVolume and FarLight: left out of all_hard_case_kinds(), so that a
// seed's configurations of the default kinds do not depend on them.
bool asked_for_by_name_only(HardCaseKind kind);
// Throws Error(Usage) naming the unknown kind.
HardCaseKind hard_case_kind_from_string(std::string_view name);

struct SamplerSpec {
  std::uint64_t seed = 1;
  std::vector<HardCaseKind> kinds = all_hard_case_kinds();  // chosen uniformly per configuration
  int width = 48, height = 36;
  std::string mesh_directory;  // where box.off, torus.off, eight.off, knot1.off, bunny.off are (data/meshes)
  bool allow_bunny = false;    // the 75k-triangle bunny among the real meshes
};

struct HardCase {
  std::uint64_t seed = 0, index = 0;
  HardCaseKind kind = HardCaseKind::EyeInShadow;
  std::string detail;      // the kind's parameters, e.g. "k=37 below", "offset=1e6"
  std::string scene_json;  // a scene file's text; mesh paths absolute
};

// The mesh files a sampler with `spec` may read (absolute paths, in a fixed
// order): what its configurations are made of besides the spec.
std::vector<std::string> sampler_mesh_files(const SamplerSpec& spec);

class HardCaseSampler {
 public:
  explicit HardCaseSampler(SamplerSpec spec);
  HardCase sample(std::uint64_t index) const;
  const SamplerSpec& spec() const { return spec_; }

 private:
  SamplerSpec spec_;
};

}  // namespace nearcap::analysis
