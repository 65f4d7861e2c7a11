// The shadow methods' plan, one row per method and near-cap kind (see
// shadow_plan.hpp).
#include "nearcap/gl/shadow_plan.hpp"

#include "nearcap/check.hpp"

namespace nearcap::gl {
namespace {

// The closed volume (sides, light cap, dark cap at infinity) counted `c`.
constexpr VolumeDraw sides(VolumeCount c) {
  return {PassKind::Sides, VolumeGeometry::Sides, VertexProgram::Extrusion, c};
}
constexpr VolumeDraw light_cap(VolumeCount c) {
  return {PassKind::LightCap, VolumeGeometry::LightCap, VertexProgram::Extrusion, c};
}
constexpr VolumeDraw dark_cap(VolumeCount c) {
  return {PassKind::DarkCap, VolumeGeometry::DarkCap, VertexProgram::Extrusion, c};
}

constexpr ShadowPlan kPlans[] = {
    {ShadowMethod::ZPass,
     NearCapKind::LightFrustum,
     FarPlane::ZPassChoice,
     CapPass::None,
     {sides(VolumeCount::ZPass)},
     1,
     ZFailSwitch::Never,
     CullingUse::NoDepthBoundsAtNearPlane},
    // The far-plane cap closes what the far plane clipped of the volume
    // drawn just before it (ZF+).
    {ShadowMethod::ZFail,
     NearCapKind::LightFrustum,
     FarPlane::ZFailChoice,
     CapPass::None,
     {sides(VolumeCount::ZFail), light_cap(VolumeCount::ZFail), dark_cap(VolumeCount::ZFail),
      VolumeDraw{PassKind::DarkCap, VolumeGeometry::FarPlaneCap, VertexProgram::Extrusion, VolumeCount::ZFail}},
     4,
     ZFailSwitch::Never,
     CullingUse::ScissorAndDepthBounds},
    {ShadowMethod::ZPPlus,
     NearCapKind::LightFrustum,
     FarPlane::FiniteNeeded,
     CapPass::NearCap,
     {sides(VolumeCount::ZPass)},
     1,
     ZFailSwitch::NoLightFrustum,
     CullingUse::ScissorAndDepthBounds},
    {ShadowMethod::ZPPlus,
     NearCapKind::ClippedSides,
     FarPlane::ZPassChoice,
     CapPass::NearCap,
     {sides(VolumeCount::ZPass)},
     1,
     ZFailSwitch::Never,
     CullingUse::ScissorAndDepthBounds},
    // Section 5: the Figure 7 program on the sides, and the corrective quads
    // of cases C1 and C2.
    {ShadowMethod::ZPPlusCorrected,
     NearCapKind::LightFrustum,
     FarPlane::FiniteNeeded,
     CapPass::NearCap,
     {VolumeDraw{PassKind::Sides, VolumeGeometry::Sides, VertexProgram::Figure7, VolumeCount::ZPass},
      VolumeDraw{PassKind::Sides, VolumeGeometry::Corrective, VertexProgram::Figure7, VolumeCount::ZPass}},
     2,
     ZFailSwitch::NoLightFrustumOrCaseD,
     CullingUse::ScissorAndDepthBounds},
    // With the clipped-sides cap there is no light frustum, so no case-D
    // switch and no corrective quads: the row is ZP+'s.
    {ShadowMethod::ZPPlusCorrected,
     NearCapKind::ClippedSides,
     FarPlane::ZPassChoice,
     CapPass::NearCap,
     {sides(VolumeCount::ZPass)},
     1,
     ZFailSwitch::Never,
     CullingUse::ScissorAndDepthBounds},
    // Doom 3 BFG's stencil preload: the closed volume counted whatever the
    // depth test says, then again as Z-pass.
    {ShadowMethod::Preload,
     NearCapKind::LightFrustum,
     FarPlane::InfiniteWanted,
     CapPass::None,
     {sides(VolumeCount::PreloadAlways), light_cap(VolumeCount::PreloadAlways), dark_cap(VolumeCount::PreloadAlways),
      sides(VolumeCount::ZPass), light_cap(VolumeCount::ZPass), dark_cap(VolumeCount::ZPass)},
     6,
     ZFailSwitch::Never,
     CullingUse::ScissorAndDepthBounds},
    {ShadowMethod::AtomicZP,
     NearCapKind::LightFrustum,
     FarPlane::ZPassChoice,
     CapPass::EyeCount,
     {sides(VolumeCount::ZPassClamped)},
     1,
     ZFailSwitch::Never,
     CullingUse::None},
};

}  // namespace

NearCapKind near_cap_kind(LightProjection p) {
  return p == LightProjection::ClippedSides ? NearCapKind::ClippedSides : NearCapKind::LightFrustum;
}

const ShadowPlan& shadow_plan(ShadowMethod method, LightProjection projection) {
  const NearCapKind kind = near_cap_kind(projection);
  for (const ShadowPlan& p : kPlans)
    if (p.method == method && (p.cap_pass != CapPass::NearCap || p.near_cap == kind)) return p;
  NEARCAP_CHECK(false);
  return kPlans[0];
}

}  // namespace nearcap::gl
