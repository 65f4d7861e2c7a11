// The shadow passes' vertex programs (see shadow_vertex_programs.hpp).
#include "nearcap/gl/shadow_vertex_programs.hpp"

namespace nearcap::gl {

Vec4f extrusion_input(const ShadowUniforms& u, const ShadowVertex& v) {
  if (v.w == 0.0f) return {v.x - u.light_position.x, v.y - u.light_position.y, v.z - u.light_position.z, 0.0f};
  return {v.x, v.y, v.z, 1.0f};
}

Vec4f extrusion_program(const ShadowUniforms& u, const ShadowVertex& v) {
  return transform(u.modelview_projection, extrusion_input(u, v), u.arithmetic);
}

Vec4f figure7_program(const ShadowUniforms& u, const ShadowVertex& v) {
  Vec4f eye{v.x, v.y, v.z, v.w};                                                                // line 5
  if (v.w == 0.0f || v.w == 4.0f) {                                                             // line 7
    eye = {eye.x - u.light_position.x, eye.y - u.light_position.y, eye.z - u.light_position.z,  // line 9
           0.0f};                                                                               // line 10
  }
  if (v.w == 2.0f) eye.w = 1.0f;                               // lines 13-15
  eye = transform(u.modelview_projection, eye, u.arithmetic);  // line 18
  const bool standard = u.depth_mapping == DepthMapping::Standard;
  if (v.w < 1.5f && (eye.w <= 0.0f || (standard ? eye.z < -eye.w : eye.z > eye.w))) {  // lines 21-23
    eye = near_cap_program(u, v);                                                      // lines 26-29
    eye.z = standard ? -eye.w : eye.w;                                                 // line 30
  }
  return eye;
}

Vec4f near_cap_program(const ShadowUniforms& u, const ShadowVertex& v) {
  const Vec4f light_frame = transform(u.light_modelview, {v.x, v.y, v.z, 1.0f}, u.arithmetic);
  return transform(u.light_projection, light_frame, u.arithmetic);
}

std::string_view to_string(VertexProgram p) {
  switch (p) {
    case VertexProgram::Extrusion:
      return "extrusion";
    case VertexProgram::Figure7:
      return "figure7";
    case VertexProgram::NearCap:
      return "near-cap";
  }
  return "?";
}

Vec4f run_vertex_program(VertexProgram p, const ShadowUniforms& u, const ShadowVertex& v) {
  switch (p) {
    case VertexProgram::Extrusion:
      return extrusion_program(u, v);
    case VertexProgram::Figure7:
      return figure7_program(u, v);
    case VertexProgram::NearCap:
      return near_cap_program(u, v);
  }
  return {};
}

}  // namespace nearcap::gl
