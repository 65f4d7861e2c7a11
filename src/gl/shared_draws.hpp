// gl/shared_draws.hpp — the vertex programs' outputs and triangle setups that
// the methods of one frame batch (shadow_methods.hpp: ShadowFrameBatch)
// share, so that each is computed once per batch (private to gl/; not
// installed).
//
// Several methods draw the same geometry with the same program and
// uniforms: Z-fail's and preload's light and dark caps (preload twice),
// ZP+'s and ZP+ corrected's near-cap pass, the Z-pass sides of Z-pass, ZP+
// and AtomicZP; the mesh (near-cap pass) and the caps are indexed draws
// (mesh_vertex_array.hpp).  The clip-space vertices of such a draw are the same bits
// whichever method asks, and so is its setup (clipping, viewport, culling)
// under states with the same_setup (pipeline.hpp).  A cached draw therefore
// rasterizes exactly the triangles a fresh one would.
#pragma once

#include <deque>
#include <vector>

#include "mesh_vertex_array.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "nearcap/gl/shadow_vertex_programs.hpp"

namespace nearcap::gl {

class SharedDraws {
 public:
  // The clip-space vertices of `program` run on each of `inputs` with
  // `uniforms`.  `inputs` is known by its address: an array that outlives
  // this object, neither moves nor changes (a batch's mesh vertices or
  // volume geometry).  `reused_ms`: what computing them took, when
  // this call found them computed before; 0 when it computed them.
  struct Program {
    const std::vector<Vec4f>& clip;
    double reused_ms;
  };
  Program run(const std::vector<ShadowVertex>& inputs, VertexProgram program, const ShadowUniforms& uniforms);
  // Those vertices set up on `fb` with `state` (Framebuffer::set_up);
  // `reused_ms`: the time of what of that (program, setup) this call found
  // done before.  The same framebuffer size and raster settings on every call.
  struct SetUp {
    const SetUpTriangles& triangles;
    double reused_ms;
  };
  SetUp set_up(const std::vector<ShadowVertex>& inputs, VertexProgram program, const ShadowUniforms& uniforms,
               const Framebuffer& fb, const DrawState& state, const RasterSettings& raster);
  // The same for an indexed draw (mesh_vertex_array.hpp), both its arrays
  // known by their addresses: the program is run once per input (and shared
  // by every draw of those inputs), the setup per vertex once per draw
  // (Framebuffer::set_up of an indexed draw).  run() gives the clip-space
  // vertex of each corner, gathered from the inputs'.
  Program run(const IndexedInputs& draw, VertexProgram program, const ShadowUniforms& uniforms);
  SetUp set_up(const IndexedInputs& draw, VertexProgram program, const ShadowUniforms& uniforms, const Framebuffer& fb,
               const DrawState& state, const RasterSettings& raster);

 private:
  struct StateSetUp {
    const std::vector<std::uint32_t>* corners = nullptr;  // an indexed draw's; null: one input per corner
    DrawState state;
    SetUpTriangles triangles;
    double ms = 0;
  };
  struct Gathered {
    const std::vector<std::uint32_t>* corners = nullptr;
    std::vector<Vec4f> clip;
  };
  struct ProgramRun {
    const std::vector<ShadowVertex>* inputs = nullptr;  // known by its address
    VertexProgram program = VertexProgram::Extrusion;
    ShadowUniforms uniforms;
    std::vector<Vec4f> clip;  // one per input
    double ms = 0;
    std::deque<StateSetUp> set_ups;  // a deque: references to earlier ones stay valid
    std::deque<Gathered> gathered;   // per corner, for an indexed draw's run()
  };
  // `found`: whether it was run before this call.
  ProgramRun& find_or_run(const std::vector<ShadowVertex>& inputs, VertexProgram program,
                          const ShadowUniforms& uniforms, bool& found);
  SetUp find_or_set_up(const std::vector<ShadowVertex>& inputs, const std::vector<std::uint32_t>* corners,
                       VertexProgram program, const ShadowUniforms& uniforms, const Framebuffer& fb,
                       const DrawState& state, const RasterSettings& raster);
  std::deque<ProgramRun> runs_;
};

// The same uniforms, bit for bit, of those `program` reads (so that it
// computes the same bits from them).
bool same_uniforms(VertexProgram program, const ShadowUniforms& a, const ShadowUniforms& b);

}  // namespace nearcap::gl
