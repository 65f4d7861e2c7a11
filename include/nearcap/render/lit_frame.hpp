// nearcap/render/lit_frame.hpp — the lit frame with its shadows, drawn by a
// real OpenGL as a shadow-volume renderer draws it, from the emulation's own
// draw calls (render/gl_frame_replay.hpp):
// Each draw's clip-space vertices are computed by the GL's own GLSL vertex
// programs from the draw's object-space inputs and uniforms (LitFrameOptions::
// vertex_stage), or uploaded as the emulation computed them.
//   1. the depth pre-pass, writing depth and the ambient colour;
//   2. per light: the stencil cleared (AtomicZP: set to the eye count by
//      its GPU pass, render/eye_count_pass.hpp), that light's near-cap and volume
//      draws (its ShadowFrame::draws, recorded), then every object again
//      with its diffuse colour for the light, depth test GL_EQUAL (the same
//      clip-space vertices, so the same depths), stencil test EQUAL 0, added
//      to the colour (glBlendFunc(GL_ONE, GL_ONE)).
// Colours are flat per triangle: albedo times (ambient, or the Lambert term
// towards the light from the triangle's centroid, divided by the number of
// lights); occluders grey, receivers a warm brown.  The Lambert term is
// two-sided like the exact reference's shadow.png (judge/reference_images.hpp):
// the camera-space face normal turned towards the eye, so a surface is lit on
// the side the camera sees, whatever its winding, and unlit exactly where
// the eye and the light lie on opposite sides of its plane.  A pixel is lit
// by a light when its stencil for that light is 0 and that term is positive,
// as the reference's pixel is lit when its exact stencil is 0 and its term
// positive.  Needs a current context (EglContext).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/render/glsl_shadow_programs.hpp"
#include "nearcap/render/pass_kinds.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::render {

// How to draw and time it.
struct LitFrameOptions {
  // Each light's stencil read back (LitFrame::stencils), outside the timing.
  bool read_stencils = false;
  // glFinish after each pass and its wall time in LitFrame::passes (the
  // extra synchronisation is in LitFrame::ms too).
  bool pass_times = false;
  // Each pass kind timed on its own (pass_kinds.hpp; implies pass_times):
  // the depth pre-pass, then per light its stencil pass drawn kind by kind
  // (the near-cap, the sides with corrective quads, the light caps, the
  // dark caps: each kind's draws together, in their recorded order, a
  // glFinish before and after), then its lit pass.  The stencil is the
  // same as in the recorded order: every stencil operation is a wrapping
  // increment or decrement, and those commute.  The times in
  // LitFrame::kind_times.
  bool pass_kind_times = false;
  // Each draw that counts front and back faces differently as two one-sided
  // draws (back faces culled with the front operations, then front faces
  // culled with the back ones), as GL without two-sided stencil draws it:
  // the same stencil, twice the vertex work (the paper's speed argument
  // assumes two-sided stencil).
  bool one_sided_stencil = false;
  // Where each draw's clip-space vertices come from: the GL's GLSL programs
  // on the object-space vertices (the default, as a renderer builds its
  // volumes), or the emulation's recorded results (render/glsl_shadow_programs.hpp).
  VertexStage vertex_stage = VertexStage::Glsl;
  // The sides as triangle strips along the silhouette's chains
  // (gl::side_strip_indices, built before the clock starts, as a renderer
  // builds them with its silhouettes): the paper's layout for ZP+'s sides,
  // the same triangles; caps, corrective quads and the mesh stay
  // independent triangles.
  bool side_strips = false;
};

// Wall time per pass (with LitFrameOptions::pass_times), and the GL's timer
// queries around the same passes: the depth pre-pass
// with the ambient term, every light's stencil pass (near-cap and volumes),
// every light's additive diffuse pass.
struct LitFramePasses {
  double depth_ms = 0, stencil_ms = 0, lit_ms = 0;
  // The same passes by GL_TIME_ELAPSED queries: a GPU's own time; llvmpipe's
  // queries do not measure its rasterization (far below the wall clock).
  double gpu_depth_ms = 0, gpu_stencil_ms = 0, gpu_lit_ms = 0;
  // AtomicZP's eye-count pass (render/eye_count_pass.hpp: the count and its
  // write into the stencil, a glFinish after), wall time, every light; a
  // part of stencil_ms.
  double eye_count_ms = 0;
};

// One pass kind of one light frame, timed on its own
// (LitFrameOptions::pass_kind_times): wall time from the glFinish before its
// first draw to the glFinish after its last.
struct KindTime {
  std::size_t light_frame = 0;  // index into the light frames (0 for the depth pre-pass)
  gl::PassKind kind = gl::PassKind::Depth;
  double ms = 0;
  double gpu_ms = 0;  // the GL_TIME_ELAPSED query around the same draws
};

struct LitFrame {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // 8-bit RGB, top row first (as a PNG stores it)
  double ms = 0;                  // every pass and glFinish (wall clock), reading the stencils back excluded
  // The uploads' share of `ms`: the wall time of the glBufferData calls
  // (each draw's vertices, colours and strip indices), CPU work on a driver
  // that copies at the call as llvmpipe does.
  double upload_ms = 0;
  LitFramePasses passes;  // with LitFrameOptions::pass_times
  // With pass_kind_times: the depth pre-pass, then per light frame each kind
  // it draws (a kind with no draw has no entry), then its lit pass.
  std::vector<KindTime> kind_times;
  // With pass_times (or pass_kind_times): per light frame its eye-count
  // pass's wall time (LitFramePasses::eye_count_ms's share; 0 for a frame
  // without AtomicZP occluders).
  std::vector<double> eye_count_ms;
  // With read_stencils: each light's stencil as its volumes left it (row 0
  // at the bottom, like ShadowFrame::stencil), one per light frame.
  std::vector<std::vector<std::uint8_t>> stencils;
  // With read_stencils: each light frame's eye count as the GL's pass
  // counted it (AtomicZP frames; nullopt for the others), read back after
  // its stencil pass.
  std::vector<std::optional<std::size_t>> eye_counts;
};

// Draws lit frames in the current context, keeping its GLSL programs
// between frames (as a renderer links its programs once: a program's first
// draw on llvmpipe compiles its machine code, which no frame should pay).
class EyeCountPass;

class LitFrameRenderer {
 public:
  LitFrameRenderer();
  ~LitFrameRenderer();
  LitFrameRenderer(const LitFrameRenderer&) = delete;
  LitFrameRenderer& operator=(const LitFrameRenderer&) = delete;

  // `light_frames[k]`: the frame of scene light k with one method, recorded
  // (EmulationSettings::record_draws), all with the same projection (one
  // method and settings for every light).  Throws Error(Gl) as GlFrameReplay.
  LitFrame render(const Scene& scene, const std::vector<gl::ShadowFrame>& light_frames, gl::DepthFormat depth,
                  const LitFrameOptions& options);

 private:
  std::unique_ptr<ShadowPrograms> programs_;
  std::unique_ptr<EyeCountPass> eye_pass_;  // made for the first AtomicZP frame
};

// One frame with a renderer of its own (its programs compiled for it).
LitFrame render_lit_frame(const Scene& scene, const std::vector<gl::ShadowFrame>& light_frames, gl::DepthFormat depth,
                          const LitFrameOptions& options);
inline LitFrame render_lit_frame(const Scene& scene, const std::vector<gl::ShadowFrame>& light_frames,
                                 gl::DepthFormat depth, bool read_stencils = false) {
  LitFrameOptions o;
  o.read_stencils = read_stencils;
  return render_lit_frame(scene, light_frames, depth, o);
}

}  // namespace nearcap::render
