// nearcap/render/pass_kinds.hpp — a lit frame's draws by the kind of pass
// they belong to (gl::PassKind, gl/pass_kind.hpp), and the work each draw
// does, for timing each kind on its own (`nearcap calibrate`,
// docs/calibration.md).
//
// A recorded draw's kind:
//   depth      DrawPass::Depth;
//   near_cap   DrawPass::NearCap: the light-frustum pass over the occluders'
//              meshes, or the clipped-sides fan;
//   sides      GeometryPart::Sides and Corrective (ZP+ corrected's
//              corrective quads);
//   light_cap  GeometryPart::LightCap;
//   dark_cap   GeometryPart::DarkCap, and ZF+'s far-plane cap (a volume
//              draw the CPU built: no vertex stage);
//   lit        none: the lit pass draws the depth pre-pass's draws again
//              (depth test GL_EQUAL), so its triangles and fragments are the
//              depth pass's.
#pragma once

#include <vector>

#include "nearcap/gl/pass_kind.hpp"
#include "nearcap/gl/shadow_methods.hpp"

namespace nearcap::render {

// The kind of a recorded draw (never Lit: the lit pass is no recorded draw).
gl::PassKind draw_kind(const gl::DrawCall& d);

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
