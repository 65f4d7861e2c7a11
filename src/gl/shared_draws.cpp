// A frame batch's shared vertex program runs and setups (see shared_draws.hpp).
#include "shared_draws.hpp"

#include <chrono>
#include <cstring>

#include "shadow_draw_setup.hpp"

namespace nearcap::gl {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

}  // namespace

bool same_uniforms(VertexProgram program, const ShadowUniforms& a, const ShadowUniforms& b) {
  // Field by field (the struct's padding is not compared), the fields the
  // program reads (shadow_vertex_programs.cpp): the extrusion program the
  // camera's matrix and the light's position, the near-cap program the
  // light's matrices, Figure 7 all of them and the depth mapping.
  const bool camera = program != VertexProgram::NearCap, light_frame = program != VertexProgram::Extrusion;
  return a.arithmetic == b.arithmetic &&
         (!camera || (same_bits(a.modelview_projection, b.modelview_projection) &&
                      same_bits(a.light_position, b.light_position))) &&
         (!light_frame ||
          (same_bits(a.light_modelview, b.light_modelview) && same_bits(a.light_projection, b.light_projection))) &&
         (program != VertexProgram::Figure7 || a.depth_mapping == b.depth_mapping);
}

SharedDraws::ProgramRun& SharedDraws::find_or_run(const std::vector<ShadowVertex>& inputs, VertexProgram program,
                                                  const ShadowUniforms& uniforms, bool& found) {
  found = true;
  for (ProgramRun& r : runs_)
    if (r.inputs == &inputs && r.program == program && same_uniforms(program, r.uniforms, uniforms)) return r;
  found = false;
  const auto t = Clock::now();
  ProgramRun& r = runs_.emplace_back();
  r.inputs = &inputs;
  r.program = program;
  r.uniforms = uniforms;
  r.clip = run_vertex_program(program, uniforms, inputs);
  r.ms = ms_since(t);
  return r;
}

SharedDraws::SetUp SharedDraws::find_or_set_up(const std::vector<ShadowVertex>& inputs,
                                               const std::vector<std::uint32_t>* corners, VertexProgram program,
                                               const ShadowUniforms& uniforms, const Framebuffer& fb,
                                               const DrawState& state, const RasterSettings& raster) {
  bool found = false;
  ProgramRun& r = find_or_run(inputs, program, uniforms, found);
  const double program_ms = found ? r.ms : 0.0;
  for (StateSetUp& s : r.set_ups)
    if (s.corners == corners && same_setup(s.state, state)) return {s.triangles, program_ms + s.ms, s};
  const auto t = Clock::now();
  SetUpTriangles triangles;
  // May throw (a degenerate vertex): nothing is kept then.
  if (corners)
    fb.set_up(r.clip, *corners, state, raster, triangles);
  else
    fb.set_up(r.clip, state, raster, triangles);
  StateSetUp& s = r.set_ups.emplace_back();
  s.corners = corners;
  s.state = state;
  s.triangles = std::move(triangles);
  s.ms = ms_since(t);
  return {s.triangles, program_ms, s};
}

SharedDraws::Program SharedDraws::run(const std::vector<ShadowVertex>& inputs, VertexProgram program,
                                      const ShadowUniforms& uniforms) {
  bool found = false;
  const ProgramRun& r = find_or_run(inputs, program, uniforms, found);
  return {r.clip, found ? r.ms : 0.0};
}

SharedDraws::Program SharedDraws::run(const IndexedInputs& draw, VertexProgram program,
                                      const ShadowUniforms& uniforms) {
  bool found = false;
  ProgramRun& r = find_or_run(draw.inputs, program, uniforms, found);
  const double reused_ms = found ? r.ms : 0.0;
  for (const Gathered& g : r.gathered)
    if (g.corners == &draw.corners) return {g.clip, reused_ms};
  Gathered& g = r.gathered.emplace_back();
  g.corners = &draw.corners;
  g.clip = per_corner(r.clip, draw.corners);
  return {g.clip, reused_ms};
}

SharedDraws::SetUp SharedDraws::set_up(const std::vector<ShadowVertex>& inputs, VertexProgram program,
                                       const ShadowUniforms& uniforms, const Framebuffer& fb, const DrawState& state,
                                       const RasterSettings& raster) {
  return find_or_set_up(inputs, nullptr, program, uniforms, fb, state, raster);
}

SharedDraws::SetUp SharedDraws::set_up(const IndexedInputs& draw, VertexProgram program, const ShadowUniforms& uniforms,
                                       const Framebuffer& fb, const DrawState& state, const RasterSettings& raster) {
  return find_or_set_up(draw.inputs, &draw.corners, program, uniforms, fb, state, raster);
}

SharedDraws::Fragments SharedDraws::rasterize(const SetUp& set_up, Framebuffer& fb, const DrawState& state,
                                              const RasterSettings& raster) {
  StateSetUp& s = set_up.entry;
  const auto t = Clock::now();
  if (s.replayable) {
    const DrawCounters counters = fb.replay(s.fragments, state, raster);
    return {counters, s.rasterized_ms - ms_since(t), true};
  }
  if (s.rasterized) return {fb.rasterize(s.triangles, state, raster), 0.0, false};
  const DrawCounters counters =
      fb.rasterize(s.triangles, state, raster, &s.fragments, kKeptFragments - kept_fragments_);
  s.rasterized = true;
  s.rasterized_ms = ms_since(t);
  s.replayable = !s.fragments.bands.empty();
  kept_fragments_ += s.fragments.size();
  return {counters, 0.0, false};
}

}  // namespace nearcap::gl
