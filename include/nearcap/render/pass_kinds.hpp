// nearcap/render/pass_kinds.hpp — a lit frame's draws by the kind of pass
// they belong to, and the work each draw does, for timing each kind on its
// own (`nearcap calibrate`, docs/calibration.md).
//
// The kinds, in the order a lit frame draws them:
//   depth      the depth pre-pass (DrawPass::Depth), once per frame;
//   near_cap   ZP+'s near-cap pass (DrawPass::NearCap): the light-frustum
//              pass over the occluders' meshes, or the clipped-sides fan;
//   sides      the volumes' sides, with ZP+ corrected's corrective quads
//              (GeometryPart::Sides and Corrective);
//   light_cap  the volumes' light caps (GeometryPart::LightCap);
//   dark_cap   the volumes' dark caps (GeometryPart::DarkCap), and ZF+'s
//              far-plane cap (a volume draw the CPU built: no vertex stage);
//   lit        a light's additive diffuse pass: the depth pre-pass's draws
//              again (depth test GL_EQUAL), so its triangles and fragments
//              are the depth pass's.
// The order of the names is analysis::PassKind's (device_profile.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <string_view>
#include <vector>

#include "nearcap/gl/shadow_methods.hpp"

namespace nearcap::render {

enum class DrawKind { Depth, Sides, LightCap, DarkCap, NearCap, Lit };
inline constexpr std::size_t kDrawKindCount = 6;
inline constexpr std::array<std::string_view, kDrawKindCount> kDrawKindNames{"depth",    "sides",    "light_cap",
                                                                             "dark_cap", "near_cap", "lit"};
inline std::string_view to_string(DrawKind k) { return kDrawKindNames[static_cast<std::size_t>(k)]; }

// The kind of a recorded draw (never Lit: the lit pass is no recorded draw).
DrawKind draw_kind(const gl::DrawCall& d);

// What the emulation's pipeline did with each of `frame.draws` (recorded,
// EmulationSettings::record_draws), one entry per draw: the draws replayed
// in their order through a gl::Framebuffer of the frame's size, cleared as
// the frame's depth pre-pass clears it, with `raster` and `depth` (the
// settings the frame was emulated with).  A draw's counters are those the
// emulation added to the frame's depth_pass, cap_pass or volume_pass, so
// each pass's sum is the frame's (tests/pass_kinds_test.cpp).  The
// fragments are those that reached the stencil test: rasterized and inside
// the scissor and depth bounds, whatever the depth test then decides, which
// is what a rasterizer pays for.  CPU work (the emulation's rasterizer, on
// all cores); no GL needed.
std::vector<gl::DrawCounters> draw_counters(const gl::ShadowFrame& frame, const gl::RasterSettings& raster,
                                            gl::DepthFormat depth);

}  // namespace nearcap::render
