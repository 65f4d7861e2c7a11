// The shadow passes' vertex programs (see shadow_vertex_programs.hpp).
#include "nearcap/gl/shadow_vertex_programs.hpp"

#include "float_transform_inline.hpp"

namespace nearcap::gl {

namespace inl = inline_transform;

Vec4f extrusion_input(const ShadowUniforms& u, const ShadowVertex& v) {
  if (v.w == 0.0f) return {v.x - u.light_position.x, v.y - u.light_position.y, v.z - u.light_position.z, 0.0f};
  return {v.x, v.y, v.z, 1.0f};
}

namespace {

// The programs, inlined into the loops below.
inline Vec4f extrusion(const ShadowUniforms& u, const ShadowVertex& v) {
  return inl::transform(u.modelview_projection, extrusion_input(u, v), u.arithmetic);
}

inline Vec4f near_cap(const ShadowUniforms& u, const ShadowVertex& v) {
  const Vec4f light_frame = inl::transform(u.light_modelview, {v.x, v.y, v.z, 1.0f}, u.arithmetic);
  return inl::transform(u.light_projection, light_frame, u.arithmetic);
}

inline Vec4f figure7(const ShadowUniforms& u, const ShadowVertex& v) {
  Vec4f eye{v.x, v.y, v.z, v.w};                                                                // line 5
  if (v.w == 0.0f || v.w == 4.0f) {                                                             // line 7
    eye = {eye.x - u.light_position.x, eye.y - u.light_position.y, eye.z - u.light_position.z,  // line 9
           0.0f};                                                                               // line 10
  }
  if (v.w == 2.0f) eye.w = 1.0f;                                    // lines 13-15
  eye = inl::transform(u.modelview_projection, eye, u.arithmetic);  // line 18
  const bool standard = u.depth_mapping == DepthMapping::Standard;
  if (v.w < 1.5f && (eye.w <= 0.0f || (standard ? eye.z < -eye.w : eye.z > eye.w))) {  // lines 21-23
    eye = near_cap(u, v);                                                              // lines 26-29
    eye.z = standard ? -eye.w : eye.w;                                                 // line 30
  }
  return eye;
}

template <class Program>
std::vector<Vec4f> run_each(const ShadowUniforms& u, const std::vector<ShadowVertex>& inputs, Program program) {
  std::vector<Vec4f> out(inputs.size());
  for (std::size_t k = 0; k < inputs.size(); ++k) out[k] = program(u, inputs[k]);
  return out;
}

}  // namespace

Vec4f extrusion_program(const ShadowUniforms& u, const ShadowVertex& v) { return extrusion(u, v); }
Vec4f figure7_program(const ShadowUniforms& u, const ShadowVertex& v) { return figure7(u, v); }
Vec4f near_cap_program(const ShadowUniforms& u, const ShadowVertex& v) { return near_cap(u, v); }

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

std::vector<Vec4f> run_vertex_program(VertexProgram p, const ShadowUniforms& u,
                                      const std::vector<ShadowVertex>& inputs) {
  switch (p) {
    case VertexProgram::Extrusion:
      return run_each(u, inputs, extrusion);
    case VertexProgram::Figure7:
      return run_each(u, inputs, figure7);
    case VertexProgram::NearCap:
      return run_each(u, inputs, near_cap);
  }
  return {};
}

}  // namespace nearcap::gl
