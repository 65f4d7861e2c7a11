// The shadow passes' vertex programs in GLSL (see glsl_shadow_programs.hpp).
#include "nearcap/render/glsl_shadow_programs.hpp"

#include <epoxy/gl.h>

#include <string>

#include "gl_objects.hpp"
#include "glsl_float32.hpp"
#include "nearcap/error.hpp"

namespace nearcap::render {
namespace {

// Common to every program: the inputs, the uniforms and the float32
// arithmetic of gl/float_transforms.cpp (dot4, transform) and
// gl/shadow_vertex_programs.cpp, in the same order.
const char* const kCommon = R"(
layout(location = 0) in vec4 vertex_in;
layout(location = 1) in vec3 colour_in;
out vec3 colour_v;
uniform mat4 modelview_projection;  // uploaded transposed: m[r] is row r
uniform mat4 light_modelview;
uniform mat4 light_projection;
uniform vec4 light_position;        // object space
uniform bool reversed;              // the camera's reversed depth mapping

vec4 transform(mat4 m, vec4 v) { return vec4(dot4(m[0], v), dot4(m[1], v), dot4(m[2], v), dot4(m[3], v)); }

vec4 extrusion_program(vec4 v) {
  precise vec4 p = v.w == 0.0 ? vec4(v.xyz - light_position.xyz, 0.0) : vec4(v.xyz, 1.0);
  return transform(modelview_projection, p);
}

vec4 near_cap_program(vec4 v) {
  return transform(light_projection, transform(light_modelview, vec4(v.xyz, 1.0)));
}

// The paper's Figure 7.
vec4 figure7_program(vec4 v) {
  precise vec4 eye = v;
  if (v.w == 0.0 || v.w == 4.0) eye = vec4(eye.xyz - light_position.xyz, 0.0);
  if (v.w == 2.0) eye.w = 1.0;
  eye = transform(modelview_projection, eye);
  if (v.w < 1.5 && (eye.w <= 0.0 || (reversed ? eye.z > eye.w : eye.z < -eye.w))) {
    eye = near_cap_program(v);
    eye.z = reversed ? eye.w : -eye.w;
  }
  return eye;
}

vec4 pass_through(vec4 v) { return v; }

#if CLIP_DISTANCE
// One depth side clamped without GL_AMD_depth_clamp_separate: GL_DEPTH_CLAMP,
// and the plane that still clips as a user clip distance, (a z + b w) with
// a = +-1 and b = 0 or 1: one rounding, the clipper's own z + w, w - z or z.
out float gl_ClipDistance[1];
uniform vec2 clip_plane;
#endif

void main() {
  gl_Position = PROGRAM(vertex_in);
#if CLIP_DISTANCE
  precise float distance = clip_plane.x * gl_Position.z + clip_plane.y * gl_Position.w;
  gl_ClipDistance[0] = distance;
#endif
  colour_v = colour_in;
}
)";

std::size_t slot(std::optional<gl::VertexProgram> p, gl::Arithmetic a, bool clip_distance) {
  return 4 * (p ? 1 + static_cast<std::size_t>(*p) : 0) + 2 * (a == gl::Arithmetic::Fused ? 1 : 0) +
         (clip_distance ? 1 : 0);
}

void set_matrix(GLuint program, const char* name, const gl::Mat4f& m) {
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_TRUE, m.m.data());
}

}  // namespace

std::string_view to_string(VertexStage s) { return name_of(s); }

std::optional<VertexStage> vertex_stage_from_string(std::string_view name) { return value_named<VertexStage>(name); }

std::string glsl_vertex_shader(std::optional<gl::VertexProgram> program, gl::Arithmetic arithmetic,
                               bool clip_distance) {
  std::string name = "pass_through";
  if (program) {
    name = std::string(gl::to_string(*program)) + "_program";
    if (*program == gl::VertexProgram::NearCap) name = "near_cap_program";
  }
  return std::string("#version 450 core\n#define FUSED ") + (arithmetic == gl::Arithmetic::Fused ? "1" : "0") +
         "\n#define CLIP_DISTANCE " + (clip_distance ? "1" : "0") + "\n#define PROGRAM " + name + "\n" + kGlslDot4 +
         kCommon;
}

ShadowPrograms::ShadowPrograms(std::string fragment_source, std::string what)
    : fragment_source_(std::move(fragment_source)), what_(std::move(what)) {}

ShadowPrograms::~ShadowPrograms() = default;

unsigned ShadowPrograms::program(std::optional<gl::VertexProgram> p, gl::Arithmetic a, bool clip_distance) {
  GlProgram& out = programs_[slot(p, a, clip_distance)];
  if (out) return out.get();
  const std::string vertex = glsl_vertex_shader(p, a, clip_distance);
  out = linked_program(vertex.c_str(), fragment_source_.c_str(),
                       what_ + " (" + std::string(p ? gl::to_string(*p) : "pass-through") + " vertex program)",
                       "gl_Position");
  return out.get();
}

void ShadowPrograms::prepare(const gl::DrawCall& d, VertexStage stage, bool clip_distance) {
  if (stage == VertexStage::Recorded || !d.vertex_stage)
    program(std::nullopt, gl::Arithmetic::Separate, clip_distance);
  else
    program(d.vertex_stage->program, d.vertex_stage->uniforms.arithmetic, clip_distance);
}

ShadowProgramUse ShadowPrograms::use(const gl::DrawCall& d, VertexStage stage, bool clip_distance) {
  ShadowProgramUse u;
  // The plane that still clips: the near one when the far side clamps.
  auto set_clip_plane = [&] {
    if (!clip_distance) return;
    const bool near = !d.state.depth_clamp_near;
    const bool reversed = d.state.depth_mapping == gl::DepthMapping::Reversed;
    // near: z + w (reversed: w - z); far: w - z (reversed: z).
    const float a = near != reversed ? 1.0f : -1.0f;
    const float b = near || !reversed ? 1.0f : 0.0f;
    glUniform2f(glGetUniformLocation(u.program, "clip_plane"), a, b);
  };
  if (stage == VertexStage::Recorded || !d.vertex_stage) {
    u.program = program(std::nullopt, gl::Arithmetic::Separate, clip_distance);
    glUseProgram(u.program);
    set_clip_plane();
    u.vertices = d.clip_vertices.empty() ? nullptr : &d.clip_vertices.front().x;
    u.count = d.clip_vertices.size();
    return u;
  }
  const gl::VertexProgramRun& run = *d.vertex_stage;
  u.program = program(run.program, run.uniforms.arithmetic, clip_distance);
  glUseProgram(u.program);
  set_clip_plane();
  set_matrix(u.program, "modelview_projection", run.uniforms.modelview_projection);
  set_matrix(u.program, "light_modelview", run.uniforms.light_modelview);
  set_matrix(u.program, "light_projection", run.uniforms.light_projection);
  const gl::Vec4f& l = run.uniforms.light_position;
  glUniform4f(glGetUniformLocation(u.program, "light_position"), l.x, l.y, l.z, l.w);
  glUniform1i(glGetUniformLocation(u.program, "reversed"), run.uniforms.depth_mapping == gl::DepthMapping::Reversed);
  static_assert(sizeof(gl::ShadowVertex) == 4 * sizeof(float));
  u.vertices = run.inputs.empty() ? nullptr : &run.inputs.front().x;
  u.count = run.inputs.size();
  return u;
}

std::vector<gl::Vec4f> ShadowPrograms::capture(const gl::DrawCall& d) {
  GLint previous_array = 0, previous_framebuffer = 0;
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &previous_array);
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_framebuffer);
  if (!capture_array_) {
    capture_array_ = new_vertex_array();
    capture_vertices_ = new_buffer();
    capture_buffer_ = new_buffer();
    // A draw needs a complete framebuffer even with rasterization discarded
    // (a surfaceless context has none): 1x1, never written.
    capture_framebuffer_ = new_framebuffer();
    glBindFramebuffer(GL_FRAMEBUFFER, capture_framebuffer_.get());
    capture_target_ = attached_renderbuffer(GL_RGBA8, GL_COLOR_ATTACHMENT0, 1, 1);
  }
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, capture_framebuffer_.get());
  const ShadowProgramUse u = use(d, VertexStage::Glsl);
  std::vector<gl::Vec4f> out(u.count);
  if (u.count == 0) return out;
  const auto bytes = static_cast<GLsizeiptr>(u.count * sizeof(gl::Vec4f));
  glBindVertexArray(capture_array_.get());
  glBindBuffer(GL_ARRAY_BUFFER, capture_vertices_.get());
  glBufferData(GL_ARRAY_BUFFER, bytes, u.vertices, GL_STREAM_DRAW);
  glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glVertexAttrib3f(1, 0, 0, 0);
  glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, capture_buffer_.get());
  glBufferData(GL_TRANSFORM_FEEDBACK_BUFFER, bytes, nullptr, GL_STREAM_READ);
  glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, capture_buffer_.get());
  glEnable(GL_RASTERIZER_DISCARD);
  glBeginTransformFeedback(GL_TRIANGLES);
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(u.count - u.count % 3));
  glEndTransformFeedback();
  glDisable(GL_RASTERIZER_DISCARD);
  glGetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, bytes, out.data());
  glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
  glBindVertexArray(static_cast<GLuint>(previous_array));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(previous_framebuffer));
  check_gl("capturing a vertex program's output");
  return out;
}

}  // namespace nearcap::render
