// nearcap/gl/light_frustum.hpp — ZP+'s light frustum (section 3.1 and 3.2 of
// the paper): the modelview M_l and the projection P_l through which the
// near-cap is rasterized, so that the light frustum's far rectangle is the
// camera's near rectangle.
//
// All in camera space, float32, as an application computes them:
//   Delta   = the light in camera space, view * light (float32 GLM product);
//   alpha   = +1 when the light is on the camera's side of the near plane
//             (Delta.z + near > 0), -1 on the other side; ON the plane there
//             is no light frustum (l_far = 0) and ZP+ must fall back to Z-fail;
//   l_far   = alpha (Delta.z + near), the light's distance to the near plane;
//   M_l     = R_alpha T(-Delta): translation to the light, then the 180-degree
//             rotation about the up axis when alpha = -1 (R = diag(alpha, 1, alpha));
//   l_near  = l_far min(d / d_max, 1/2) (section 3.2; d = distance from the
//             light to the nearest occluder, d_max = largest distance from the
//             light to a corner of the near rectangle, both in camera space),
//             times a scale (1 = the paper's ratio).  The cap at 1/2 is
//             nearcap's and applies whenever d / d_max > 1/2: it keeps
//             l_near < l_far always (d >= d_max would put it at or beyond
//             l_far) and P_l's depth row away from l_near = l_far;
//   P_l     = a named formulation (LightProjection).
// The paper writes P_l for a near rectangle centred on the view axis; for an
// off-centre frustum Delta.x and Delta.y are taken relative to the rectangle's
// centre ((left + right) / 2, (bottom + top) / 2), which is the same matrix
// when the frustum is centred.  Either way the light's NDC x and y of a point
// of the near rectangle equal the camera's, so both passes share a viewport.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "nearcap/gl/float_transforms.hpp"
#include "nearcap/named_values.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::gl {

// How P_l is formed.
enum class LightProjection {
  Paper,         // section 3.1's matrix, entries computed directly in float32
  GlFrustum,     // glFrustum(l, r, b, t, l_near, l_far) of the same pyramid, computed in double, rounded
  Composed,      // P_l * M_l * MV composed in double (section 3.1's P_l, Delta in double) and rounded
                 // to float32 once per object: one uploaded matrix, P_l the identity
  Rebased,       // the same pyramid with its origin moved to the near rectangle's centre: M_l is the
                 // translation by -(cx, cy, -near), and P_l acts on u = v - (cx, cy, -near), which is
                 // small near the near plane, so the shear's large terms (the paper's -2 dx / w times
                 // z' = alpha (v_z - Delta_z)) no longer cancel there:
                 //   x = (2/w) (l_far u_x - alpha dx u_z), y = (2/h) (l_far u_y - alpha dy u_z),
                 //   w_clip = l_far - alpha u_z, z = K (alpha u_z - l_far) + L (the paper's K, L)
  ClippedSides,  // no light frustum at all: the near-cap is the stencil-counted fan over the edges
                 // the clipper leaves in the near plane when it clips the volume's own sides and
                 // caps (gl/near_plane_cap.hpp; in the spirit of Usta et al., HPG 2019); the sides
                 // are the plain Z-pass sides, with no Figure 7 program, corrective quads, case-D
                 // switch or light-in-the-near-plane fallback, so zpplus and zpplus-corrected draw
                 // the same frame.  light_frustum() still computes the paper's M_l and P_l for the
                 // conditioning features; no pass uses them.
};
inline constexpr NamedValue<LightProjection> kLightProjectionTable[] = {
    {LightProjection::Paper, "paper", ""},
    {LightProjection::GlFrustum, "glfrustum", ""},
    {LightProjection::Composed, "composed", "P_l M_l MV in double, rounded once"},
    {LightProjection::Rebased, "rebased", "origin at the near rectangle's centre"},
    {LightProjection::ClippedSides, "clipped-sides",
     "no light frustum: the near-cap is the fan over the edges the clipper leaves in the near plane"},
};
constexpr const auto& named_values(LightProjection) { return kLightProjectionTable; }
static_assert(names_are_unique<LightProjection>());
inline std::string_view to_string(LightProjection p) { return name_of(p); }
inline std::optional<LightProjection> light_projection_from_string(std::string_view name) {
  return value_named<LightProjection>(name);
}

// How l_near is chosen.
enum class LightNearRule {
  PaperRatio,  // l_far * min(d / d_max, 1/2) (section 3.2; the cap is nearcap's)
  ExactMax,    // min(L*, l_far / 2), L* the largest admissible l_near computed exactly
               // (exact/light_pyramid.hpp), rounded down to float32
  NearClamp,   // the paper's own proposal (section 6): the cap pass clamps depth on
               // its near side instead of clipping there, so no occluder is lost
               // whatever l_near is; l_near = l_far / 2 keeps P_l well-conditioned
};
inline constexpr NamedValue<LightNearRule> kLightNearRuleTable[] = {
    {LightNearRule::PaperRatio, "paper-ratio", "l_far min(d / d_max, 1/2)"},
    {LightNearRule::ExactMax, "exact-max", "the largest admissible, exactly, capped at l_far / 2"},
    {LightNearRule::NearClamp, "near-clamp", "depth clamp at the near side"},
};
constexpr const auto& named_values(LightNearRule) { return kLightNearRuleTable; }
static_assert(names_are_unique<LightNearRule>());
inline std::string_view to_string(LightNearRule r) { return name_of(r); }
inline std::optional<LightNearRule> light_near_rule_from_string(std::string_view name) {
  return value_named<LightNearRule>(name);
}

struct LightFrustumChoice {
  LightProjection projection = LightProjection::Paper;
  LightNearRule near_rule = LightNearRule::PaperRatio;
  double near_scale = 1.0;  // l_near multiplied by this: a safety margin below the rule (tuned by the analysis)
};

struct LightFrustum {
  bool defined = false;  // false: the light lies in the near plane (float test), or l_near is not positive
  std::string undefined_reason;
  int alpha = 1;
  Vec4f delta;  // the light in camera space (w = 1)
  float l_near = 0, l_far = 0;
  double d = 0, d_max = 0;    // paper-ratio's inputs (0 for the other rules)
  double admissible = 0;      // exact-max: L* rounded toward zero (infinity: no occluder in the pyramid)
  bool near_clamped = false;  // near-clamp: the cap pass clamps depth at the near side, no near clipping
  Mat4f modelview;            // M_l: camera space -> light frame
  Mat4f projection;           // P_l
  // composed: P_l * M_l in double, row-major (camera space -> the light's clip space).
  std::array<std::array<double, 4>, 4> composed{};
};

// The light frustum of light `light` for the scene's camera and occluders.
LightFrustum light_frustum(const Scene& scene, std::size_t light, const LightFrustumChoice& choice);

// The light's camera-space position in float32, as an application computes it
// (view rounded to float32, times the light rounded to float32).
Vec4f light_in_camera_space(const Scene& scene, std::size_t light);

// The distance from point p (given in world space) to the nearest occluder
// triangle, measured in camera space (where d_max is), in double.
double distance_to_occluders(const Scene& scene, const Vec3d& p);

}  // namespace nearcap::gl
