// tests/support/cap_draw_state.hpp — the draw state of a near-cap pass
// (gl/near_plane_cap.hpp) as the cap tests draw one on its own.
#pragma once

#include "nearcap/gl/pipeline.hpp"

namespace nearcap::test {

// No depth test, vertices in the near plane kept by the clipper, and the
// stencil counting front faces +1 and back faces -1: the stencil then holds
// each pixel's winding number of the cap's triangles (mod 256).
inline gl::DrawState cap_draw_state() {
  gl::DrawState s;
  s.depth_func = gl::DepthFunc::Always;
  s.vertices_on_near_plane = true;
  s.front = {gl::StencilOp::Keep, gl::StencilOp::IncrementWrap};
  s.back = {gl::StencilOp::Keep, gl::StencilOp::DecrementWrap};
  return s;
}

}  // namespace nearcap::test
