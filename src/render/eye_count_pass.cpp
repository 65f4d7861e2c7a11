// AtomicZP's eye count on the real GL (see eye_count_pass.hpp).
#include "nearcap/render/eye_count_pass.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <string>

#include "gl_objects.hpp"
#include "glsl_float32.hpp"
#include "nearcap/error.hpp"
#include "nearcap/gl/light_frustum.hpp"

namespace nearcap::render {
namespace {

constexpr GLuint kLocalSize = 64;
constexpr GLuint kMaxGroups = 65535;  // GL_MAX_COMPUTE_WORK_GROUP_COUNT's guaranteed minimum

// gl/eye_count.cpp's and gl/float_transforms.cpp's float32 operations, in
// their order.  Each product and sum lands in a `precise` variable of its
// own function, so no compiler pass fuses or reorders across them.
const char* const kCountShader = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Vertices { vec4 vertices[]; };
layout(binding = 0, offset = 0) uniform atomic_uint eye_count;
uniform mat4 modelview;   // uploaded transposed: modelview[r] is row r
uniform vec4 light;       // camera space
uniform bool mirrored;    // h = -1
uniform uint first;       // the occluder's first triangle in `vertices`
uniform uint triangles;   // its triangle count
uniform uint group_offset;  // the dispatch's first work group (dispatches of at most 65535 groups)

vec3 camera_space(vec4 v) { return vec3(dot4(modelview[0], v), dot4(modelview[1], v), dot4(modelview[2], v)); }

float difference_of_products(float a, float b, float c, float d) {
  precise float cd = c * d;
#if FUSED
  precise float r = fma(a, b, -cd);
#else
  precise float ab = a * b;
  precise float r = ab - cd;
#endif
  return r;
}

vec3 cross3(vec3 a, vec3 b) {
  return vec3(difference_of_products(a.y, b.z, a.z, b.y), difference_of_products(a.z, b.x, a.x, b.z),
              difference_of_products(a.x, b.y, a.y, b.x));
}

float dot3(vec3 a, vec3 b) {
  precise float r = a.x * b.x;
#if FUSED
  r = fma(a.y, b.y, r);
  r = fma(a.z, b.z, r);
#else
  r = r + a.y * b.y;
  r = r + a.z * b.z;
#endif
  return r;
}

void main() {
  const uint t = (gl_WorkGroupID.x + group_offset) * 64u + gl_LocalInvocationID.x;
  if (t >= triangles) return;
  const uint v = 3u * (first + t);
  const vec3 a = camera_space(vertices[v]), b = camera_space(vertices[v + 1u]), c = camera_space(vertices[v + 2u]);
  const vec3 l = light.xyz;
  precise vec3 ab = b - a, ac = c - a, to_light = l - a, to_eye = vec3(0.0) - a;
  const vec3 n = cross3(ab, ac);
  const float h = mirrored ? -1.0 : 1.0;
  precise float lit = h * dot3(n, to_light), eye = h * dot3(n, to_eye);
  if (!(lit > 0.0) || !(eye < 0.0)) return;  // not facing the light, or the eye not behind the plane
  const float s0 = dot3(l, cross3(a, b)), s1 = dot3(l, cross3(b, c)), s2 = dot3(l, cross3(c, a));
  if ((s0 > 0.0 && s1 > 0.0 && s2 > 0.0) || (s0 < 0.0 && s1 < 0.0 && s2 < 0.0)) atomicCounterIncrement(eye_count);
}
)";

// A full-screen triangle from gl_VertexID; the fragment shader exports the
// count as its stencil reference.
const char* const kStencilVertexShader = R"(#version 450 core
void main() {
  const vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)";
const char* const kStencilFragmentShader = R"(#version 450 core
#extension GL_ARB_shader_stencil_export : require
layout(binding = 0, offset = 0) uniform atomic_uint eye_count;
void main() { gl_FragStencilRefARB = int(atomicCounter(eye_count) & 255u); }
)";

}  // namespace

EyeCountInputs eye_count_inputs(const Scene& scene, std::size_t light, const std::vector<std::size_t>& objects,
                                gl::Arithmetic arithmetic) {
  EyeCountInputs in;
  in.light = gl::light_in_camera_space(scene, light);
  in.arithmetic = arithmetic;
  for (std::size_t o : objects) {
    const SceneObject& obj = scene.objects[o];
    if (!obj.occluder) continue;
    const TriangleMesh& mesh = *obj.mesh;
    in.occluders.push_back({o, gl::eye_count_object(scene, o, arithmetic), in.triangles(), mesh.triangles.size()});
    for (const auto& t : mesh.triangles)
      for (int k = 0; k < 3; ++k) {
        const Vec3d& q = mesh.positions[t[k]];
        in.vertices.push_back({static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z), 1.0f});
      }
  }
  return in;
}

std::vector<std::size_t> eye_counted_objects(const gl::ShadowFrame& frame) {
  std::vector<std::size_t> out;
  if (!frame.eye_count) return out;
  for (const auto& [object, method] : frame.object_methods)
    if (method == gl::ShadowMethod::AtomicZP) out.push_back(object);
  return out;
}

gl::Arithmetic recorded_arithmetic(const gl::ShadowFrame& frame) {
  for (const gl::DrawCall& d : frame.draws)
    if (d.vertex_stage) return d.vertex_stage->uniforms.arithmetic;
  return gl::Arithmetic::Separate;
}

EyeCountPass::EyeCountPass() {
  if (!epoxy_has_gl_extension("GL_ARB_compute_shader") && epoxy_gl_version() < 43)
    throw Error(ErrorKind::Gl, "the eye-count pass needs compute shaders (GL 4.3); the context has GL " +
                                   std::to_string(epoxy_gl_version() / 10) + "." +
                                   std::to_string(epoxy_gl_version() % 10));
  for (int fused = 0; fused < 2; ++fused)
    count_programs_[fused] = linked_compute_program(
        std::string("#version 450 core\n#define FUSED ") + (fused ? "1" : "0") + "\n" + kGlslDot4 + kCountShader,
        "the eye-count pass's compute program");
  if (epoxy_has_gl_extension("GL_ARB_shader_stencil_export"))
    stencil_program_ = linked_program(kStencilVertexShader, kStencilFragmentShader, "the eye count's stencil program");
  vertices_ = new_buffer();
  counter_ = new_buffer();
  glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, counter_.get());
  glBufferData(GL_ATOMIC_COUNTER_BUFFER, sizeof(GLuint), nullptr, GL_DYNAMIC_COPY);
  empty_array_ = new_vertex_array();
  // llvmpipe compiles a program's machine code at its first dispatch: one
  // empty dispatch of each here, so that no timed frame pays for it.
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, vertices_.get());
  glBufferData(GL_SHADER_STORAGE_BUFFER, 16, nullptr, GL_STREAM_DRAW);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, vertices_.get());
  glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, counter_.get());
  for (const GlProgram& program : count_programs_) {
    glUseProgram(program.get());
    glUniform1ui(glGetUniformLocation(program.get(), "triangles"), 0);
    glDispatchCompute(1, 1, 1);
  }
  glFinish();
  check_gl("creating the eye-count pass");
}

EyeCountPass::~EyeCountPass() = default;

void EyeCountPass::use_read_back_stencil() { stencil_program_.reset(); }

void EyeCountPass::run(const EyeCountInputs& in, double* upload_ms) {
  const GLuint zero = 0;
  glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, counter_.get());
  glBufferSubData(GL_ATOMIC_COUNTER_BUFFER, 0, sizeof zero, &zero);
  glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, counter_.get());
  const auto u0 = std::chrono::steady_clock::now();
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, vertices_.get());
  glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(1, in.vertices.size()) * 16),
               in.vertices.empty() ? nullptr : &in.vertices.front().x, GL_STREAM_DRAW);
  if (upload_ms) *upload_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - u0).count();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, vertices_.get());
  const GLuint program = count_programs_[in.arithmetic == gl::Arithmetic::Fused ? 1 : 0].get();
  glUseProgram(program);
  glUniform4f(glGetUniformLocation(program, "light"), in.light.x, in.light.y, in.light.z, in.light.w);
  const GLint modelview = glGetUniformLocation(program, "modelview"),
              mirrored = glGetUniformLocation(program, "mirrored"), first = glGetUniformLocation(program, "first"),
              triangles = glGetUniformLocation(program, "triangles"),
              group_offset = glGetUniformLocation(program, "group_offset");
  for (const EyeCountInputs::Occluder& o : in.occluders) {
    if (o.triangles == 0) continue;
    glUniformMatrix4fv(modelview, 1, GL_TRUE, o.uniforms.modelview.m.data());
    glUniform1i(mirrored, o.uniforms.mirrored ? 1 : 0);
    glUniform1ui(first, static_cast<GLuint>(o.first));
    glUniform1ui(triangles, static_cast<GLuint>(o.triangles));
    const std::size_t groups = (o.triangles + kLocalSize - 1) / kLocalSize;
    for (std::size_t g = 0; g < groups; g += kMaxGroups) {
      glUniform1ui(group_offset, static_cast<GLuint>(g));
      glDispatchCompute(static_cast<GLuint>(std::min<std::size_t>(kMaxGroups, groups - g)), 1, 1);
    }
  }
  check_gl("the eye-count pass");
}

std::size_t EyeCountPass::read_count() {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_ATOMIC_COUNTER_BARRIER_BIT);
  GLuint count = 0;
  glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, counter_.get());
  glGetBufferSubData(GL_ATOMIC_COUNTER_BUFFER, 0, sizeof count, &count);
  check_gl("reading the eye count back");
  return count;
}

EyeCountReadBack EyeCountPass::run_and_read_back(const EyeCountInputs& inputs) {
  EyeCountReadBack out;
  out.triangles = inputs.triangles();
  const auto t0 = std::chrono::steady_clock::now();
  run(inputs);
  glFinish();
  const auto t1 = std::chrono::steady_clock::now();
  out.count = read_count();
  const auto t2 = std::chrono::steady_clock::now();
  out.pass_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  out.read_back_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
  return out;
}

void EyeCountPass::write_stencil() {
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDepthMask(GL_FALSE);
  glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glStencilMask(0xFF);
  if (!stencil_program_) {
    glClearStencil(static_cast<GLint>(read_count() & 0xffu));
    glClear(GL_STENCIL_BUFFER_BIT);
    return;
  }
  GLint previous_array = 0;
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &previous_array);
  glMemoryBarrier(GL_ATOMIC_COUNTER_BARRIER_BIT);
  glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, counter_.get());
  glUseProgram(stencil_program_.get());
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_ALWAYS, 0, 0xFF);
  glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  glBindVertexArray(empty_array_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(static_cast<GLuint>(previous_array));
  check_gl("writing the eye count into the stencil");
}

}  // namespace nearcap::render
