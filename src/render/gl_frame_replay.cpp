// An emulated frame's draw calls on a real OpenGL (see gl_frame_replay.hpp).
#include "nearcap/render/gl_frame_replay.hpp"

#include <epoxy/gl.h>

#include <chrono>
#include <string>

#include "draw_state.hpp"
#include "gl_objects.hpp"
#include "nearcap/error.hpp"

namespace nearcap::render {
namespace {

const char* const kFragmentShader = R"(#version 450 core
uniform int object_id;
layout(location = 0) out int object;
void main() { object = object_id; }
)";

}  // namespace

GlFrameReplay::GlFrameReplay(int width, int height, gl::DepthFormat depth) : width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw Error(ErrorKind::Usage,
                "frame size " + std::to_string(width) + "x" + std::to_string(height) + " is not 1 to 16384 pixels");
  far_only_clamp_ = epoxy_has_gl_extension("GL_AMD_depth_clamp_separate");
  // The colour attachment holds each pixel's object id.
  target_ = make_offscreen_target(width, height, GL_R32I, depth_stencil_format(depth == gl::DepthFormat::Fixed24),
                                  "the replay");
  glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);

  programs_ = std::make_unique<ShadowPrograms>(kFragmentShader, "the replay's program");
  check_gl("creating the replay");
}

GlFrameReplay::~GlFrameReplay() = default;

ReplayedFrame GlFrameReplay::replay(const std::vector<gl::DrawCall>& draws, float volume_depth_offset,
                                    VertexStage stage) {
  const bool depth_bounds_test = has_depth_bounds_test();
  check_depth_bounds(draws, depth_bounds_test);
  const auto t0 = std::chrono::steady_clock::now();
  glBindFramebuffer(GL_FRAMEBUFFER, target_.framebuffer.get());
  glViewport(0, 0, width_, height_);
  glDisable(GL_MULTISAMPLE);
  disable_volume_culling(depth_bounds_test);
  glFrontFace(GL_CCW);
  glDepthMask(GL_TRUE);
  glStencilMask(0xFF);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClearDepth(cleared_depth(draws));
  const GLint stencil_clear = cleared_stencil(draws);
  glClearStencil(stencil_clear);
  glClear(GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  const GLint no_object[4] = {-1, -1, -1, -1};
  glClearBufferiv(GL_COLOR, 0, no_object);
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_ALWAYS, 0, 0xFF);
  glBindVertexArray(target_.vertex_array.get());
  glBindBuffer(GL_ARRAY_BUFFER, target_.vertices.get());

  ReplayedFrame out;
  out.width = width_;
  out.height = height_;
  const std::size_t n = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  for (std::size_t k = 0; k < draws.size(); ++k) {
    const gl::DrawCall& d = draws[k];
    const gl::DrawState& s = d.state;
    apply_draw_state(s, far_only_clamp_, depth_bounds_test);
    if (volume_depth_offset != 0 && d.pass == gl::DrawPass::Volume) {
      glEnable(GL_POLYGON_OFFSET_FILL);
      glPolygonOffset(0.0f, volume_depth_offset);
    } else {
      glDisable(GL_POLYGON_OFFSET_FILL);
    }
    const ShadowProgramUse use = programs_->use(d, stage, clamps_by_clip_distance(s, far_only_clamp_));
    glUniform1i(glGetUniformLocation(use.program, "object_id"), s.object_id);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(use.count * sizeof(gl::Vec4f)), use.vertices, GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(use.count));
    const bool cap_ends =
        d.pass == gl::DrawPass::NearCap && (k + 1 == draws.size() || draws[k + 1].pass != gl::DrawPass::NearCap);
    if (cap_ends) {
      out.near_cap.resize(n);
      glReadPixels(0, 0, width_, height_, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, out.near_cap.data());
      // The near-cap pass alone, as the emulation records it: a frame that
      // mixes ZP+ and AtomicZP cleared the stencil to the eye count first.
      for (std::uint8_t& v : out.near_cap) v = static_cast<std::uint8_t>(v - stencil_clear);
    }
  }
  disable_volume_culling(depth_bounds_test);
  glFinish();
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  out.stencil.resize(n);
  glReadPixels(0, 0, width_, height_, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, out.stencil.data());
  out.object.resize(n);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, width_, height_, GL_RED_INTEGER, GL_INT, out.object.data());
  disable_depth_clamps(far_only_clamp_);
  glDisable(GL_POLYGON_OFFSET_FILL);
  apply_depth_mapping(gl::DepthMapping::Standard);
  check_gl("replaying a frame");
  return out;
}

ReplayComparison compare(const ReplayedFrame& real, const gl::ShadowFrame& emulated) {
  if (real.width != emulated.width || real.height != emulated.height)
    throw Error(ErrorKind::Usage, "a replayed frame and an emulated one of different sizes");
  ReplayComparison c;
  for (std::size_t p = 0; p < real.stencil.size(); ++p) {
    if (real.stencil[p] != emulated.stencil[p]) c.stencil_pixels.push_back(p);
    c.object += real.object[p] != emulated.object[p];
  }
  c.stencil = c.stencil_pixels.size();
  if (!real.near_cap.empty() && real.near_cap.size() == emulated.near_cap.size())
    for (std::size_t p = 0; p < real.near_cap.size(); ++p) c.near_cap += real.near_cap[p] != emulated.near_cap[p];
  return c;
}

}  // namespace nearcap::render
