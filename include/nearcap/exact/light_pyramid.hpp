// nearcap/exact/light_pyramid.hpp — the largest admissible l_near of ZP+'s
// light frustum, exactly.
//
// The near-cap pass draws the occluders through a frustum with its apex at
// the light l and its far rectangle the camera's near rectangle (camera space,
// z = -near).  Its near plane, parallel to the near rectangle at axial
// distance l_near from the light, clips away every occluder point nearer to
// the light than l_near; the cap is right only if no occluder point of the
// light pyramid (l and the near rectangle, closed) lies there.  So the largest
// admissible l_near is
//     L* = min { a(P) : P an occluder point in the pyramid },
//     a(P) = alpha (l_z - P_z),  alpha = sign(l_z + near)  (the axial distance),
// the minimum of a linear function over the convex polygons (triangle ∩
// pyramid), attained at one of their vertices: a triangle vertex inside the
// pyramid, a triangle edge crossing a side plane, or a pyramid edge (the ray
// from l through a corner of the rectangle) piercing the triangle.
//
// Computed by clipping each occluder triangle against the pyramid's four side
// planes over rationals (the camera-space vertices and light are exact,
// camera_space.hpp), after a double-precision pass that discards triangles
// certainly outside the pyramid and visits the others nearest first, so that
// only the few that can hold the minimum are clipped exactly.  The paper's
// l_far d / d_max (d the distance to the nearest occluder) is admissible by
// construction: never above L* (tests/light_pyramid_test.cpp).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "nearcap/exact/camera_space.hpp"

namespace nearcap {

struct AdmissibleLightNear {
  std::optional<Rational> l_near;   // L*; nothing when no occluder point lies in the pyramid
  Rational l_far;                   // alpha (l_z + near) > 0
  std::size_t exact_triangles = 0;  // triangles clipped over rationals
};

// Throws Error(Degenerate) when the light lies in the near plane (l_far = 0).
AdmissibleLightNear max_admissible_light_near(const CameraSpaceScene& scene, std::size_t light);

// Per scene object: does the occluder hold a point of the light pyramid (the
// light excluded, the rest closed: the side planes and the near rectangle)?
// Exactly when some point of the near rectangle sees the light through the
// occluder, so an occluder that meets none has an empty near-cap and Z-pass
// is exact for it.  False for receivers.  Decided like the above: a double
// cull, then exact clipping of the remaining triangles until one meets.
// Throws Error(Degenerate) when the light lies in the near plane.
std::vector<bool> occluders_meeting_light_pyramid(const CameraSpaceScene& scene, std::size_t light);

}  // namespace nearcap
