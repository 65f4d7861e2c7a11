// The lit frame on a real GL (see lit_frame.hpp).
#include "nearcap/render/lit_frame.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include "draw_state.hpp"
#include "gl_objects.hpp"
#include "nearcap/error.hpp"
#include "nearcap/gl/shadow_volume_geometry.hpp"
#include "nearcap/render/eye_count_pass.hpp"
#include "nearcap/render/glsl_shadow_programs.hpp"

namespace nearcap::render {
namespace {

const char* const kFragmentShader = R"(#version 450 core
in vec3 colour_v;
layout(location = 0) out vec4 colour;
void main() { colour = vec4(colour_v, 1.0); }
)";

constexpr float kAmbient = 0.2f;

// Per vertex of object o's depth draw (3 per triangle, mesh order): its
// triangle's colour, ambient when `light` is null, else the diffuse term.
// The diffuse term is two-sided, by the exact reference's rule (shadow.png,
// judge/reference_images.cpp): in camera space, the face normal is turned
// towards the eye (the origin) and the Lambert term is that normal's cosine
// with the direction to the light, clamped at 0.  A receiver is lit on
// whichever side the camera sees, so a room seen from inside or a floor
// whose triangles face down is lit where the light reaches it, and a face is
// dark exactly when the eye and the light lie on opposite sides of its
// plane, whatever the mesh's winding.  The sign is the same at every point of
// the triangle, so the centroid's light direction decides as the reference's
// per-pixel one does.
std::vector<float> colours(const Scene& scene, std::size_t o, const Vec3d* light, std::size_t lights) {
  const SceneObject& obj = scene.objects[o];
  const float albedo[3] = {obj.occluder ? 0.75f : 0.80f, obj.occluder ? 0.75f : 0.55f, obj.occluder ? 0.78f : 0.35f};
  std::vector<float> out;
  out.reserve(9 * obj.mesh->triangles.size());
  const Affine3d& view = scene.camera.view;
  const Vec3d light_camera = light ? view.apply(*light) : Vec3d{0, 0, 0};
  for (const auto& t : obj.mesh->triangles) {
    float k = kAmbient;
    if (light) {
      auto camera_vertex = [&](VertexIndex v) { return view.apply(obj.object_to_world.apply(obj.mesh->positions[v])); };
      const Vec3d a = camera_vertex(t[0]), b = camera_vertex(t[1]), c = camera_vertex(t[2]);
      Vec3d n = cross(b - a, c - a);
      if (dot(n, a) > 0) n = Vec3d{-n.x, -n.y, -n.z};  // the side the eye sees
      const Vec3d centroid = (1.0 / 3.0) * (a + b + c), to_light = light_camera - centroid;
      const double nl = std::sqrt(dot(n, n) * dot(to_light, to_light));
      k = nl > 0 ? static_cast<float>(std::max(0.0, dot(n, to_light) / nl) * (1.0 - kAmbient) /
                                      static_cast<double>(lights))
                 : 0.0f;
    }
    for (int v = 0; v < 3; ++v)
      for (float x : albedo) out.push_back(x * k);
  }
  return out;
}

}  // namespace

LitFrameRenderer::LitFrameRenderer()
    : programs_(std::make_unique<ShadowPrograms>(kFragmentShader, "the lit frame's program")) {}

LitFrameRenderer::~LitFrameRenderer() = default;

LitFrame render_lit_frame(const Scene& scene, const std::vector<gl::ShadowFrame>& light_frames, gl::DepthFormat depth,
                          const LitFrameOptions& options) {
  LitFrameRenderer renderer;
  return renderer.render(scene, light_frames, depth, options);
}

LitFrame LitFrameRenderer::render(const Scene& scene, const std::vector<gl::ShadowFrame>& light_frames,
                                  gl::DepthFormat depth, const LitFrameOptions& options) {
  ShadowPrograms& programs = *programs_;
  const bool read_stencils = options.read_stencils;
  if (light_frames.empty()) throw Error(ErrorKind::Usage, "a lit frame needs at least one light's shadow frame");
  const int width = scene.camera.width, height = scene.camera.height;
  const bool far_only_clamp = epoxy_has_gl_extension("GL_AMD_depth_clamp_separate");
  for (const gl::ShadowFrame& f : light_frames)
    if (f.draws.empty()) throw Error(ErrorKind::Usage, "a lit frame needs recorded draws (record_draws)");
  const bool depth_bounds_test = has_depth_bounds_test();
  for (const gl::ShadowFrame& f : light_frames) check_depth_bounds(f.draws, depth_bounds_test);
  LitFrame out;
  double read_ms = 0;  // reading the stencils back, left out of the frame's time
  const OffscreenTarget offscreen = make_offscreen_target(
      width, height, GL_RGBA8, depth_stencil_format(depth == gl::DepthFormat::Fixed24), "the lit frame");
  const GlBuffer colours_buffer = new_buffer(), strip_buffer = new_buffer();  // attribute 1; strip indices
  // Every program the frame needs, linked before the clock starts.
  // With side_strips, each sides draw's strip indices, built before it too.
  std::map<const gl::DrawCall*, std::vector<std::uint32_t>> strips;
  // AtomicZP's eye-count pass: each light frame's inputs (the counted
  // occluders' float32 vertices and uniforms), built before it too.
  std::vector<std::optional<EyeCountInputs>> eye_inputs(light_frames.size());
  for (std::size_t k = 0; k < light_frames.size(); ++k) {
    const gl::ShadowFrame& f = light_frames[k];
    if (!f.eye_count) continue;
    if (!eye_pass_) eye_pass_ = std::make_unique<EyeCountPass>();
    eye_inputs[k] = eye_count_inputs(scene, f.light, eye_counted_objects(f), recorded_arithmetic(f));
  }
  for (const gl::ShadowFrame& f : light_frames)
    for (const gl::DrawCall& d : f.draws) {
      programs.prepare(d, options.vertex_stage, clamps_by_clip_distance(d.state, far_only_clamp));
      if (options.side_strips && d.vertex_stage && d.vertex_stage->part == gl::GeometryPart::Sides)
        strips[&d] = gl::side_strip_indices(d.vertex_stage->inputs);
    }
  const auto t0 = std::chrono::steady_clock::now();
  gl::StencilOps second_ops;  // the back faces' operations, for a one-sided stencil's second draw
  // With pass_times: a GL_TIME_ELAPSED query around each pass (pass_begin,
  // pass_done), then glFinish, and the wall time since the last mark and the
  // query's time added to `into` and `gpu_into`.
  auto mark = std::chrono::steady_clock::now();
  const bool pass_times = options.pass_times || options.pass_kind_times;
  if (pass_times) out.eye_count_ms.assign(light_frames.size(), 0.0);
  const GlQuery timer = pass_times ? new_query() : GlQuery();
  auto pass_begin = [&] {
    if (pass_times) glBeginQuery(GL_TIME_ELAPSED, timer.get());
  };
  auto pass_done = [&](double& into, double& gpu_into) {
    if (!pass_times) return;
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    const auto now = std::chrono::steady_clock::now();
    into += std::chrono::duration<double, std::milli>(now - mark).count();
    mark = now;
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timer.get(), GL_QUERY_RESULT, &ns);
    gpu_into += static_cast<double>(ns) * 1e-6;
  };
  auto draw = [&](const gl::DrawCall& d, const std::vector<float>& rgb, int times = 1) {
    const ShadowProgramUse use =
        programs.use(d, options.vertex_stage, clamps_by_clip_distance(d.state, far_only_clamp));
    auto upload = [&](GLenum target, std::size_t bytes, const void* data) {
      const auto u0 = std::chrono::steady_clock::now();
      glBufferData(target, static_cast<GLsizeiptr>(bytes), data, GL_STREAM_DRAW);
      out.upload_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - u0).count();
    };
    glBindBuffer(GL_ARRAY_BUFFER, offscreen.vertices.get());
    upload(GL_ARRAY_BUFFER, use.count * sizeof(gl::Vec4f), use.vertices);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(0);
    if (rgb.empty()) {
      glDisableVertexAttribArray(1);
      glVertexAttrib3f(1, 0, 0, 0);
    } else {
      glBindBuffer(GL_ARRAY_BUFFER, colours_buffer.get());
      upload(GL_ARRAY_BUFFER, rgb.size() * sizeof(float), rgb.data());
      glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
      glEnableVertexAttribArray(1);
    }
    const auto strip = strips.find(&d);
    auto submit = [&] {
      if (strip == strips.end()) {
        glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(use.count));
      } else {
        glDrawElements(GL_TRIANGLE_STRIP, static_cast<GLsizei>(strip->second.size()), GL_UNSIGNED_INT, nullptr);
      }
    };
    if (strip != strips.end()) {
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, strip_buffer.get());
      upload(GL_ELEMENT_ARRAY_BUFFER, strip->second.size() * sizeof(std::uint32_t), strip->second.data());
    }
    submit();
    for (int k = 1; k < times; ++k) {
      // The one-sided stencil's second draw: the other facing, the other operations.
      glCullFace(GL_FRONT);
      glStencilOpSeparate(GL_FRONT_AND_BACK, GL_KEEP, stencil_op(second_ops.depth_fail),
                          stencil_op(second_ops.depth_pass));
      submit();
    }
  };

  pass_begin();
  glViewport(0, 0, width, height);
  glEnable(GL_PRIMITIVE_RESTART_FIXED_INDEX);  // gl::kStripRestart ends a strip
  glDisable(GL_MULTISAMPLE);
  glDisable(GL_BLEND);
  glFrontFace(GL_CCW);
  glDepthMask(GL_TRUE);
  glStencilMask(0xFF);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClearColor(0.05f, 0.06f, 0.09f, 1.0f);
  glClearDepth(cleared_depth(light_frames.front().draws));
  glClearStencil(0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_ALWAYS, 0, 0xFF);
  // 1. The depth pre-pass with the ambient colour.
  std::vector<const gl::DrawCall*> depth_draws;
  for (const gl::DrawCall& d : light_frames.front().draws)
    if (d.pass == gl::DrawPass::Depth) depth_draws.push_back(&d);
  for (const gl::DrawCall* d : depth_draws) {
    apply_draw_state(d->state, far_only_clamp, depth_bounds_test);
    draw(*d, colours(scene, static_cast<std::size_t>(d->state.object_id), nullptr, 1));
  }
  pass_done(out.passes.depth_ms, out.passes.gpu_depth_ms);
  if (options.pass_kind_times)
    out.kind_times.push_back({0, gl::PassKind::Depth, out.passes.depth_ms, out.passes.gpu_depth_ms});
  // 2. Per light: its stencil, then its diffuse light where the stencil is 0.
  for (std::size_t k = 0; k < light_frames.size(); ++k) {
    pass_begin();
    disable_volume_culling(depth_bounds_test);  // glClear honours the scissor
    if (eye_inputs[k]) {
      // AtomicZP: the eye count on the GPU, written into the stencil there
      // (render/eye_count_pass.hpp), where the emulation clears to its count.
      const auto e0 = std::chrono::steady_clock::now();
      eye_pass_->run(*eye_inputs[k], &out.upload_ms);
      eye_pass_->write_stencil();
      if (pass_times) {
        glFinish();
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - e0).count();
        out.passes.eye_count_ms += ms;
        out.eye_count_ms[k] = ms;
      }
    } else {
      glClearStencil(cleared_stencil(light_frames[k].draws));
      glClear(GL_STENCIL_BUFFER_BIT);
    }
    glStencilFunc(GL_ALWAYS, 0, 0xFF);
    glDisable(GL_BLEND);
    auto draw_stencil = [&](const gl::DrawCall& d) {
      apply_draw_state(d.state, far_only_clamp, depth_bounds_test);
      const bool two_sided =
          d.state.cull == gl::CullFace::None &&
          (d.state.front.depth_fail != d.state.back.depth_fail || d.state.front.depth_pass != d.state.back.depth_pass);
      if (!options.one_sided_stencil || !two_sided) {
        draw(d, {});
        return;
      }
      // Front faces (back culled) with the front operations, then back faces.
      glEnable(GL_CULL_FACE);
      glCullFace(GL_BACK);
      glStencilOpSeparate(GL_FRONT_AND_BACK, GL_KEEP, stencil_op(d.state.front.depth_fail),
                          stencil_op(d.state.front.depth_pass));
      second_ops = d.state.back;
      draw(d, {}, 2);
    };
    if (!options.pass_kind_times) {
      for (const gl::DrawCall& d : light_frames[k].draws)
        if (d.pass != gl::DrawPass::Depth) draw_stencil(d);
      pass_done(out.passes.stencil_ms, out.passes.gpu_stencil_ms);
    } else {
      pass_done(out.passes.stencil_ms, out.passes.gpu_stencil_ms);  // the stencil's clear
      for (const gl::PassKind kind :
           {gl::PassKind::NearCap, gl::PassKind::Sides, gl::PassKind::LightCap, gl::PassKind::DarkCap}) {
        bool drawn = false;
        pass_begin();
        for (const gl::DrawCall& d : light_frames[k].draws)
          if (d.pass != gl::DrawPass::Depth && draw_kind(d) == kind) {
            draw_stencil(d);
            drawn = true;
          }
        KindTime t{k, kind, 0, 0};
        pass_done(t.ms, t.gpu_ms);
        out.passes.stencil_ms += t.ms;
        out.passes.gpu_stencil_ms += t.gpu_ms;
        if (drawn) out.kind_times.push_back(t);
      }
    }
    if (read_stencils) {
      const auto r0 = std::chrono::steady_clock::now();
      std::vector<std::uint8_t>& st = out.stencils.emplace_back(static_cast<std::size_t>(width) * height);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadPixels(0, 0, width, height, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, st.data());
      out.eye_counts.push_back(eye_inputs[k] ? std::optional<std::size_t>(eye_pass_->read_count()) : std::nullopt);
      read_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0).count();
      mark = std::chrono::steady_clock::now();  // the read is no pass
    }
    pass_begin();
    disable_depth_clamps(far_only_clamp);
    disable_volume_culling(depth_bounds_test);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_EQUAL);
    if (!depth_draws.empty()) apply_depth_mapping(depth_draws.front()->state.depth_mapping);
    glDepthMask(GL_FALSE);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glStencilFunc(GL_EQUAL, 0, 0xFF);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    const Vec3d& light = scene.lights[light_frames[k].light].position;
    for (const gl::DrawCall* d : depth_draws)
      draw(*d, colours(scene, static_cast<std::size_t>(d->state.object_id), &light, light_frames.size()));
    KindTime lit{k, gl::PassKind::Lit, 0, 0};
    pass_done(lit.ms, lit.gpu_ms);
    out.passes.lit_ms += lit.ms;
    out.passes.gpu_lit_ms += lit.gpu_ms;
    if (options.pass_kind_times) out.kind_times.push_back(lit);
  }
  glFinish();
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() - read_ms;
  out.width = width;
  out.height = height;
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  glDisable(GL_BLEND);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  apply_depth_mapping(gl::DepthMapping::Standard);
  check_gl("drawing the lit frame");
  out.rgb.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      for (int c = 0; c < 3; ++c)
        out.rgb[(static_cast<std::size_t>(height - 1 - j) * width + i) * 3 + c] =
            rgba[(static_cast<std::size_t>(j) * width + i) * 4 + c];
  return out;
}

}  // namespace nearcap::render
