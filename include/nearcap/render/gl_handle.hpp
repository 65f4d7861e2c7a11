// nearcap/render/gl_handle.hpp — move-only owners of OpenGL object names:
// each deletes its object when it goes out of scope, also when a
// constructor throws after making it, and hands it on when moved.
//
// A handle holds the name (GLuint) and nothing else; 0 is "no object".
// Deleting needs the context the object was made in to be current
// (EglContext), as every GL call of nearcap_render does.  The GL's own
// header stays out of this one: the handles are made by the functions of
// src/render/gl_objects.hpp.
#pragma once

namespace nearcap::render {

enum class GlObject { Buffer, VertexArray, Program, Shader, Framebuffer, Renderbuffer, Query };

// glDelete* (glDeleteProgram, glDeleteShader) of one name of `kind`; 0 is ignored.
void delete_gl_object(GlObject kind, unsigned name) noexcept;

template <GlObject Kind>
class GlHandle {
 public:
  GlHandle() = default;
  explicit GlHandle(unsigned name) noexcept : name_(name) {}  // takes ownership of `name`
  ~GlHandle() { reset(); }
  GlHandle(GlHandle&& other) noexcept : name_(other.name_) { other.name_ = 0; }
  GlHandle& operator=(GlHandle&& other) noexcept {
    if (this != &other) {
      reset();
      name_ = other.name_;
      other.name_ = 0;
    }
    return *this;
  }
  GlHandle(const GlHandle&) = delete;
  GlHandle& operator=(const GlHandle&) = delete;

  unsigned get() const noexcept { return name_; }
  explicit operator bool() const noexcept { return name_ != 0; }
  // Deletes the object now (no object afterwards).
  void reset() noexcept {
    delete_gl_object(Kind, name_);
    name_ = 0;
  }
  // The name, no longer owned: the caller deletes it.
  unsigned release() noexcept {
    const unsigned name = name_;
    name_ = 0;
    return name;
  }

 private:
  unsigned name_ = 0;
};

using GlBuffer = GlHandle<GlObject::Buffer>;
using GlVertexArray = GlHandle<GlObject::VertexArray>;
using GlProgram = GlHandle<GlObject::Program>;
using GlShader = GlHandle<GlObject::Shader>;
using GlFramebuffer = GlHandle<GlObject::Framebuffer>;
using GlRenderbuffer = GlHandle<GlObject::Renderbuffer>;
using GlQuery = GlHandle<GlObject::Query>;

// What the coverage probe, the frame replay and the lit frame draw into and
// from: a framebuffer object with a colour and a depth-stencil renderbuffer,
// and a vertex array with one vertex buffer (gl_objects.hpp:
// make_offscreen_target).
struct OffscreenTarget {
  GlFramebuffer framebuffer;
  GlRenderbuffer colour, depth_stencil;
  GlVertexArray vertex_array;
  GlBuffer vertices;
};

}  // namespace nearcap::render
