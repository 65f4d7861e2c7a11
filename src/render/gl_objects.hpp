// What every real-GL class of nearcap_render does with the GL the same way:
// errors as nearcap::Error (kind Gl), new objects owned by their handles
// (gl_handle.hpp), shaders and programs from source, the offscreen target.
// Needs a current context (EglContext).  Private to src/render/.
#pragma once

#include <epoxy/gl.h>

#include <string>

#include "nearcap/error.hpp"
#include "nearcap/render/gl_handle.hpp"

namespace nearcap::render {

// Throws Error(Gl) naming `step` when the GL reports an error.
inline void check_gl(const char* step) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) throw Error(ErrorKind::Gl, std::string("GL error ") + std::to_string(e) + " after " + step);
}

// A new object of each kind (glGen*), owned.
template <GlObject Kind, class Generate>
GlHandle<Kind> generated(Generate generate) {
  GLuint n = 0;
  generate(1, &n);
  return GlHandle<Kind>(n);
}
inline GlBuffer new_buffer() { return generated<GlObject::Buffer>(glGenBuffers); }
inline GlVertexArray new_vertex_array() { return generated<GlObject::VertexArray>(glGenVertexArrays); }
inline GlFramebuffer new_framebuffer() { return generated<GlObject::Framebuffer>(glGenFramebuffers); }
inline GlRenderbuffer new_renderbuffer() { return generated<GlObject::Renderbuffer>(glGenRenderbuffers); }
inline GlQuery new_query() { return generated<GlObject::Query>(glGenQueries); }

inline GlShader compiled_shader(GLenum stage, const char* source) {
  GlShader shader(glCreateShader(stage));
  const GLuint s = shader.get();
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw Error(ErrorKind::Gl, std::string("shader compilation failed: ") + log);
  }
  return shader;
}

// Links `program`; a failure throws Gl "WHAT does not link: LOG".
inline void link_checked(GLuint program, const std::string& what) {
  glLinkProgram(program);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) {
    char log[1024] = {};
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    throw Error(ErrorKind::Gl, what + " does not link: " + log);
  }
}

// A program of a vertex and a fragment shader; `what` names it in the error.
// `captured`: a vertex output transform feedback may capture (or null).
inline GlProgram linked_program(const char* vertex_source, const char* fragment_source, const std::string& what,
                                const char* captured = nullptr) {
  const GlShader vs = compiled_shader(GL_VERTEX_SHADER, vertex_source);
  const GlShader fs = compiled_shader(GL_FRAGMENT_SHADER, fragment_source);
  GlProgram program(glCreateProgram());
  const GLuint p = program.get();
  glAttachShader(p, vs.get());
  glAttachShader(p, fs.get());
  if (captured) glTransformFeedbackVaryings(p, 1, &captured, GL_INTERLEAVED_ATTRIBS);
  link_checked(p, what);
  return program;
}

// A program of one compute shader; `what` names it in the error.
inline GlProgram linked_compute_program(const std::string& source, const std::string& what) {
  const GlShader cs = compiled_shader(GL_COMPUTE_SHADER, source.c_str());
  GlProgram program(glCreateProgram());
  glAttachShader(program.get(), cs.get());
  link_checked(program.get(), what);
  return program;
}

// A width x height renderbuffer of `format` attached to the bound
// framebuffer at `attachment`.
inline GlRenderbuffer attached_renderbuffer(GLenum format, GLenum attachment, int width, int height) {
  GlRenderbuffer buffer = new_renderbuffer();
  glBindRenderbuffer(GL_RENDERBUFFER, buffer.get());
  glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, buffer.get());
  return buffer;
}

// A width x height framebuffer object with a `colour_format` renderbuffer
// at colour attachment 0 and a `depth_stencil_format` one at the
// depth-stencil attachment, and a vertex array with one buffer; all three
// left bound (GL_FRAMEBUFFER, the vertex array, GL_ARRAY_BUFFER).  Throws
// Error(Gl) "`what`'s framebuffer object is incomplete", deleting what it made.
inline OffscreenTarget make_offscreen_target(int width, int height, GLenum colour_format, GLenum depth_stencil_format,
                                             const std::string& what) {
  OffscreenTarget t;
  t.framebuffer = new_framebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, t.framebuffer.get());
  t.colour = attached_renderbuffer(colour_format, GL_COLOR_ATTACHMENT0, width, height);
  t.depth_stencil = attached_renderbuffer(depth_stencil_format, GL_DEPTH_STENCIL_ATTACHMENT, width, height);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error(ErrorKind::Gl, what + "'s framebuffer object is incomplete");
  t.vertex_array = new_vertex_array();
  glBindVertexArray(t.vertex_array.get());
  t.vertices = new_buffer();
  glBindBuffer(GL_ARRAY_BUFFER, t.vertices.get());
  return t;
}

// The depth-stencil format of a depth buffer format (8 stencil bits either way).
inline GLenum depth_stencil_format(bool fixed24) { return fixed24 ? GL_DEPTH24_STENCIL8 : GL_DEPTH32F_STENCIL8; }

}  // namespace nearcap::render
