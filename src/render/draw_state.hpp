// An emulated draw call's state set on the real GL (gl/pipeline.hpp's
// DrawState; render/gl_frame_replay.hpp says how each field maps).  Private
// to src/render/.  Needs a current context.
#pragma once

#include <epoxy/gl.h>

#include <algorithm>
#include <string>
#include <vector>

#include "nearcap/error.hpp"
#include "nearcap/gl/pipeline.hpp"

namespace nearcap::render {

// The depth a frame's depth buffer is cleared to: 0 when its depth pre-pass
// draws with the reversed mapping (near at 1), else 1.
// The value a frame's stencil buffer is cleared to: its AtomicZP volume
// draws' stencil_clear (the eye count, the same on each), else 0.  In a
// frame that mixes methods the other volume draws carry 0: the first
// non-zero one is the frame's.
inline GLint cleared_stencil(const std::vector<gl::DrawCall>& draws) {
  for (const gl::DrawCall& d : draws)
    if (d.pass == gl::DrawPass::Volume && d.state.stencil_clear != 0) return d.state.stencil_clear;
  return 0;
}
inline double cleared_depth(const std::vector<gl::DrawCall>& draws) {
  for (const gl::DrawCall& d : draws)
    if (d.pass == gl::DrawPass::Depth) return d.state.depth_mapping == gl::DepthMapping::Reversed ? 0.0 : 1.0;
  return 1.0;
}

// Does `s` clamp one depth side through GL_DEPTH_CLAMP with the other plane
// as gl_ClipDistance[0] (the driver lacks GL_AMD_depth_clamp_separate,
// `far_only_clamp` false)?  Its program then writes the distance
// (ShadowPrograms::use's clip_distance).
inline bool clamps_by_clip_distance(const gl::DrawState& s, bool far_only_clamp) {
  return !far_only_clamp && gl::one_sided_depth_clamp(s);
}

// No depth clamp of any kind (GL_DEPTH_CLAMP, the user clip plane that
// stands in for a one-sided clamp, and the separate AMD ones where the
// driver has them).
inline void disable_depth_clamps(bool far_only_clamp) {
  glDisable(GL_DEPTH_CLAMP);
  glDisable(GL_CLIP_DISTANCE0);
  if (far_only_clamp) {
    glDisable(GL_DEPTH_CLAMP_FAR_AMD);
    glDisable(GL_DEPTH_CLAMP_NEAR_AMD);
  }
}

// glClipControl for a depth mapping (GL 4.5): the reversed mapping's
// GL_ZERO_TO_ONE, or GL's default.
inline void apply_depth_mapping(gl::DepthMapping m) {
  glClipControl(GL_LOWER_LEFT, m == gl::DepthMapping::Reversed ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
}

inline GLenum stencil_op(gl::StencilOp op) {
  switch (op) {
    case gl::StencilOp::IncrementWrap:
      return GL_INCR_WRAP;
    case gl::StencilOp::DecrementWrap:
      return GL_DECR_WRAP;
    case gl::StencilOp::Keep:
      break;
  }
  return GL_KEEP;
}

// Volume culling (gl/volume_bounds.hpp): the scissor test, and the depth
// bounds test where the driver has GL_EXT_depth_bounds_test
// (`depth_bounds_test`; a frame that needs it is refused before, by
// check_depth_bounds).
inline void apply_volume_culling(const gl::DrawState& s, bool depth_bounds_test) {
  if (s.scissor) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(s.scissor->x0, s.scissor->y0, std::max(0, s.scissor->x1 - s.scissor->x0),
              std::max(0, s.scissor->y1 - s.scissor->y0));
  } else {
    glDisable(GL_SCISSOR_TEST);
  }
  if (!depth_bounds_test) return;
  if (s.depth_bounds) {
    glEnable(GL_DEPTH_BOUNDS_TEST_EXT);
    glDepthBoundsEXT((*s.depth_bounds)[0], (*s.depth_bounds)[1]);
  } else {
    glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
  }
}

inline void disable_volume_culling(bool depth_bounds_test) {
  glDisable(GL_SCISSOR_TEST);
  if (depth_bounds_test) glDisable(GL_DEPTH_BOUNDS_TEST_EXT);
}

// Does the current context's driver have GL_EXT_depth_bounds_test?
inline bool has_depth_bounds_test() { return epoxy_has_gl_extension("GL_EXT_depth_bounds_test"); }

// Throws Error(Gl) when a draw culls by depth bounds and the driver lacks them.
inline void check_depth_bounds(const std::vector<gl::DrawCall>& draws, bool depth_bounds_test) {
  if (depth_bounds_test) return;
  for (const gl::DrawCall& d : draws)
    if (d.state.depth_bounds)
      throw Error(ErrorKind::Gl, std::string("--volume-culling depth-bounds (or both) needs GL_EXT_depth_bounds_test; "
                                             "the driver (") +
                                     reinterpret_cast<const char*>(glGetString(GL_RENDERER)) +
                                     ") lacks it: use --volume-culling scissor");
}

// Culling, the clip control (the depth mapping), the depth test and writes,
// depth clamp (one side only through GL_AMD_depth_clamp_separate when
// `far_only_clamp`, else through GL_DEPTH_CLAMP with the other plane clipped
// as gl_ClipDistance[0]), the two-sided stencil operations, volume culling;
// colour writes follow depth writes (the object ids are written with the
// depth).
inline void apply_draw_state(const gl::DrawState& s, bool far_only_clamp, bool depth_bounds_test) {
  apply_volume_culling(s, depth_bounds_test);
  if (s.cull == gl::CullFace::None) {
    glDisable(GL_CULL_FACE);
  } else {
    glEnable(GL_CULL_FACE);
    glCullFace(s.cull == gl::CullFace::Back ? GL_BACK : GL_FRONT);
  }
  if (s.depth_func == gl::DepthFunc::Always) {
    glDisable(GL_DEPTH_TEST);
  } else {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(s.depth_func == gl::DepthFunc::Greater ? GL_GREATER : GL_LESS);
  }
  apply_depth_mapping(s.depth_mapping);
  glDepthMask(s.depth_write ? GL_TRUE : GL_FALSE);
  glColorMaski(0, s.depth_write, s.depth_write, s.depth_write, s.depth_write);
  if (clamps_by_clip_distance(s, far_only_clamp))
    glEnable(GL_CLIP_DISTANCE0);
  else
    glDisable(GL_CLIP_DISTANCE0);
  if ((s.depth_clamp_near && s.depth_clamp_far) || s.vertices_on_near_plane || s.vertices_on_far_plane ||
      clamps_by_clip_distance(s, far_only_clamp)) {
    glEnable(GL_DEPTH_CLAMP);
  } else {
    glDisable(GL_DEPTH_CLAMP);
    if (far_only_clamp) {
      // GL_DEPTH_CLAMP_NEAR_AMD and _FAR_AMD name the planes of depth 0 and
      // 1; with the reversed mapping the camera's far plane is depth 0.
      const bool reversed = s.depth_mapping == gl::DepthMapping::Reversed;
      const bool clamp_depth_one = reversed ? s.depth_clamp_near : s.depth_clamp_far;
      const bool clamp_depth_zero = reversed ? s.depth_clamp_far : s.depth_clamp_near;
      if (clamp_depth_one)
        glEnable(GL_DEPTH_CLAMP_FAR_AMD);
      else
        glDisable(GL_DEPTH_CLAMP_FAR_AMD);
      if (clamp_depth_zero)
        glEnable(GL_DEPTH_CLAMP_NEAR_AMD);
      else
        glDisable(GL_DEPTH_CLAMP_NEAR_AMD);
    }
  }
  glStencilOpSeparate(GL_FRONT, GL_KEEP, stencil_op(s.front.depth_fail), stencil_op(s.front.depth_pass));
  glStencilOpSeparate(GL_BACK, GL_KEEP, stencil_op(s.back.depth_fail), stencil_op(s.back.depth_pass));
}

}  // namespace nearcap::render
