// nearcap/render/eye_count_pass.hpp — AtomicZP's per-frame eye count on a
// real OpenGL: a GLSL compute pass over the occluder triangles into an
// atomic counter, and the count written into the stencil on the GPU.
//
// The emulation's count (gl/eye_count.hpp) is the reference: the pass runs
// the same float32 operations in the same order, one invocation per
// triangle, in camera space (the eye at the origin):
//   p_k     = MV * v_k                   (4 row dot products, left to right,
//                                         or fma chains: gl::transform)
//   n       = (p1 - p0) x (p2 - p0)      (each component a*b - c*d, or
//                                         fma(a, b, -(c*d)) fused)
//   lit     = h * dot(n, l - p0) > 0     (dot: x x' + y y' + z z' left to
//   eye     = h * dot(n, 0 - p0) < 0      right, or fma(z, z', fma(y, y', x x')))
//   s_k     = dot(l, p_k x p_k+1)
//   crossed = lit && eye && s_0, s_1, s_2 all > 0 or all < 0
//   atomicCounterIncrement once per crossed triangle.
// Every intermediate is a GLSL `precise` variable, so the compiler neither
// contracts a product and a sum into an fma nor reorders a sum (GLSL 4.50
// section 4.7.1); gl::Arithmetic::Fused spells its fmas out with fma().  The
// uniforms come from the CPU as a renderer's do, computed once per occluder
// exactly as the emulation computes them: MV = view * object in float32
// (gl::eye_count_object), h from the sign of its 3x3 determinant, and l the
// light in camera space (gl::light_in_camera_space).  The vertices are the
// mesh's positions rounded to float32, 3 per triangle in mesh order, w = 1.
//
// What can still differ from the emulation: a driver whose fma() is two
// roundings (GLSL allows it; llvmpipe's is) runs the shader's part of
// Arithmetic::Fused unfused, while the uniforms, computed on the CPU, stay
// fused; and a GPU that flushes
// subnormal floats to zero (llvmpipe does) decides differently only where an
// intermediate is below 2^-126.  tests/eye_count_pass_test.cpp holds the
// GL's count against the emulation's on every bundled scene, on eyes within
// 3 float32 ulps of a side plane (where the float count itself goes wrong),
// and on triangles whose eye -> light line grazes an edge.
//
// The count into the stencil: a full-screen triangle whose fragment shader
// reads the counter and exports it as the stencil reference
// (GL_ARB_shader_stencil_export, glStencilOp GL_REPLACE), so the frame's
// stencil starts at the count (mod 256) with no CPU round trip: the
// emulation's glClearStencil(count), moved onto the GPU.  Without the
// extension the count is read back and cleared to (EyeCountPass::
// stencil_on_gpu() says which).  Needs a current context with GL 4.3
// (compute shaders, atomic counters); EglContext gives 4.5.
#pragma once

#include <cstddef>
#include <vector>

#include "nearcap/gl/eye_count.hpp"
#include "nearcap/gl/float_transforms.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/render/gl_handle.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::render {

// One frame's inputs to the pass, built on the CPU.
struct EyeCountInputs {
  struct Occluder {
    std::size_t object = 0;  // scene index
    gl::EyeCountObject uniforms;
    std::size_t first = 0;  // its first triangle in `vertices`
    std::size_t triangles = 0;
  };
  std::vector<Occluder> occluders;
  std::vector<gl::Vec4f> vertices;  // object space, (x, y, z, 1), 3 per triangle, occluder after occluder
  gl::Vec4f light;                  // camera space
  gl::Arithmetic arithmetic = gl::Arithmetic::Separate;
  std::size_t triangles() const { return vertices.size() / 3; }
};

// The inputs for `objects` (scene indices; non-occluders are skipped, as
// gl::float_eye_count skips them) of light `light`.
EyeCountInputs eye_count_inputs(const Scene& scene, std::size_t light, const std::vector<std::size_t>& objects,
                                gl::Arithmetic arithmetic);

// The occluders a recorded frame counted (its ShadowFrame::object_methods
// drawn with AtomicZP); empty for a frame without an eye count.
std::vector<std::size_t> eye_counted_objects(const gl::ShadowFrame& frame);

// The arithmetic a recorded frame's programs used (its first draw with a
// vertex stage; Separate when none has one).
gl::Arithmetic recorded_arithmetic(const gl::ShadowFrame& frame);

// A run whose count was read back (EyeCountPass::run_and_read_back).
struct EyeCountReadBack {
  std::size_t count = 0;
  std::size_t triangles = 0;  // the invocations
  double pass_ms = 0;         // the upload, the dispatches and glFinish (wall clock)
  double read_back_ms = 0;    // reading the counter back after that: the CPU round trip
};

// The pass: its programs and buffers, made once per context and owned by
// handles (gl_handle.hpp), so they go with the pass.
class EyeCountPass {
 public:
  // Compiles the compute program (both arithmetics) and, where the driver
  // has GL_ARB_shader_stencil_export, the stencil program.  Throws
  // Error(Gl) when the context cannot run them, leaving no GL object.
  EyeCountPass();
  ~EyeCountPass();
  EyeCountPass(const EyeCountPass&) = delete;
  EyeCountPass& operator=(const EyeCountPass&) = delete;

  // Uploads the vertices, zeroes the counter and dispatches one invocation
  // per triangle (one dispatch per occluder, its uniforms set).  Returns at
  // once: the count stays on the GPU.  Leaves the compute program in use.
  // `upload_ms`, when given, gets the wall time of the glBufferData call.
  void run(const EyeCountInputs& inputs, double* upload_ms = nullptr);

  // The last run's count (waits for it: a CPU round trip).
  std::size_t read_count();
  // run(), glFinish, read_count(), each part timed.
  EyeCountReadBack run_and_read_back(const EyeCountInputs& inputs);

  // Every pixel of the bound draw framebuffer's stencil set to the last
  // run's count mod 256 (the viewport's pixels; the scissor and depth bounds
  // tests must be off).  On the GPU where stencil_on_gpu(), else read back
  // and cleared.  Changes the program, the depth test (off), the colour and
  // depth write masks (off), face culling (off) and the stencil function and
  // operations; restores the vertex array binding.  Callers set their own
  // draw state after it.
  void write_stencil();
  bool stencil_on_gpu() const { return static_cast<bool>(stencil_program_); }

  // Forces the read-back path of write_stencil (tests of both paths).
  void use_read_back_stencil();

 private:
  GlProgram count_programs_[2];  // [Arithmetic::Fused]
  GlProgram stencil_program_;    // none without GL_ARB_shader_stencil_export
  GlBuffer vertices_, counter_;
  GlVertexArray empty_array_;
};

}  // namespace nearcap::render
