// nearcap/exact/segment_crossing.hpp — does the segment from a light to a sample point
// cross a triangle?  And the near-cap count built on it.
//
// The segment is [l, p_eps]: l the light (fixed, exact), p_eps a sample point
// under nearcap's symbolic perturbation (perturbation.hpp).  It crosses
// triangle (a, b, c) when l lies strictly on one side of the triangle's plane,
// p_eps strictly on the other, and the line l p_eps passes strictly inside the
// triangle: orient(l, p, a, b), orient(l, p, b, c), orient(l, p, c, a) share a
// non-zero sign.  Each is an affine form in p, so the perturbation decides every
// tie at p.  A triangle whose plane holds the light (Facing::EdgeOn) is never
// crossed: the segment can only touch it at l, and lights on occluders are
// rejected when the scene is loaded.
#pragma once

#include <cstdint>

#include <cstddef>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/light_facing.hpp"

namespace nearcap {

// A sample point: certified estimate and exact value (both camera space).
struct SamplePoint {
  BoundedVec3 approx;
  RationalVec3 exact;
};

// `facing` is triangle f's facing for this light (Front or Back; EdgeOn -> false).
bool segment_crosses_triangle(const CameraSpaceScene& scene, std::size_t o, FaceIndex f, std::size_t light,
                              Facing facing, const SamplePoint& p, FilterStats* stats);

// The exact near-cap count at a point p of the near plane: the number of
// light-front-facing occluder triangles (all occluders of the scene) crossed by
// [l, p_eps].  Brute force over every front-facing triangle: the oracle that the
// arrangement and the accelerated per-pixel reference are tested against.
// `facing[o]` must hold light_facing(scene, o, light) for every occluder o (and
// may be empty for receivers).
std::size_t near_cap_count_brute_force(const CameraSpaceScene& scene, std::size_t light,
                                       const std::vector<std::vector<Facing>>& facing, const SamplePoint& p,
                                       FilterStats* stats);

// The camera-space near-plane point of pixel (i, j): column i from the left,
// row j from the bottom; x = left + (i + 1/2)/W (right - left), y likewise,
// z = -near.  Exact and certified estimate.
SamplePoint pixel_centre(const Frustum& frustum, int width, int height, int i, int j);

// A point of the window at dyadic window coordinates (x / 2^shift, y / 2^shift)
// (pixel (i, j) covers [i, i+1] x [j, j+1]; its centre is (2i+1, 2j+1, shift 1)).
// The sub-pixel sample points of the crack distance (crack_distance.hpp).
struct WindowPoint {
  std::int64_t x = 1, y = 1;  // |x|, |y| < 2^53 / width, height: exact doubles
  int shift = 1;              // 0 <= shift <= 30
};
inline WindowPoint window_pixel_centre(int i, int j) { return {2 * std::int64_t{i} + 1, 2 * std::int64_t{j} + 1, 1}; }
// Its camera-space near-plane point: x = left + X (right - left) / (W 2^shift).
BoundedVec3 window_point_estimate(const Frustum& frustum, int width, int height, const WindowPoint& p);
// The camera-space step of a window offset (X, Y) at that shift:
// (X (right - left) / (W 2^shift), Y (top - bottom) / (H 2^shift), 0), the
// estimate's own terms (a point is (left, bottom, -near) plus its offset).
BoundedVec3 window_offset_estimate(const Frustum& frustum, int width, int height, const WindowPoint& offset);
RationalVec3 window_point_exact(const Frustum& frustum, int width, int height, const WindowPoint& p);
// Its two halves, for callers that want the rational only on demand.
BoundedVec3 pixel_centre_estimate(const Frustum& frustum, int width, int height, int i, int j);
RationalVec3 pixel_centre_exact(const Frustum& frustum, int width, int height, int i, int j);

}  // namespace nearcap
