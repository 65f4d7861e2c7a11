// nearcap/exact/eye_count.hpp — how many of a light's shadow volumes contain
// the eye, decided exactly: the constant AtomicZP (gl/eye_count.hpp) adds to
// depth-clamped Z-pass.
//
// The count is the reference's own (segment_crossing.hpp): the number of
// light-front-facing occluder triangles crossed by [l, e_eps], where e is the
// eye (the camera-space origin) under nearcap's one degeneracy rule
// (perturbation.hpp): an eye exactly on a triangle's plane or on a plane
// through the light and an occluder edge (a side plane of a volume) is
// decided as if nudged first along the view direction (-z), then right, then
// up.  Each test is the sign of an affine form in the eye, filtered, then
// exact.
//
// What the perturbation cannot make right: an eye exactly on a side plane
// sees that plane edge-on, and the points just in front of it differ in
// count across the plane's image, a line through the frame; no one constant
// is right on both sides.  The rule picks the count of the view direction's
// side.  `on_boundary` says that the perturbation decided some test at the
// eye that mattered (a zero value: the eye in the plane of a triangle the
// line eye->light passes through, or on the plane through the light and a
// triangle's edge).  It is conservative: a tie on an edge between two
// light-facing triangles is reported too, although every nudge gives the
// same count there.
#pragma once

#include <cstddef>
#include <vector>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/light_facing.hpp"
#include "nearcap/numeric/filter_stats.hpp"

namespace nearcap {

struct ExactEyeCount {
  std::size_t count = 0;
  bool on_boundary = false;  // a tie at the eye was decided by the perturbation
};

// `facing[o]` must hold light_facing(scene, o, light) for every occluder o
// counted; an empty entry counts nothing (receivers, or the occluders left
// out of a count over some of them: the count adds over occluders).  The
// overload without it computes them for every occluder.
ExactEyeCount exact_eye_count(const CameraSpaceScene& scene, std::size_t light,
                              const std::vector<std::vector<Facing>>& facing, FilterStats* stats = nullptr);
ExactEyeCount exact_eye_count(const CameraSpaceScene& scene, std::size_t light, FilterStats* stats = nullptr);

}  // namespace nearcap
