// nearcap/analysis/near_rectangle_pyramid.hpp — does an occluder triangle
// meet the part of the view pyramid between the eye and the near plane?
//
// The near-rectangle pyramid of a frustum: the points t q, q on the near
// rectangle (z = -near, x in [left, right], y in [bottom, top], camera
// space) and 0 < t < 1; closed here (its boundary, the eye included, counts
// as meeting), so that a decision on it is conservative.  It is the convex
// polyhedron of six half-spaces:
//     near x + left z >= 0,   -near x - right z >= 0,
//     near y + bottom z >= 0, -near y - top z >= 0,
//     z + near >= 0,          -z >= 0
// (the last implied by the four sides, left < right and bottom < top).
// A view ray (inside the view pyramid, past the eye) meets an occluder in
// front of the near plane exactly where the occluder meets this pyramid;
// AtomicZP's candidate condition (docs/atomiczp.md, "Where it is right")
// is that no occluder triangle does.
//
// Decided exactly: each vertex's side of each plane is filtered
// (BoundedDouble, then rationals); a triangle wholly outside one half-space
// is clear; the others are clipped against the six half-spaces over
// rationals (Sutherland-Hodgman, closed half-spaces), and meet the pyramid
// where anything is left.
#pragma once

#include <array>
#include <cstddef>

#include "nearcap/exact/camera_space.hpp"

namespace nearcap::analysis {

// Triangle (a, b, c) of occluder o of `cs` (vertex indices) against the
// near-rectangle pyramid of `frustum` (the frustum the frame is drawn with;
// its bounds and near are exact doubles).
bool triangle_meets_near_rectangle_pyramid(const CameraSpaceScene& cs, std::size_t o,
                                           const std::array<VertexIndex, 3>& triangle, const Frustum& frustum);

// The same for a triangle given by its exact camera-space vertices.
bool triangle_meets_near_rectangle_pyramid(const std::array<RationalVec3, 3>& triangle, const Frustum& frustum);

// What occluder_clear_of_near_rectangle_pyramid looked at before it decided:
// the triangles it reached (it stops at the first that meets the pyramid),
// those of them across the slab -near <= z < 0 (tested against the pyramid),
// and those of the tested ones that the vertices' filtered sides left to the
// rational clip.
struct NearRectanglePyramidWork {
  std::size_t triangles = 0;
  std::size_t tested = 0;
  std::size_t clipped = 0;
};

// Whether no triangle of occluder o of `cs` meets the near-rectangle pyramid
// of `frustum`, decided exactly.  First, per vertex: a triangle wholly
// beyond the near plane (every vertex z < -near) or wholly on or behind the
// eye's plane (every vertex z >= 0) is clear; the others are tested as
// triangle_meets_near_rectangle_pyramid tests them, each vertex's place and
// sides decided once for all its triangles.  `work`, where given, receives
// what it looked at (added to).
bool occluder_clear_of_near_rectangle_pyramid(const CameraSpaceScene& cs, std::size_t o, const Frustum& frustum,
                                              NearRectanglePyramidWork* work = nullptr);

}  // namespace nearcap::analysis
