// nearcap/analysis/engine_policies.hpp — the rules shipped engines use to
// choose, per occluder, between Z-pass and Z-fail: the baselines a runtime
// switch policy is measured against.
//
// Each rule is reproduced from the engine's published source as it decides
// (float32, world space), on nearcap's scene model (a point light, closed
// occluders, one camera):
//   doom3         Doom 3 (R_PotentiallyInsideInfiniteShadow): the occluder's
//                 box grown by 2 znear contains the view or the light, or the
//                 light-view segment crosses it: Z-fail.
//   doom3-bfg     Doom 3 BFG: the same box test grown by 4 znear, then the
//                 precise test (R_ViewInsideShadowVolume): Z-fail only when
//                 the view-light segment meets a light-facing triangle grown
//                 by a sphere of radius 4 znear.
//   ogre          Ogre (Light::_getNearClipVolume): the volume between the
//                 light and the camera's near rectangle (four planes through
//                 the light and the rectangle's edges, the camera's plane,
//                 and the plane through the light parallel to it) meets the
//                 caster's world box: Z-fail.  A light within 1e-6 of the near
//                 plane makes the volume degenerate: Z-fail for every caster
//                 (what Ogre's comment says it intends; its code builds two
//                 world-space planes z = +-near instead).
//   always-zfail  Z-fail for every occluder.
// The boxes are world-space axis-aligned boxes of the transformed vertices
// (the engines keep object-space boxes of unscaled models; for a rotated
// object the world box is the larger, so the rule only gets more
// conservative).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/named_values.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::analysis {

enum class EnginePolicy { Doom3, Doom3BFG, Ogre, AlwaysZFail };
inline constexpr NamedValue<EnginePolicy> kEnginePolicyTable[] = {
    {EnginePolicy::Doom3, "doom3", "Doom 3's box test grown by 2 znear"},
    {EnginePolicy::Doom3BFG, "doom3-bfg", "Doom 3 BFG's box test, then its precise test"},
    {EnginePolicy::Ogre, "ogre", "Ogre's near-clip volume against the caster's box"},
    {EnginePolicy::AlwaysZFail, "always-zfail", "Z-fail for every occluder"},
};
constexpr const auto& named_values(EnginePolicy) { return kEnginePolicyTable; }
static_assert(names_are_unique<EnginePolicy>());
inline constexpr auto kAllEnginePolicies = values_of<EnginePolicy>();
std::string_view to_string(EnginePolicy p);
std::optional<EnginePolicy> engine_policy_from_string(std::string_view name);

// One occluder's choice and the test that made it.
struct OccluderChoice {
  std::size_t object = 0;
  bool zfail = false;
  std::string_view reason;  // e.g. "view in the grown box", "no test met"
};

// The rule's choice for every occluder of the scene under `light`.
std::vector<OccluderChoice> engine_choices(EnginePolicy policy, const Scene& scene, std::size_t light);

// The methods per scene object for gl::ShadowFrameBatch::render: Z-fail where
// chosen, Z-pass elsewhere (non-occluders: Z-pass, unused).
std::vector<gl::ShadowMethod> object_methods(const Scene& scene, const std::vector<OccluderChoice>& choices);

}  // namespace nearcap::analysis
