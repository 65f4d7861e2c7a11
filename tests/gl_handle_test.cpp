// render/gl_handle.hpp: a handle deletes its GL object when it goes, hands
// it on when moved, and a construction that throws halfway leaves no GL
// object behind (every name of the context checked with glIs* afterwards).
#include "nearcap/render/gl_handle.hpp"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "../src/render/gl_objects.hpp"
#include "llvmpipe_fixture.hpp"
#include "nearcap/error.hpp"
#include "nearcap/render/eye_count_pass.hpp"
#include "nearcap/render/glsl_shadow_programs.hpp"

namespace nearcap {
namespace {

class GlHandleTest : public test::LlvmpipeTest {};

// The names among the first 1024 that are objects of the context.  The
// fixture's context is new, so every object found was made by the test.
std::string live_objects() {
  std::string out;
  for (GLuint n = 1; n <= 1024; ++n) {
    if (glIsBuffer(n)) out += " buffer " + std::to_string(n);
    if (glIsVertexArray(n)) out += " vertex-array " + std::to_string(n);
    if (glIsProgram(n)) out += " program " + std::to_string(n);
    if (glIsShader(n)) out += " shader " + std::to_string(n);
    if (glIsFramebuffer(n)) out += " framebuffer " + std::to_string(n);
    if (glIsRenderbuffer(n)) out += " renderbuffer " + std::to_string(n);
  }
  return out;
}

TEST_F(GlHandleTest, AHandleDeletesItsObjectAndMovesIt) {
  render::GlBuffer a = render::new_buffer();
  const GLuint name = a.get();
  glBindBuffer(GL_ARRAY_BUFFER, name);  // a buffer object from its first binding on
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  ASSERT_TRUE(glIsBuffer(name));
  render::GlBuffer b = std::move(a);
  EXPECT_FALSE(a);
  EXPECT_EQ(b.get(), name);
  EXPECT_TRUE(glIsBuffer(name));
  { const render::GlBuffer c = std::move(b); }
  EXPECT_FALSE(glIsBuffer(name));
  EXPECT_EQ(live_objects(), "");
}

// The fragment shader does not compile: the vertex shader compiled before
// it goes too.
TEST_F(GlHandleTest, AProgramThatDoesNotCompileLeavesNoShader) {
  render::ShadowPrograms programs("#version 450 core\nthis is not GLSL\n", "a broken program");
  const gl::DrawCall draw;
  EXPECT_THROW(programs.prepare(draw, render::VertexStage::Recorded), Error);
  EXPECT_EQ(live_objects(), "");
}

// A colour attachment of a depth format: the framebuffer is incomplete, and
// the framebuffer and renderbuffers made before the check go.
TEST_F(GlHandleTest, AnIncompleteOffscreenTargetLeavesNoObject) {
  try {
    render::make_offscreen_target(16, 16, GL_DEPTH24_STENCIL8, GL_DEPTH24_STENCIL8, "a test target");
    ADD_FAILURE() << "an incomplete framebuffer was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Gl);
    EXPECT_NE(std::string(e.what()).find("a test target's framebuffer object is incomplete"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(live_objects(), "");
  // The same call with a colour format: complete, its objects live while it does.
  {
    const render::OffscreenTarget t =
        render::make_offscreen_target(16, 16, GL_RGBA8, GL_DEPTH24_STENCIL8, "a test target");
    EXPECT_TRUE(glIsFramebuffer(t.framebuffer.get()));
    EXPECT_TRUE(glIsRenderbuffer(t.colour.get()));
    EXPECT_TRUE(glIsVertexArray(t.vertex_array.get()));
  }
  EXPECT_EQ(live_objects(), "");
}

// The eye-count pass's constructor ends with a GL error check; a GL error
// left pending before it makes that check throw after every program,
// buffer and vertex array of the pass is made, and they all go.  A pass
// made without the error keeps its objects until it goes.  The constructor
// leaves a compute program in use, and the GL deletes a program in use only
// once it is no longer current: glUseProgram(0) before each look.
TEST_F(GlHandleTest, AnEyeCountPassThatThrowsLeavesNoObject) {
  glEnable(0xFFFFu);  // GL_INVALID_ENUM, pending until the next glGetError
  try {
    const render::EyeCountPass pass;
    ADD_FAILURE() << "a pending GL error was not reported";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Gl);
    EXPECT_NE(std::string(e.what()).find("creating the eye-count pass"), std::string::npos) << e.what();
  }
  glUseProgram(0);
  EXPECT_EQ(live_objects(), "");
  {
    const render::EyeCountPass pass;
    glUseProgram(0);
    EXPECT_NE(live_objects(), "");
  }
  EXPECT_EQ(live_objects(), "");
}

}  // namespace
}  // namespace nearcap
