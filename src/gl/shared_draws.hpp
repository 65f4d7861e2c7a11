// gl/shared_draws.hpp — the vertex programs' outputs, triangle setups and
// covered fragments that the methods of one frame batch (shadow_methods.hpp:
// ShadowFrameBatch) share, so that each is computed once per batch (private
// to gl/; not installed).
//
// Several methods draw the same geometry with the same program and
// uniforms: Z-fail's and preload's light and dark caps (preload twice),
// ZP+'s and ZP+ corrected's near-cap pass, the Z-pass sides of Z-pass, ZP+
// and AtomicZP; the mesh (near-cap pass) and the caps are indexed draws
// (mesh_vertex_array.hpp).  The clip-space vertices of such a draw are the same bits
// whichever method asks, and so is its setup (clipping, viewport, culling)
// under states with the same_setup (pipeline.hpp), and so are the fragments
// its triangles cover: what differs between the methods (depth test, stencil
// operations, volume culling) acts on each fragment.  A cached draw therefore
// rasterizes exactly the triangles a fresh one would, and its replayed
// fragments meet the same tests in the same order.
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
  // A setup kept: the draw's setup with its state, and its first
  // rasterization's fragments (where `replayable`) and time.
  struct StateSetUp {
    const std::vector<std::uint32_t>* corners = nullptr;  // an indexed draw's; null: one input per corner
    DrawState state;
    SetUpTriangles triangles;
    double ms = 0;
    bool rasterized = false, replayable = false;
    CoveredFragments fragments;
    double rasterized_ms = 0;
  };
  // Those vertices set up on `fb` with `state` (Framebuffer::set_up);
  // `reused_ms`: the time of what of that (program, setup) this call found
  // done before.  The same framebuffer size and raster settings on every call.
  struct SetUp {
    const SetUpTriangles& triangles;
    double reused_ms;
    StateSetUp& entry;  // this object's, for rasterize()
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
  // The fragment stage of `set_up` on `fb` with `state` (a same_setup state,
  // the same framebuffer and raster settings as the setup's): the first call
  // rasterizes its triangles and keeps the fragments they cover, a later one
  // replays them (Framebuffer::replay).  A draw's fragments are kept where
  // they fit in what the batch's kept fragments leave of kKeptFragments; the
  // others are rasterized each time.  `reused_ms`: what the rasterization replayed
  // took, less the replay; 0 when this call rasterized (`replayed` false).
  struct Fragments {
    DrawCounters counters;
    double reused_ms;
    bool replayed;
  };
  Fragments rasterize(const SetUp& set_up, Framebuffer& fb, const DrawState& state, const RasterSettings& raster);
  // 8 MiB of kept fragments (8 bytes each), 54 per pixel at 160x120, where
  // the room paths' batches keep at most 53 per pixel and the bunny orbit's
  // 15 (docs/findings/sweep-speed.md); at 640x480 some draws fit.
  static constexpr std::size_t kKeptFragments = std::size_t{1} << 20;

 private:
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
  std::size_t kept_fragments_ = 0;
};

// The same uniforms, bit for bit, of those `program` reads (so that it
// computes the same bits from them).
bool same_uniforms(VertexProgram program, const ShadowUniforms& a, const ShadowUniforms& b);

}  // namespace nearcap::gl
