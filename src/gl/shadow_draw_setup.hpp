// gl/shadow_draw_setup.hpp — what the frame renderer (shadow_methods.cpp)
// draws with, per object and per method: the object's uniforms and
// orientation, the draw calls that record a vertex program run, and each
// volume count's stencil state (private to gl/; not installed).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "nearcap/gl/engine_classification.hpp"
#include "nearcap/gl/float_transforms.hpp"
#include "nearcap/gl/light_frustum.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "nearcap/gl/shadow_methods.hpp"
#include "nearcap/gl/shadow_plan.hpp"
#include "nearcap/gl/shadow_vertex_programs.hpp"
#include "nearcap/gl/shadow_volume_geometry.hpp"
#include "nearcap/gl/volume_bounds.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::gl::draw_setup {

// What the application prepares for one object.
struct ObjectSetup {
  ShadowUniforms uniforms;
  bool mirrored = false;  // the modelview reverses orientation: glFrontFace(GL_CW)
  bool occluder = false;
  const EngineSilhouette* silhouette = nullptr;  // in the batch's shared work
  const ShadowVolumeGeometry* geometry = nullptr;
  bool case_d = false;
  std::optional<VolumeBounds> bounds;  // EmulationSettings::volume_culling
  std::size_t index = 0;               // in the scene's objects
};

Vec4f light_in_object_space(const SceneObject& obj, const Vec3d& light);
float determinant3(const Mat4f& m);
Mat4f identity_matrix();
// (P_l M_l) * view * object_to_world, all in double, rounded to float32 once.
Mat4f composed_light_matrix(const LightFrustum& lf, const Affine3d& view, const Affine3d& object_to_world);
// `s` with its faces swapped where the modelview reverses orientation.
DrawState oriented(DrawState s, bool mirrored);

// A recorded draw call whose vertices `program` made from `in`.
DrawCall program_draw(DrawPass pass, std::vector<Vec4f> clip, const DrawState& s, VertexProgram program,
                      GeometryPart part, const std::vector<ShadowVertex>& in, const ShadowUniforms& u);

inline constexpr StencilOps kCountOnPass{StencilOp::Keep, StencilOp::IncrementWrap};
inline constexpr StencilOps kUncountOnPass{StencilOp::Keep, StencilOp::DecrementWrap};
inline constexpr StencilOps kCountOnFail{StencilOp::IncrementWrap, StencilOp::Keep};
inline constexpr StencilOps kUncountOnFail{StencilOp::DecrementWrap, StencilOp::Keep};
inline constexpr StencilOps kCountAlways{StencilOp::IncrementWrap, StencilOp::IncrementWrap};
inline constexpr StencilOps kUncountAlways{StencilOp::DecrementWrap, StencilOp::DecrementWrap};

DrawState zpass_state();
// The state a plan's volume draw counts with; `far`: the frame's Z-fail far
// plane for the occluder, `eye_clear`: AtomicZP's stencil clear.
DrawState volume_state(VolumeCount c, ZFailFar far, std::uint8_t eye_clear);
GeometryPart geometry_part(VolumeGeometry g);
// Whether a method of the plan wants the infinite far plane under `settings`.
bool wants_infinite(FarPlane f, const EmulationSettings& settings);

}  // namespace nearcap::gl::draw_setup
