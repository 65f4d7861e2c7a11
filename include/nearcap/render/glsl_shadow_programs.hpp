// nearcap/render/glsl_shadow_programs.hpp — the shadow passes' vertex
// programs in GLSL: the GPU building each draw's clip-space vertices from
// object-space vertices and uniforms, as the paper's renderer does, instead
// of receiving the emulation's results.
//
// The programs are gl/shadow_vertex_programs.hpp's, line for line, with the
// emulation's float32 operation order: each matrix row's dot product summed
// left to right into a `precise` variable (no contraction into fused
// multiply-adds, GLSL 4.50 section 4.7.1), or with explicit fma() chains for
// Arithmetic::Fused; matrices uploaded transposed so that m[r] is row r.
//   extrusion  w = 0: (x - light, 0), else (x, y, z, 1); times P * MV;
//   figure7    Figure 7: extrude (w = 0, 4), nail (w = 2), transform; a
//              movable vertex the near plane clips is re-transformed by
//              P_l * (M_l * MV) and pushed onto the near plane;
//   near-cap   P_l * (M_l * MV * (x, y, z, 1)).
// A draw whose vertices the CPU built (DrawCall::vertex_stage absent: the
// clipped-sides near cap) and every draw under VertexStage::Recorded go
// through a pass-through program.  Each program also passes a per-vertex
// colour (attribute 1) to the fragment shader's `colour_v`.
// Needs a current context (EglContext).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nearcap/gl/pipeline.hpp"
#include "nearcap/named_values.hpp"

namespace nearcap::render {

// Where a real-GL draw's clip-space vertices come from:
//   recorded  the emulation's float32 results, uploaded (a pass-through shader);
//   glsl      the GLSL programs above, run by the GL on the object-space inputs.
enum class VertexStage { Recorded, Glsl };
inline constexpr NamedValue<VertexStage> kVertexStageTable[] = {
    {VertexStage::Glsl, "glsl", "the GL's own GLSL vertex programs, Figure 7 among them, on the object-space vertices"},
    {VertexStage::Recorded, "recorded", "the emulation's float32 results, uploaded"},
};
constexpr const auto& named_values(VertexStage) { return kVertexStageTable; }
static_assert(names_are_unique<VertexStage>());
std::string_view to_string(VertexStage s);
std::optional<VertexStage> vertex_stage_from_string(std::string_view name);

// The vertex shader's source: `program`'s (nullopt: pass-through) with
// `arithmetic`; with `clip_distance`, it also writes gl_ClipDistance[0], the
// distance to the depth plane that still clips where one side is clamped
// through GL_DEPTH_CLAMP (gl::one_sided_depth_clamp on a driver without
// GL_AMD_depth_clamp_separate; render/draw_state.hpp).
std::string glsl_vertex_shader(std::optional<gl::VertexProgram> program, gl::Arithmetic arithmetic,
                               bool clip_distance = false);

// What to upload for one draw, and with which program.
struct ShadowProgramUse {
  unsigned program = 0;
  const float* vertices = nullptr;  // 4 floats each, attribute 0
  std::size_t count = 0;
};

// Every vertex program with one fragment shader, compiled on first use.
class ShadowPrograms {
 public:
  // `fragment_source` may read `in vec3 colour_v`; `what` names the programs in errors.
  ShadowPrograms(std::string fragment_source, std::string what);
  ~ShadowPrograms();
  ShadowPrograms(const ShadowPrograms&) = delete;
  ShadowPrograms& operator=(const ShadowPrograms&) = delete;

  // glUseProgram of the program that gives `d`'s vertices under `stage`, its
  // uniforms set; returns it with the vertices to upload as attribute 0.
  // `clip_distance`: the variant that writes gl_ClipDistance[0] for d.state's
  // unclamped depth plane (glsl_vertex_shader).
  ShadowProgramUse use(const gl::DrawCall& d, VertexStage stage, bool clip_distance = false);
  // Compiles and links the program `d` needs under `stage` now (not during a timed frame).
  void prepare(const gl::DrawCall& d, VertexStage stage, bool clip_distance = false);

  // The GL's gl_Position for each of `d`'s vertices under VertexStage::Glsl,
  // captured by transform feedback with rasterization discarded: what the
  // GPU's program computed, to hold against d.clip_vertices.
  std::vector<gl::Vec4f> capture(const gl::DrawCall& d);

 private:
  unsigned program(std::optional<gl::VertexProgram> p, gl::Arithmetic a, bool clip_distance);
  std::string fragment_source_, what_;
  std::array<unsigned, 16> programs_{};  // [1 + program][arithmetic][clip distance]: 0 pass-through
  unsigned capture_buffer_ = 0, capture_vertices_ = 0, capture_array_ = 0, capture_framebuffer_ = 0,
           capture_target_ = 0;
};

}  // namespace nearcap::render
