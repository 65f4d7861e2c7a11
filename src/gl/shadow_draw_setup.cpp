// The frame renderer's per-object setup, vertex programs and stencil states
// (see shadow_draw_setup.hpp).
#include "shadow_draw_setup.hpp"

#include <glm/glm.hpp>

#include <array>
#include <utility>

#include "glm_affine.hpp"
#include "nearcap/check.hpp"

namespace nearcap::gl::draw_setup {

Vec4f light_in_object_space(const SceneObject& obj, const Vec3d& light) {
  const glm::dvec4 p = glm::inverse(to_glm(obj.object_to_world)) * glm::dvec4(light.x, light.y, light.z, 1.0);
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), 1.0f};
}

float determinant3(const Mat4f& m) {
  return m.at(0, 0) * (m.at(1, 1) * m.at(2, 2) - m.at(1, 2) * m.at(2, 1)) -
         m.at(0, 1) * (m.at(1, 0) * m.at(2, 2) - m.at(1, 2) * m.at(2, 0)) +
         m.at(0, 2) * (m.at(1, 0) * m.at(2, 1) - m.at(1, 1) * m.at(2, 0));
}

Mat4f identity_matrix() {
  Mat4f m;
  for (int k = 0; k < 4; ++k) m.at(k, k) = 1.0f;
  return m;
}

Mat4f composed_light_matrix(const LightFrustum& lf, const Affine3d& view, const Affine3d& object_to_world) {
  std::array<std::array<double, 4>, 4> mv{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      double v = c == 3 ? view.rows[r][3] : 0.0;
      for (int k = 0; k < 3; ++k) v += view.rows[r][k] * object_to_world.rows[k][c];
      mv[r][c] = v;
    }
  mv[3][3] = 1.0;
  Mat4f out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      double v = 0;
      for (int k = 0; k < 4; ++k) v += lf.composed[r][k] * mv[k][c];
      out.at(r, c) = static_cast<float>(v);
    }
  return out;
}

DrawState oriented(DrawState s, bool mirrored) {
  if (!mirrored) return s;
  std::swap(s.front, s.back);
  if (s.cull == CullFace::Back)
    s.cull = CullFace::Front;
  else if (s.cull == CullFace::Front)
    s.cull = CullFace::Back;
  return s;
}

DrawCall program_draw(DrawPass pass, std::vector<Vec4f> clip, const DrawState& s, VertexProgram program,
                      GeometryPart part, const std::vector<ShadowVertex>& in, const ShadowUniforms& u) {
  return {pass, std::move(clip), s, VertexProgramRun{program, part, in, u}};
}

DrawState zpass_state() {
  DrawState s;
  s.front = kCountOnPass;
  s.back = kUncountOnPass;
  return s;
}
// AtomicZP's volumes: Z-pass counting with GL_DEPTH_CLAMP, so that nothing
// is clipped at the near plane (the crossings between the eye and the near
// plane pass the depth test at the clamped depth) nor at the far one.
DrawState atomiczp_state(std::uint8_t eye_count) {
  DrawState s = zpass_state();
  s.depth_clamp_near = true;
  s.depth_clamp_far = true;
  s.stencil_clear = eye_count;
  return s;
}
DrawState zfail_state(ZFailFar far) {
  DrawState s;
  s.front = kUncountOnFail;
  s.back = kCountOnFail;
  s.depth_clamp_near = far == ZFailFar::DepthClamp;
  s.depth_clamp_far = far == ZFailFar::DepthClamp || far == ZFailFar::DepthClampFar;
  s.far_first = far == ZFailFar::FarCap;
  return s;
}
DrawState preload_state() {
  DrawState s;
  s.front = kUncountAlways;
  s.back = kCountAlways;
  return s;
}

DrawState volume_state(VolumeCount c, ZFailFar far, std::uint8_t eye_clear) {
  switch (c) {
    case VolumeCount::ZPass:
      return zpass_state();
    case VolumeCount::ZPassClamped:
      return atomiczp_state(eye_clear);
    case VolumeCount::ZFail:
      return zfail_state(far);
    case VolumeCount::PreloadAlways:
      break;
  }
  return preload_state();
}

GeometryPart geometry_part(VolumeGeometry g) {
  switch (g) {
    case VolumeGeometry::Sides:
      return GeometryPart::Sides;
    case VolumeGeometry::Corrective:
      return GeometryPart::Corrective;
    case VolumeGeometry::LightCap:
      return GeometryPart::LightCap;
    case VolumeGeometry::DarkCap:
      return GeometryPart::DarkCap;
    case VolumeGeometry::FarPlaneCap:
      break;
  }
  NEARCAP_CHECK(g != VolumeGeometry::FarPlaneCap);  // built on the CPU, from no geometry part
  return GeometryPart::Mesh;
}

bool wants_infinite(FarPlane f, const EmulationSettings& settings) {
  switch (f) {
    case FarPlane::FiniteNeeded:
      return false;
    case FarPlane::InfiniteWanted:
      return true;
    case FarPlane::ZPassChoice:
      return settings.zpass_far == ZPassFar::Infinite;
    case FarPlane::ZFailChoice:
      break;
  }
  return settings.zfail_far == ZFailFar::Infinite;
}
}  // namespace nearcap::gl::draw_setup
