// nearcap/render/gl_frame_replay.hpp — an emulated frame's draw calls run by a
// real OpenGL: what the GPU's stencil buffer holds for the same inputs.
//
// The emulation (gl/shadow_methods.hpp, with EmulationSettings::record_draws)
// keeps each draw call's clip-space vertices, float32 as its vertex program
// computed them, the program's object-space inputs and uniforms, and its
// state.  GlFrameReplay uploads those vertices unchanged (VertexStage::
// Recorded: a pass-through vertex shader, gl_Position is the recorded vec4)
// or has the GL's own GLSL programs compute them from the inputs
// (VertexStage::Glsl, render/glsl_shadow_programs.hpp), and sets the same
// state, so that clipping, rasterization, the depth test and the stencil
// operations are the driver's own:
//   framebuffer   GL_DEPTH24_STENCIL8 (GL_DEPTH32F_STENCIL8 for the float32
//                 depth format) and an R32I object-id attachment, cleared to
//                 depth 1, stencil 0, object -1; viewport the whole frame;
//   depth         DepthFunc::Less -> GL_LESS, Always -> the depth test off;
//                 glDepthMask from depth_write; GL_DEPTH_CLAMP when both
//                 near and far clamp; one side only (far-only clamp, the
//                 near-clamp l_near rule's cap) through
//                 GL_AMD_depth_clamp_separate where the driver has it, else
//                 GL_DEPTH_CLAMP with the plane that still clips as
//                 gl_ClipDistance[0] (the vertex program writes z + w, w - z
//                 or z; the llvmpipe model's clipper clips it as Mesa does a
//                 user plane: gl::ClipSettings::depth_plane_as_clip_distance);
//                 vertices_on_near_plane (the clipped-sides near cap) ->
//                 GL_DEPTH_CLAMP, so the driver does not cut it again at the
//                 near plane its vertices lie on only to within rounding;
//   stencil       test always passing, two-sided ops (glStencilOpSeparate),
//                 GL_INCR_WRAP / GL_DECR_WRAP;
//   culling       front faces counter-clockwise, glCullFace as recorded;
//   object ids    written with the depth (colour writes on only when
//                 depth_write).
// A far plane at infinity (DrawState::clip_far false) needs no state: its
// clip-space z equals w at infinity, which GL's far clipping keeps.  The
// rasterizer's sub-pixel precision, fill rule and guard band are the
// driver's; the emulation's defaults are llvmpipe's (gl/rasterizer.hpp).
// Needs a current context (EglContext).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/render/gl_handle.hpp"
#include "nearcap/render/glsl_shadow_programs.hpp"

namespace nearcap::render {

struct ReplayedFrame {
  int width = 0, height = 0;
  std::vector<std::uint8_t> stencil;   // row 0 at the bottom
  std::vector<std::int32_t> object;    // -1 where nothing was drawn
  std::vector<std::uint8_t> near_cap;  // the stencil after the near-cap pass (empty without one)
  double ms = 0;                       // uploads, draws and glFinish (wall clock)
};

class GlFrameReplay {
 public:
  GlFrameReplay(int width, int height, gl::DepthFormat depth);
  ~GlFrameReplay();
  GlFrameReplay(const GlFrameReplay&) = delete;
  GlFrameReplay& operator=(const GlFrameReplay&) = delete;

  // Runs `draws` (ShadowFrame::draws) from cleared buffers and reads back.
  // `volume_depth_offset`: a polygon offset (glPolygonOffset(0, units), in
  // units of the depth buffer's resolution) on the volume pass's fragments,
  // a probe for depth ties: 0 replays the frame as recorded.  `stage`: the
  // recorded clip-space vertices, or the GLSL programs run on the GL.
  ReplayedFrame replay(const std::vector<gl::DrawCall>& draws, float volume_depth_offset = 0,
                       VertexStage stage = VertexStage::Recorded);

  // True when the driver has GL_AMD_depth_clamp_separate (one-sided depth
  // clamp in fixed function; without it, GL_DEPTH_CLAMP and a clip distance).
  bool has_far_only_clamp() const { return far_only_clamp_; }

 private:
  int width_, height_;
  bool far_only_clamp_ = false;
  OffscreenTarget target_;  // colour: each pixel's object id (GL_R32I)
  std::unique_ptr<ShadowPrograms> programs_;
};

// Where a replayed frame and the emulated one differ.
struct ReplayComparison {
  std::size_t stencil = 0;                  // pixels whose stencil values differ
  std::vector<std::size_t> stencil_pixels;  // which (index j * width + i)
  std::size_t object = 0;                   // pixels that see different objects
  std::size_t near_cap = 0;                 // pixels whose near-cap pass differs (ZP+ methods)
};
ReplayComparison compare(const ReplayedFrame& gl, const gl::ShadowFrame& emulated);

}  // namespace nearcap::render
