// nearcap/exact/central_grid.hpp — triangles binned by their direction from a centre.
//
// Every query of the per-pixel reference is a segment or a ray from a fixed
// centre: the eye (view rays through pixel centres) or the light (segments
// [l, p] for the near-cap, (l, q) for the stencil).  So the acceleration
// structure is a cube map around the centre: each of its six faces is an
// adaptive 2-D grid over the face's projection plane, and a triangle is listed
// in every cell its central projection may touch.  A query direction w picks
// one face (its largest coordinate) and one cell: the candidates.
//
// The grid only ever narrows a search, never decides: binning is conservative
// (projected boxes are widened by their certified error plus kQueryMargin, a
// triangle reaching the centre's side of a face's plane is listed in all of
// that face's cells) and a query whose own uncertainty exceeds kQueryMargin
// gets every triangle.  The exact predicates then decide on the candidates.
// Doubles are right here: they estimate, the predicates decide.
//
// Storage: a grid takes its lists and the temporaries of its build from
// pools that keep the vectors earlier grids gave back, with their capacity
// (src/exact/vector_pool.hpp), and gives them back when destroyed: a grid
// rebuilt every frame (the camera or the light moved) writes into memory
// already mapped.  The lists are the same either way.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "nearcap/numeric/vec3.hpp"

namespace nearcap {

class CentralGrid {
 public:
  // A triangle as the grid sees it: vertex estimates, each coordinate within
  // `error` of the exact vertex.  `id` is returned by queries.
  struct Triangle {
    std::array<Vec3d, 3> vertex;
    double error = 0;
    std::uint32_t id = 0;
  };
  // A cell's entry: the triangle's id and a lower bound, over the triangle, of
  // the coordinate along the face's axis (distance from the centre's plane),
  // in increasing order of that bound within each cell.
  struct Entry {
    std::uint32_t id;
    double axis_lower_bound;
  };

  // A contiguous run of entries (C++17 has no std::span).  A cell's run,
  // from candidates(), also carries the query's point (u, v) on its face and
  // the face's box of every triangle it lists: may_contain(id) is false when
  // the query point lies outside triangle id's box, and then the triangle
  // certainly does not contain the query's exact direction (the grid lists a
  // triangle in the cell of that point only because its box may hold it, see
  // candidates()).  A run without boxes (all()) may contain every triangle.
  struct EntryRange {
    const Entry* first = nullptr;
    const Entry* last = nullptr;
    const std::array<float, 4>* box_of = nullptr;  // the face's boxes by id (u_lo, u_hi, v_lo, v_hi), or none
    double u = 0, v = 0;                           // the query point on the face, when box_of is set
    const Entry* begin() const { return first; }
    const Entry* end() const { return last; }
    std::size_t size() const { return static_cast<std::size_t>(last - first); }
    bool may_contain(std::uint32_t id) const {
      if (!box_of) return true;
      const std::array<float, 4>& b = box_of[id];
      return b[0] <= u && u <= b[1] && b[2] <= v && v <= b[3];
    }
  };

  static constexpr double kQueryMargin = 0x1p-20;  // in face coordinates (tan of angle)

  // `centre` within `centre_error` per coordinate of the exact centre.
  // `cells_per_triangle` sets the grid resolution.  Each face of the cube map
  // is built when a query first reaches it (thread-safe): the grid around the
  // eye is queried on the faces the view frustum meets, and the others cost
  // nothing.  A face's lists are the same whenever it is built.
  CentralGrid(const Vec3d& centre, double centre_error, std::vector<Triangle> triangles,
              double cells_per_triangle = 1.0);
  ~CentralGrid();
  CentralGrid(const CentralGrid&) = delete;
  CentralGrid& operator=(const CentralGrid&) = delete;

  // The candidates for direction w (estimate of the exact direction, each
  // coordinate within w_error): every triangle whose projection may contain
  // the direction.  When the query is too uncertain it returns all() instead.
  // Why the boxes filter: the query point (u, v) lies within kQueryMargin of
  // the exact direction's projection, and each triangle's box is its
  // projection's certified box widened by kQueryMargin; so a triangle that
  // contains the exact direction has (u, v) in its box.
  EntryRange candidates(const Vec3d& w, double w_error) const;
  // The candidates for every direction within w_error (per coordinate, any
  // size) of w: the ids of the triangles listed in the cells the region's
  // projection touches, sorted and unique.  False when the region reaches
  // beyond one face or is too wide to be worth it: the caller takes all().
  bool candidates_in(const Vec3d& w, double w_error, std::vector<std::uint32_t>& ids) const;
  EntryRange all() const { return {all_.data(), all_.data() + all_.size()}; }
  // Builds now (if not yet built) every face whose cone meets a direction of
  // the box lo <= w <= hi (per coordinate, relative to the centre; widened
  // by a relative 2^-20): the faces a known set of queries will read, so
  // that building them is paid here rather than by the first query.
  void build_faces_meeting(const Vec3d& lo, const Vec3d& hi) const;

  std::size_t triangle_count() const { return all_.size(); }
  std::size_t listed_entries() const;  // total over all cells (memory / quality)

 private:
  struct Face {
    double u0 = 0, v0 = 0, du = 1, dv = 1;  // grid origin and cell size
    int nu = 0, nv = 0;
    std::vector<std::uint32_t> offsets;  // CSR over cells, size nu*nv+1
    std::vector<Entry> entries;
    // Each listed triangle's conservative box on this face, by id, as floats
    // rounded outward (u_lo, u_hi, v_lo, v_hi): region queries keep only the
    // triangles whose box meets the region's.
    std::vector<std::array<float, 4>> box_of;
  };
  struct Pending;                 // the inputs of the faces not built yet
  const Face& face(int f) const;  // built on first use
  void build_face(int f) const;
  Vec3d centre_;
  double centre_error_;
  mutable std::array<Face, 6> faces_;
  std::vector<Entry> all_;
  std::unique_ptr<Pending> pending_;
};

}  // namespace nearcap
