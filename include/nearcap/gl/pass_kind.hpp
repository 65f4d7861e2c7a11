// nearcap/gl/pass_kind.hpp — the kinds of pass a lit frame draws, by which
// its draws are counted and timed (render/pass_kinds.hpp, `nearcap
// calibrate`, analysis/device_profile.hpp) and the shadow methods' plan
// names its draws (shadow_plan.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

namespace nearcap::gl {

// The passes a lit frame draws, each timed on its own when calibrating
// (`nearcap calibrate`, docs/calibration.md), in the order of their names:
//   depth      the depth pre-pass (DrawPass::Depth), once per frame;
//   sides      the volumes' sides, with ZP+ corrected's corrective quads;
//   light_cap  the volumes' light caps;
//   dark_cap   the volumes' dark caps, and ZF+'s far-plane cap;
//   near_cap   ZP+'s near-cap pass (DrawPass::NearCap): the light-frustum
//              pass over the occluders' meshes, or the clipped-sides fan;
//   lit        a light's additive diffuse pass: the depth pre-pass's draws
//              again (depth test GL_EQUAL).
// The names are those of calibration files and policy.json.
enum class PassKind { Depth, Sides, LightCap, DarkCap, NearCap, Lit };
inline constexpr std::size_t kPassKindCount = 6;
inline constexpr std::array<std::string_view, kPassKindCount> kPassKindNames{"depth",    "sides",    "light_cap",
                                                                             "dark_cap", "near_cap", "lit"};
inline std::string_view to_string(PassKind k) { return kPassKindNames[static_cast<std::size_t>(k)]; }

}  // namespace nearcap::gl
