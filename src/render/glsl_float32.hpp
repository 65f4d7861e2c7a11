// src/render/glsl_float32.hpp (private to the render layer): the GLSL form
// of gl/float_transforms.cpp's dot4, the one float32 dot product every
// shader that repeats the emulation's arithmetic calls.  Each product and
// sum lands in a `precise` variable, so no compiler pass fuses or reorders
// across them; FUSED (0 or 1, defined before it) picks fma's order.
#pragma once

namespace nearcap::render {

inline constexpr const char* kGlslDot4 = R"(
float dot4(vec4 a, vec4 b) {
  precise float r = a.x * b.x;
#if FUSED
  r = fma(a.y, b.y, r);
  r = fma(a.z, b.z, r);
  r = fma(a.w, b.w, r);
#else
  r = r + a.y * b.y;
  r = r + a.z * b.z;
  r = r + a.w * b.w;
#endif
  return r;
}
)";

}  // namespace nearcap::render
