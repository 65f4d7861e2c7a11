// nearcap/gl/shadow_plan.hpp — what each shadow method draws, as one table:
// per (method, near-cap kind) the projection it needs, its per-frame pass
// before the volumes, each occluder's volume draws (which geometry, which
// vertex program, how they count, how they clamp), and when an occluder
// switches to Z-fail.  The software pipeline (shadow_methods.cpp) walks it;
// the pass kinds name the draws for timing (render/pass_kinds.hpp,
// analysis/device_profile.hpp).
//
// The rows (shadow_methods.hpp describes each method):
//   method            cap            far plane          volume draws                       Z-fail switch
//   zpass             -              zpass_far          sides                              never
//   zfail             -              zfail_far          sides, light cap, dark cap, ZF+    never
//   zpplus            light frustum  finite (needed)    sides                              no light frustum
//   zpplus            clipped sides  zpass_far          sides                              never
//   zpplus-corrected  light frustum  finite (needed)    Figure 7 sides, corrective quads   no light frustum, case D
//   zpplus-corrected  clipped sides  zpass_far          sides                              never
//   preload           -              infinite (wanted)  closed volume always, then zpass   never
//   atomiczp          eye count      zpass_far          sides, clamped                     never
// An occluder that switches draws the zfail row's volume with the switch's
// clamp (EmulationSettings::switch_clamp) and is left out of the near-cap
// pass.
#pragma once

#include <array>
#include <cstddef>

#include "nearcap/gl/light_frustum.hpp"
#include "nearcap/gl/pass_kind.hpp"
#include "nearcap/gl/pipeline.hpp"
#include "nearcap/gl/shadow_methods.hpp"

namespace nearcap::gl {

// A ZP+ method's near-cap: through the light frustum (section 3; the
// light-frustum projections of LightProjection), or the fan over the edges
// the near plane's clipping leaves of the closed volume
// (LightProjection::ClippedSides, near_plane_cap.hpp).
enum class NearCapKind { LightFrustum, ClippedSides };
NearCapKind near_cap_kind(LightProjection p);

// What a method asks of the frame's camera projection.  A frame takes the
// finite frustum when one of its occluders needs it, else the infinite far
// plane when one wants it, else the finite one.
enum class FarPlane {
  FiniteNeeded,    // ZP+'s light-frustum cap and case-D switch (section 5.2)
  InfiniteWanted,  // preload
  ZPassChoice,     // EmulationSettings::zpass_far
  ZFailChoice,     // EmulationSettings::zfail_far: infinite for ZFailFar::Infinite
};

// The per-frame pass between the depth pre-pass and the volumes.
enum class CapPass {
  None,
  NearCap,   // ZP+'s near-cap pass, of the row's NearCapKind
  EyeCount,  // AtomicZP: the stencil cleared to the eye count (eye_count.hpp)
};

// How a volume draw counts into the stencil buffer.
enum class VolumeCount {
  ZPass,          // front +1, back -1 on depth pass
  ZPassClamped,   // the same with GL_DEPTH_CLAMP and the eye count's clear (AtomicZP)
  ZFail,          // back +1, front -1 on depth fail, clamped as the frame's Z-fail far plane says
  PreloadAlways,  // front -1, back +1 whatever the depth test says (preload's first volume)
};

// What a volume draw draws: a part of the shadow volume's geometry through
// a vertex program, or ZF+'s far-plane cap (built on the CPU from the
// clip-space vertices of the row's earlier draws of the occluder; drawn
// only where the Z-fail far plane is ZFailFar::FarCap and finite).
enum class VolumeGeometry { Sides, Corrective, LightCap, DarkCap, FarPlaneCap };

struct VolumeDraw {
  PassKind kind = PassKind::Sides;
  VolumeGeometry geometry = VolumeGeometry::Sides;
  VertexProgram program = VertexProgram::Extrusion;
  VolumeCount count = VolumeCount::ZPass;
};

// When an occluder of the method draws the zfail row's volume instead.
enum class ZFailSwitch {
  Never,
  NoLightFrustum,         // the light lies in the near plane (ShadowFrame::fallback)
  NoLightFrustumOrCaseD,  // that, or the occluder has a case-D quad (section 5.2)
};

// Volume culling (volume_bounds.hpp) of the method's draws.
enum class CullingUse {
  ScissorAndDepthBounds,
  NoDepthBoundsAtNearPlane,  // Z-pass: no depth bounds where the region meets the near plane
  None,                      // AtomicZP: its volumes count between the eye and the near plane too
};

struct ShadowPlan {
  ShadowMethod method;
  NearCapKind near_cap;  // with CapPass::NearCap: the row's cap kind; unused otherwise
  FarPlane far_plane;
  CapPass cap_pass;
  std::array<VolumeDraw, 6> draws;  // the first draw_count, in order, per occluder
  std::size_t draw_count;
  ZFailSwitch zfail_switch;
  CullingUse culling;
};

// The row of `method` with the near-cap kind of `projection`.
const ShadowPlan& shadow_plan(ShadowMethod method, LightProjection projection);

}  // namespace nearcap::gl
