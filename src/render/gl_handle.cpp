// Deleting the GL objects that render::GlHandle owns (see gl_handle.hpp).
#include "nearcap/render/gl_handle.hpp"

#include <epoxy/gl.h>

namespace nearcap::render {

void delete_gl_object(GlObject kind, unsigned name) noexcept {
  if (name == 0) return;
  const GLuint n = name;
  switch (kind) {
    case GlObject::Buffer:
      glDeleteBuffers(1, &n);
      return;
    case GlObject::VertexArray:
      glDeleteVertexArrays(1, &n);
      return;
    case GlObject::Program:
      glDeleteProgram(n);
      return;
    case GlObject::Shader:
      glDeleteShader(n);
      return;
    case GlObject::Framebuffer:
      glDeleteFramebuffers(1, &n);
      return;
    case GlObject::Renderbuffer:
      glDeleteRenderbuffers(1, &n);
      return;
    case GlObject::Query:
      glDeleteQueries(1, &n);
      return;
  }
}

}  // namespace nearcap::render
