// nearcap/gl/shadow_vertex_programs.hpp — the vertex stage of every shadow
// pass, emulated in float32 with the operation order of the GLSL source.
//
// Input vertices are object-space positions with the w code of the paper's
// Figure 7 (ShadowVertex).  Matrices are what the application uploads:
//   modelview_projection = P * MV (float32 product: gl_ModelViewProjectionMatrix;
//                          every camera pass, the depth pre-pass included, uses
//                          this one matrix so that shadow sides and the surfaces
//                          they start on are transformed identically);
//   light_modelview      = M_l * MV (float32 product);
//   light_projection     = P_l;
//   light_position       = the light in object space (w = 1), float32.
// Each matrix-vector product is `transform` (float_transforms.hpp) with the
// chosen Arithmetic: products summed left to right, separately rounded or fused.
#pragma once

#include <string_view>
#include <vector>

#include "nearcap/gl/float_transforms.hpp"

namespace nearcap::gl {

// An object-space vertex with Figure 7's w: 1 in place, 0 extruded to infinity
// away from the light, 2 in place and nailed, 4 extruded and nailed.
struct ShadowVertex {
  float x = 0, y = 0, z = 0, w = 1;
};

struct ShadowUniforms {
  Mat4f modelview_projection;
  Mat4f light_modelview;
  Mat4f light_projection;
  Vec4f light_position;  // object space
  Arithmetic arithmetic = Arithmetic::Separate;
  // The camera's depth mapping: which clip plane is its near plane (Figure 7's test and counterparts).
  DepthMapping depth_mapping = DepthMapping::Standard;
};

// The plain program (Z-pass, Z-fail, ZP+ as published): w = 0 extrudes,
// anything else is the point (x, y, z, 1).
Vec4f extrusion_program(const ShadowUniforms& u, const ShadowVertex& v);
// What that program transforms: (x, y, z, 1), or (x - light, 0) for w = 0;
// extrusion_program(u, v) is transform(u.modelview_projection, this).
Vec4f extrusion_input(const ShadowUniforms& u, const ShadowVertex& v);

// Figure 7, line by line: extrude for w = 0 or 4, stick for w = 2, transform by
// the camera; a movable vertex (w < 1.5) that the near plane clips
// (w_clip <= 0 or z_clip < -w_clip) is re-transformed through the light
// frustum and pushed onto the near plane (z = -w): its near-cap counterpart.
// With the reversed depth mapping the test is z_clip > w_clip and the
// counterpart's z is w.
Vec4f figure7_program(const ShadowUniforms& u, const ShadowVertex& v);

// The near-cap pass: P_l * (light_modelview * (x, y, z, 1)), the two products
// of Figure 7's lines 28-29, so a counterpart and the cap's own vertex agree
// bit for bit.
Vec4f near_cap_program(const ShadowUniforms& u, const ShadowVertex& v);

// The three programs by name, for what runs them elsewhere (the real GL's
// GLSL versions, render/glsl_shadow_programs.hpp): "extrusion", "figure7",
// "near-cap".
enum class VertexProgram { Extrusion, Figure7, NearCap };
std::string_view to_string(VertexProgram p);
Vec4f run_vertex_program(VertexProgram p, const ShadowUniforms& u, const ShadowVertex& v);
// The same on each of `inputs`, in order (the programs inlined into one loop).
std::vector<Vec4f> run_vertex_program(VertexProgram p, const ShadowUniforms& u,
                                      const std::vector<ShadowVertex>& inputs);

}  // namespace nearcap::gl
