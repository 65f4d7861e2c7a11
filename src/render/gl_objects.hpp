// What every real-GL class of nearcap_render does with the GL the same way:
// errors as nearcap::Error (kind Gl), shaders and programs from source.
// Needs a current context (EglContext).  Private to src/render/.
#pragma once

#include <epoxy/gl.h>

#include <string>

#include "nearcap/error.hpp"

namespace nearcap::render {

// Throws Error(Gl) naming `step` when the GL reports an error.
inline void check_gl(const char* step) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) throw Error(ErrorKind::Gl, std::string("GL error ") + std::to_string(e) + " after " + step);
}

inline GLuint compile_shader(GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw Error(ErrorKind::Gl, std::string("shader compilation failed: ") + log);
  }
  return shader;
}

// A program of a vertex and a fragment shader; `what` names it in the error.
// `captured`: a vertex output transform feedback may capture (or null).
inline GLuint link_program(const char* vertex_source, const char* fragment_source, const std::string& what,
                           const char* captured = nullptr) {
  const GLuint vs = compile_shader(GL_VERTEX_SHADER, vertex_source);
  const GLuint fs = compile_shader(GL_FRAGMENT_SHADER, fragment_source);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  if (captured) glTransformFeedbackVaryings(program, 1, &captured, GL_INTERLEAVED_ATTRIBS);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) {
    char log[1024] = {};
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    glDeleteProgram(program);
    throw Error(ErrorKind::Gl, what + " does not link: " + log);
  }
  return program;
}

// A width x height renderbuffer of `format` attached to the bound
// framebuffer at `attachment`.
inline GLuint attach_renderbuffer(GLenum format, GLenum attachment, int width, int height) {
  GLuint buffer = 0;
  glGenRenderbuffers(1, &buffer);
  glBindRenderbuffer(GL_RENDERBUFFER, buffer);
  glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, buffer);
  return buffer;
}

// The depth-stencil format of a depth buffer format (8 stencil bits either way).
inline GLenum depth_stencil_format(bool fixed24) { return fixed24 ? GL_DEPTH24_STENCIL8 : GL_DEPTH32F_STENCIL8; }

}  // namespace nearcap::render
