// nearcap/near_cap.hpp — the true near-cap: an exact planar arrangement of the
// near rectangle into faces of constant near-cap count.
//
// For light l and a point p of the near rectangle R (camera space, z = -near),
// cap(p) is the number of light-front-facing occluder triangles crossed by the
// segment [l, p] (under nearcap's perturbation of p; pixel_reference.hpp).  It
// is constant off a set of curves, all in the near plane:
//   - the silhouette edges' parts inside the light pyramid (the convex hull of
//     l and R), projected centrally from l onto the near plane;
//   - the cuts of front-facing triangles by the near plane, clipped to R (the
//     three edges of a front face lying in the plane);
//   - the four edges of R.
// (Edges between two front faces cancel and are left out.)  The curves are
// computed exactly in rationals and arranged by CGAL (Epeck, Arrangement_2);
// each face's count is the exact count at one interior point, found by a
// vertical ray from the midpoint of one of its edges.  A superset of curves
// would only split faces; a missing one would show as two different counts
// inside one face, which the tests look for against the brute-force count.
//
// A light exactly in the near plane makes the pyramid flat: Error(Degenerate).
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "nearcap/camera_space.hpp"
#include "nearcap/filter_stats.hpp"

namespace nearcap {

// A point of the near plane, camera-space (x, y), exact.
struct NearCapPoint {
  Rational x, y;
};

struct NearCapFace {
  std::size_t count = 0;
  std::vector<NearCapPoint> outer;               // counter-clockwise
  std::vector<std::vector<NearCapPoint>> holes;  // clockwise
  double area_estimate = 0;                      // in camera-space units^2
};

class NearCap {
 public:
  static NearCap build(const CameraSpaceScene& scene, std::size_t light, FilterStats* stats = nullptr);
  NearCap(NearCap&&) noexcept;
  NearCap& operator=(NearCap&&) noexcept;
  ~NearCap();

  const std::vector<NearCapFace>& faces() const { return faces_; }
  std::size_t max_count() const;
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
