// Coverage of triangles by the real GL rasterizer (see coverage_probe.hpp).
#include "nearcap/render/coverage_probe.hpp"

#include <epoxy/gl.h>

#include <string>

#include "gl_objects.hpp"
#include "nearcap/error.hpp"

namespace nearcap::render {
namespace {

bool is_power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }

// Positions arrive in normalized device coordinates, computed exactly on the
// CPU; the shader passes them through with w = 1.
const char* const kVertexShader = R"(#version 450 core
layout(location = 0) in vec2 ndc;
void main() { gl_Position = vec4(ndc, 0.0, 1.0); }
)";
const char* const kFragmentShader = R"(#version 450 core
out vec4 colour;
void main() { colour = vec4(1.0); }
)";

}  // namespace

CoverageProbe::CoverageProbe(int width, int height) : width_(width), height_(height) {
  if (!is_power_of_two(width) || !is_power_of_two(height) || width > 16384 || height > 16384)
    throw Error(ErrorKind::Usage, "coverage probe size " + std::to_string(width) + "x" + std::to_string(height) +
                                      " is not a power of two up to 16384");
  target_ = make_offscreen_target(width, height, GL_RGBA8, GL_DEPTH24_STENCIL8, "the coverage probe");
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  program_ = linked_program(kVertexShader, kFragmentShader, "the coverage probe's program");
  check_gl("creating the coverage probe");
}

CoverageProbe::~CoverageProbe() = default;

std::vector<std::uint8_t> CoverageProbe::coverage(const std::vector<std::array<gl::WindowVertex, 3>>& triangles) {
  // Window -> NDC: x_ndc = 2 x / width - 1, exact for power-of-two sizes and
  // coordinates on a 1/2^k grid; the viewport transform maps it back exactly.
  std::vector<float> ndc;
  ndc.reserve(triangles.size() * 6);
  for (const auto& t : triangles)
    for (const gl::WindowVertex& v : t) {
      ndc.push_back(2.0f * v.x / static_cast<float>(width_) - 1.0f);
      ndc.push_back(2.0f * v.y / static_cast<float>(height_) - 1.0f);
    }
  glBindFramebuffer(GL_FRAMEBUFFER, target_.framebuffer.get());
  glViewport(0, 0, width_, height_);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_MULTISAMPLE);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glEnable(GL_STENCIL_TEST);
  glStencilMask(0xFF);
  glClearStencil(0);
  glClear(GL_STENCIL_BUFFER_BIT);
  glStencilFunc(GL_ALWAYS, 0, 0xFF);
  glStencilOp(GL_KEEP, GL_KEEP, GL_INCR_WRAP);
  glUseProgram(program_.get());
  glBindVertexArray(target_.vertex_array.get());
  glBindBuffer(GL_ARRAY_BUFFER, target_.vertices.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(ndc.size() * sizeof(float)), ndc.data(), GL_STREAM_DRAW);
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles.size() * 3));
  std::vector<std::uint8_t> counts(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, counts.data());
  check_gl("drawing and reading the coverage probe");
  return counts;
}

}  // namespace nearcap::render
