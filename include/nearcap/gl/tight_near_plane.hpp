// nearcap/gl/tight_near_plane.hpp — the camera's near plane pushed out
// towards the scene: the other cure, beside reversed-Z, for near planes so
// small that the depth buffer cannot separate the scene's surfaces.
//
// The near plane decides nothing the viewer sees as long as no scene point
// in view lies in front of it, so an engine may move it out to the nearest
// such point (as engines fit near and far planes to the scene's bounds).
// Here: d = the smallest camera-space depth (-z) of the scene's triangles
// clipped, in double, to the view pyramid (the four side planes through the
// eye, each moved out by half a percent of the window's size, and z < 0;
// the far plane ignored), and the near plane
// moves to d / 2 when that is farther than the scene's; left, right, bottom
// and top scale with it, so the field of view and every pixel's ray stay the
// same.  The half margin is many orders of magnitude above double's
// rounding, so no point in view is clipped: the frame sees what the scene's
// camera sees and the exact reference (for the scene's camera) judges its
// shadow status; only the near-cap (ZP+) is a different one.
#pragma once

#include <optional>
#include <string_view>

#include "nearcap/named_values.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap::gl {

enum class NearPlane {
  Scene,  // the scene file's
  Tight,  // half the depth of the nearest point in view, when farther
};
inline constexpr NamedValue<NearPlane> kNearPlaneTable[] = {
    {NearPlane::Scene, "scene", "the scene file's"},
    {NearPlane::Tight, "tight",
     "moved out to half the depth of the nearest point in view, when farther: the same image, more depth precision"},
};
constexpr const auto& named_values(NearPlane) { return kNearPlaneTable; }
static_assert(names_are_unique<NearPlane>());
inline std::string_view to_string(NearPlane p) { return name_of(p); }
inline std::optional<NearPlane> near_plane_from_string(std::string_view name) { return value_named<NearPlane>(name); }

// The scene camera's frustum with the tight near plane: the same frustum
// when no triangle is in view or half the nearest depth is not beyond the
// scene's near plane (it never moves nearer the eye).
Frustum tight_frustum(const Scene& scene);

}  // namespace nearcap::gl
