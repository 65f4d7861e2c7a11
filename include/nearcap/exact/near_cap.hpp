// nearcap/exact/near_cap.hpp — the true near-cap: an exact planar arrangement of the
// near rectangle into faces of constant near-cap count.
//
// For light l and a point p of the near rectangle R (camera space, z = -near),
// cap(p) is the number of light-front-facing occluder triangles crossed by the
// segment [l, p] (under nearcap's perturbation of p; pixel_reference.hpp).  It
// is constant off a set of curves, all in the near plane:
//   - the silhouette edges' parts inside the light pyramid (the convex hull of
//     l and R), projected centrally from l onto the near plane;
//   - the cuts of front-facing triangles by the near plane, clipped to R (and
//     the edges of a front face lying in the plane, when l is beyond it);
//   - the four edges of R.
// (Edges between two front faces cancel and are left out.)  The curves are
// computed exactly in rationals and arranged by CGAL (Epeck, Arrangement_2).
// Each curve carries the integer change of the count across it (overlapping
// curves add theirs); one face's count is the brute-force count at an interior
// point, and a walk over the faces gives every other count from the deltas
// (derivations in near_cap.cpp).  The walk checks that every face gets one
// count whichever way it is reached (NEARCAP_CHECK), and that the faces' exact
// areas add up to R's.  Edges with the same count on both sides are then
// removed, except on the near plane's cuts of front faces: an edge separates
// two different counts, or R from its outside, or lies where the near plane
// cuts a front face (there the count ON the edge may differ from both sides).
// A vertex where a front face only touches the near plane stays too, isolated.
//
// Counts at points ON an edge or a vertex are not the arrangement's business:
// there the perturbation of the sample point decides (perturbation.hpp), and
// near_cap_count_brute_force or the per-pixel reference give them.
//
// Cost: O((n + k) log n) for n curves and k crossings, plus one brute-force
// count (O(front faces)).  FilterStats: Predicate::Arrangement counts the
// silhouette edges and front faces that a certified double test dismissed as
// missing the light pyramid / the near plane (filtered) and those that needed
// exact rationals (exact: they were clipped or cut exactly); the other
// predicates count the light facing and the one brute-force count.
//
// A light exactly in the near plane makes the pyramid flat: Error(Degenerate).
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/numeric/filter_stats.hpp"

namespace nearcap {

// A point of the near plane, camera-space (x, y), exact.
struct NearCapPoint {
  Rational x, y;
};

// A face of the near-cap: a connected open region of R of constant count.
struct NearCapFace {
  std::size_t count = 0;
  std::vector<NearCapPoint> outer;               // counter-clockwise
  std::vector<std::vector<NearCapPoint>> holes;  // clockwise
  double area_estimate = 0;                      // camera-space units^2: the exact area, rounded
};

class NearCap {
 public:
  // The near-cap of light `light` (an index of scene.light_count()).  Throws
  // Error(Degenerate) when the light lies in the near plane.
  static NearCap build(const CameraSpaceScene& scene, std::size_t light, FilterStats* stats = nullptr);
  NearCap(NearCap&&) noexcept;
  NearCap& operator=(NearCap&&) noexcept;
  ~NearCap();

  const std::vector<NearCapFace>& faces() const { return faces_; }
  std::size_t max_count() const;
  // Curves that entered the arrangement: projected silhouette edges, and
  // near-plane curves (cuts of front faces; edges of front faces lying in the
  // near plane when the light is beyond it).  Edges after the simplification.
  std::size_t silhouette_curves() const { return silhouette_curves_; }
  std::size_t near_plane_cuts() const { return near_plane_cuts_; }
  std::size_t arrangement_edges() const;

  // The count of the face holding (x, y) in its interior; nothing when the
  // point lies on an edge or a vertex, or outside the near rectangle.
  std::optional<std::size_t> count_at(const Rational& x, const Rational& y) const;

 private:
  struct Impl;
  NearCap();
  std::unique_ptr<Impl> impl_;
  std::vector<NearCapFace> faces_;
  std::size_t silhouette_curves_ = 0;
  std::size_t near_plane_cuts_ = 0;
};

}  // namespace nearcap
