// The cube-map grid of triangles around a centre (see central_grid.hpp).
#include "nearcap/exact/central_grid.hpp"

#include <tbb/blocked_range.h>
#include <tbb/collaborative_call_once.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

#include "vector_pool.hpp"

namespace nearcap {
namespace {

constexpr double kRounding = 0x1p-50;  // generous relative bound for a few double operations
constexpr double kFaceRange = 1.0 + 2.0 * CentralGrid::kQueryMargin;

struct FaceAxes {
  int axis, u, v;
  double sign;
};
FaceAxes face_axes(int f) { return {f / 2, (f / 2 + 1) % 3, (f / 2 + 2) % 3, (f % 2 == 0) ? 1.0 : -1.0}; }

// Bound on the error of a face coordinate u = w_u / m computed from estimates
// within `err` per coordinate, with denom = m - err > 0 (a lower bound of the
// exact m): |W_u/M - w_u/m| <= err (1 + |u|) / denom, plus the division's rounding.
double projection_error(double u, double err, double denom) {
  return err * (1.0 + std::fabs(u)) / denom * (1.0 + kRounding) + kRounding * std::fabs(u);
}

struct Box {
  double u_lo, u_hi, v_lo, v_hi;
};

// What one triangle looks like from one face: skipped, projected to a box, or
// reaching the face's plane (listed everywhere on the face).
enum class Placement { Skip, Boxed, Whole };

struct FacePlacement {
  Placement placement = Placement::Skip;
  Box box{};
  double axis_lower_bound = 0;
};

// Distance from the origin to triangle abc (closest point by regions, as in
// Ericson, Real-Time Collision Detection, 5.1.5).  An estimate: the caller
// compares it with a threshold far above its rounding error.
double distance_to_origin(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d p{0, 0, 0};
  const Vec3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  auto norm = [](const Vec3d& v) { return std::sqrt(dot(v, v)); };
  if (d1 <= 0 && d2 <= 0) return norm(a);
  const Vec3d bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return norm(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return norm(a + Vec3d{v * ab.x, v * ab.y, v * ab.z});
  }
  const Vec3d cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return norm(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return norm(a + Vec3d{w * ac.x, w * ac.y, w * ac.z});
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return norm(b + Vec3d{w * (c.x - b.x), w * (c.y - b.y), w * (c.z - b.z)});
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return norm(a + Vec3d{v * ab.x + w * ac.x, v * ab.y + w * ac.y, v * ab.z + w * ac.z});
}

// A polygon on the stack: no allocation per clip.  A triangle clipped by 4
// planes has at most 7 vertices; each clip at most doubles the count even
// when rounding makes the polygon slightly non-convex, so 3 * 2^4 = 48 always
// suffice.
struct SmallPolygon {
  std::array<Vec3d, 48> v;
  std::size_t n = 0;
  void push(const Vec3d& p) { v[n++] = p; }
};

// Clips a polygon (coordinates relative to the centre) to the half-space
// s * w[axis] >= w[other] * t for t = +1 or -1: one side of the face's cone.
void clip_to_cone_side(const SmallPolygon& poly, const FaceAxes& ax, int other, double t, SmallPolygon& out) {
  out.n = 0;
  const std::size_t n = poly.n;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3d& a = poly.v[k];
    const Vec3d& b = poly.v[k + 1 == n ? 0 : k + 1];
    const double fa = ax.sign * a[ax.axis] - t * a[other];
    const double fb = ax.sign * b[ax.axis] - t * b[other];
    if (fa >= 0) out.push(a);
    if ((fa >= 0) != (fb >= 0)) {
      const double s = fa / (fa - fb);
      out.push(Vec3d{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z)});
    }
  }
}

// A triangle relative to the centre, with what every face needs of it.
struct Relative {
  std::array<Vec3d, 3> w;  // vertices minus the centre
  double err = 0;          // per coordinate, of w against the exact relative vertices
  // Near the apex the cone opening no longer covers the input error: a
  // triangle passing that close to the centre is listed everywhere.
  bool near_apex = false;
  // The face whose cone strictly holds all three vertices (then the whole
  // triangle, the cone being convex), with room to spare for the errors and
  // the cones' opening: no other face can list it.  -1 when there is none.
  int only_face = -1;
};

Relative relative_to(const CentralGrid::Triangle& t, const Vec3d& centre, double centre_error) {
  Relative r;
  double mag = 0;
  for (int i = 0; i < 3; ++i) {
    r.w[i] = t.vertex[i] - centre;
    mag = std::max({mag, std::fabs(r.w[i].x), std::fabs(r.w[i].y), std::fabs(r.w[i].z)});
  }
  // Every point of the clipped polygon below lies within `err` (per coordinate)
  // of a point of the exact triangle in the exact cone: input errors plus the
  // rounding of the subtraction and of a few clipping steps.
  r.err = t.error + centre_error + 16.0 * kRounding * mag;
  const double apex = 0x1p22 * r.err;
  r.near_apex = distance_to_origin(r.w[0], r.w[1], r.w[2]) <= 4.0 * apex;
  int face = -1;
  for (int i = 0; i < 3; ++i) {
    const Vec3d& v = r.w[i];
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (std::fabs(v[a]) > std::fabs(v[axis])) axis = a;
    const FaceAxes ax = face_axes(2 * axis + (v[axis] >= 0 ? 0 : 1));
    // Strictly inside with a relative margin far above the cones' opening
    // (2^-20) and an absolute one above the errors.
    const double m = ax.sign * v[ax.axis];
    const bool strict = m * (1.0 - 0x1p-16) - 4.0 * r.err > std::max(std::fabs(v[ax.u]), std::fabs(v[ax.v]));
    const int f = 2 * axis + (v[axis] >= 0 ? 0 : 1);
    if (!strict || (i > 0 && f != face)) return r;
    face = f;
  }
  r.only_face = face;
  return r;
}

// `scratch`: two polygon buffers, made once by the caller (zeroing 2 KB per
// call would cost more than the clipping).
FacePlacement place(const Relative& r, int f, std::array<SmallPolygon, 2>& scratch) {
  const FaceAxes ax = face_axes(f);
  const std::array<Vec3d, 3>& w = r.w;
  const double err = r.err;
  FacePlacement out;
  double lower = std::numeric_limits<double>::infinity();
  bool all_behind = true;
  for (int i = 0; i < 3; ++i) {
    const double m = ax.sign * w[i][ax.axis];
    if (!(m < -err)) all_behind = false;
    lower = std::min(lower, m - err);
  }
  out.axis_lower_bound = lower;
  if (all_behind) return out;
  if (r.near_apex) {
    out.placement = Placement::Whole;
    return out;
  }
  if (r.only_face >= 0 && r.only_face != f) return out;
  // The part of the triangle inside the face's cone |w_u|, |w_v| <= m, widened:
  // the cone is opened by a relative margin so that clipping in double never
  // loses a part of the exact triangle that the exact cone holds.
  const double open = 1.0 + 0x1p-20;
  SmallPolygon* in = &scratch[0];
  SmallPolygon* out_poly = &scratch[1];
  in->n = 0;
  for (const Vec3d& p : w) in->push(p);
  // A triangle strictly inside this face's cone needs no clipping.
  for (int other : {ax.u, ax.v})
    for (double side : {1.0 / open, -1.0 / open}) {
      if (in->n == 0 || r.only_face == f) break;
      clip_to_cone_side(*in, ax, other, side, *out_poly);
      std::swap(in, out_poly);
    }
  const SmallPolygon& poly = *in;
  if (poly.n == 0) return out;  // no point of the exact triangle lies in the exact cone
  Box b{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (std::size_t k = 0; k < poly.n; ++k) {
    const Vec3d& v = poly.v[k];
    const double m = ax.sign * v[ax.axis];
    const double u = v[ax.u] / m, vv = v[ax.v] / m;
    const double denom = m - err;
    const double eu = projection_error(u, err, denom), ev = projection_error(vv, err, denom);
    b.u_lo = std::min(b.u_lo, u - eu);
    b.u_hi = std::max(b.u_hi, u + eu);
    b.v_lo = std::min(b.v_lo, vv - ev);
    b.v_hi = std::max(b.v_hi, vv + ev);
  }
  b.u_lo = std::max(b.u_lo - CentralGrid::kQueryMargin, -kFaceRange);
  b.u_hi = std::min(b.u_hi + CentralGrid::kQueryMargin, kFaceRange);
  b.v_lo = std::max(b.v_lo - CentralGrid::kQueryMargin, -kFaceRange);
  b.v_hi = std::min(b.v_hi + CentralGrid::kQueryMargin, kFaceRange);
  if (!(b.u_lo <= b.u_hi && b.v_lo <= b.v_hi)) return out;
  out.placement = Placement::Boxed;
  out.box = b;
  return out;
}

// The largest float <= x and the smallest float >= x (x finite or infinite).
float float_below(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float float_above(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

int cell_index(double x, double origin, double size, int n) {
  const double c = std::floor((x - origin) / size);
  if (c < 0) return 0;
  if (c >= n) return n - 1;
  return static_cast<int>(c);
}

}  // namespace

// What building a face needs, kept until all six are built.
struct CentralGrid::Pending {
  std::vector<Triangle> triangles;
  std::vector<Relative> relative;
  // The triangles each face has to place: those strictly inside its cone,
  // and those that are not strictly inside one cone (or pass near the
  // centre), which every face places.
  std::array<std::vector<std::uint32_t>, 6> inside;
  std::vector<std::uint32_t> anywhere;
  std::uint32_t max_id = 0;
  double cells_per_triangle = 1;
  std::array<tbb::collaborative_once_flag, 6> built;
  std::atomic<int> faces_built{0};
  void give_back();
};

CentralGrid::CentralGrid(const Vec3d& centre, double centre_error, std::vector<Triangle> triangles,
                         double cells_per_triangle)
    : centre_(centre), centre_error_(centre_error), pending_(std::make_unique<Pending>()) {
  all_ = VectorPool<Entry>::instance().take(triangles.size());
  for (const Triangle& t : triangles) all_.push_back({t.id, -std::numeric_limits<double>::infinity()});

  // Building is per triangle and per cell, on all cores; every list keeps
  // the order a sequential build gives (the grid is the same either way).
  Pending& p = *pending_;
  p.cells_per_triangle = cells_per_triangle;
  p.relative = VectorPool<Relative>::instance().take(triangles.size());
  p.relative.resize(triangles.size());
  for (auto& v : p.inside) v = VectorPool<std::uint32_t>::instance().take(0);
  p.anywhere = VectorPool<std::uint32_t>::instance().take(0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i)
                        p.relative[i] = relative_to(triangles[i], centre_, centre_error_);
                    });
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const Relative& r = p.relative[i];
    if (r.only_face >= 0 && !r.near_apex)
      p.inside[static_cast<std::size_t>(r.only_face)].push_back(static_cast<std::uint32_t>(i));
    else
      p.anywhere.push_back(static_cast<std::uint32_t>(i));
  }
  for (const Triangle& t : triangles) p.max_id = std::max(p.max_id, t.id);
  p.triangles = std::move(triangles);
}

// What a grid held goes back to the pools, for the next grid's build.
void CentralGrid::Pending::give_back() {
  VectorPool<Triangle>::instance().give(triangles);
  VectorPool<Relative>::instance().give(relative);
  for (auto& v : inside) VectorPool<std::uint32_t>::instance().give(v);
  VectorPool<std::uint32_t>::instance().give(anywhere);
}

CentralGrid::~CentralGrid() {
  if (pending_) pending_->give_back();
  for (Face& face : faces_) {
    VectorPool<std::uint32_t>::instance().give(face.offsets);
    VectorPool<Entry>::instance().give(face.entries);
    VectorPool<std::array<float, 4>>::instance().give(face.box_of);
  }
  VectorPool<Entry>::instance().give(all_);
}

const CentralGrid::Face& CentralGrid::face(int f) const {
  tbb::collaborative_call_once(pending_->built[static_cast<std::size_t>(f)], [&] {
    build_face(f);
    // The last face built: nothing reads the inputs any more.
    if (pending_->faces_built.fetch_add(1) + 1 == 6) pending_->give_back();
  });
  return faces_[static_cast<std::size_t>(f)];
}

void CentralGrid::build_faces_meeting(const Vec3d& lo, const Vec3d& hi) const {
  // The smallest |x| over [lo_a, hi_a].
  auto closest_to_zero = [](double lo_a, double hi_a) {
    return lo_a <= 0 && hi_a >= 0 ? 0.0 : std::min(std::fabs(lo_a), std::fabs(hi_a));
  };
  for (int f = 0; f < 6; ++f) {
    const FaceAxes ax = face_axes(f);
    // The largest sign * w_axis over the box; the face's cone holds the
    // directions with sign * w_axis >= |w_u|, |w_v|.
    const double m = (ax.sign > 0 ? hi[ax.axis] : -lo[ax.axis]) * (1.0 + 0x1p-20);
    if (m > 0 && m >= closest_to_zero(lo[ax.u], hi[ax.u]) && m >= closest_to_zero(lo[ax.v], hi[ax.v])) face(f);
  }
}

void CentralGrid::build_face(int f) const {
  const Pending& pending = *pending_;
  const std::vector<Triangle>& triangles = pending.triangles;
  const std::vector<Relative>& relative = pending.relative;
  const std::array<std::vector<std::uint32_t>, 6>& inside = pending.inside;
  const std::vector<std::uint32_t>& anywhere = pending.anywhere;
  const std::uint32_t max_id = pending.max_id;
  const double cells_per_triangle = pending.cells_per_triangle;
  struct Placed {
    std::uint32_t index;
    FacePlacement placement;
  };
  // The temporaries come from the pools too (vector_pool.hpp): the next
  // face's build, or the next frame's, finds their pages mapped.
  const std::vector<std::uint32_t>& face_inside = inside[static_cast<std::size_t>(f)];
  PooledVector<Placed> placed_storage(face_inside.size() + anywhere.size());
  PooledVector<std::uint32_t> order_storage(face_inside.size() + anywhere.size());
  PooledVector<FacePlacement> placements_storage(face_inside.size() + anywhere.size());
  std::vector<Placed>& placed = *placed_storage;
  std::vector<std::uint32_t>& order = *order_storage;
  std::vector<FacePlacement>& placements = *placements_storage;
  tbb::enumerable_thread_specific<std::unique_ptr<std::array<SmallPolygon, 2>>> scratches(
      [] { return std::make_unique<std::array<SmallPolygon, 2>>(); });
  {
    Face& face = faces_[static_cast<std::size_t>(f)];
    Box extent{kFaceRange, -kFaceRange, kFaceRange, -kFaceRange};
    std::size_t boxed = 0;
    order.assign(face_inside.begin(), face_inside.end());
    order.insert(order.end(), anywhere.begin(), anywhere.end());
    placements.resize(order.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 512),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        std::array<SmallPolygon, 2>& scratch = *scratches.local();
                        for (std::size_t k = r.begin(); k < r.end(); ++k)
                          placements[k] = place(relative[order[k]], f, scratch);
                      });
    for (std::size_t k = 0; k < order.size(); ++k) {
      const std::uint32_t i = order[k];
      const FacePlacement& p = placements[k];
      if (p.placement == Placement::Skip) continue;
      placed.push_back({i, p});
      if (p.placement != Placement::Boxed) continue;
      ++boxed;
      const Box& b = p.box;
      extent = {std::min(extent.u_lo, b.u_lo), std::max(extent.u_hi, b.u_hi), std::min(extent.v_lo, b.v_lo),
                std::max(extent.v_hi, b.v_hi)};
    }
    if (boxed == 0) extent = {-kFaceRange, kFaceRange, -kFaceRange, kFaceRange};
    const double width = std::max(extent.u_hi - extent.u_lo, 1e-300);
    const double height = std::max(extent.v_hi - extent.v_lo, 1e-300);
    const double cells = std::max(1.0, static_cast<double>(boxed) * cells_per_triangle);
    face.nu = static_cast<int>(std::clamp(std::round(std::sqrt(cells * width / height)), 1.0, 2048.0));
    face.nv = static_cast<int>(std::clamp(std::round(std::sqrt(cells * height / width)), 1.0, 2048.0));
    face.u0 = extent.u_lo;
    face.v0 = extent.v_lo;
    face.du = width / face.nu;
    face.dv = height / face.nv;

    // Two passes over a CSR layout: count, then fill.  Each pass runs on all
    // cores over bands of cell rows; a band's task visits every placed
    // triangle in order and touches only its own rows, so each cell lists its
    // triangles in the order a sequential pass gives.
    const std::size_t cell_count = static_cast<std::size_t>(face.nu) * static_cast<std::size_t>(face.nv);
    PooledVector<std::uint32_t> counts_storage(cell_count + 1);
    PooledVector<Entry> whole_storage;
    std::vector<std::uint32_t>& counts = *counts_storage;
    std::vector<Entry>& whole = *whole_storage;
    counts.assign(cell_count + 1, 0);
    struct CellSpan {
      int i0, i1, j0, j1;
    };
    auto span_of = [&](const Box& b) {
      return CellSpan{cell_index(b.u_lo, face.u0, face.du, face.nu), cell_index(b.u_hi, face.u0, face.du, face.nu),
                      cell_index(b.v_lo, face.v0, face.dv, face.nv), cell_index(b.v_hi, face.v0, face.dv, face.nv)};
    };
    PooledVector<CellSpan> spans_storage(placed.size());
    std::vector<CellSpan>& spans = *spans_storage;
    spans.resize(placed.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, placed.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t k = r.begin(); k < r.end(); ++k)
                          if (placed[k].placement.placement == Placement::Boxed)
                            spans[k] = span_of(placed[k].placement.box);
                      });
    // One band per thread: every band scans the whole list, so more bands
    // than threads would only repeat that scan.
    const int bands = std::max(1, std::min(face.nv, tbb::this_task_arena::max_concurrency()));
    auto for_band_cells = [&](auto&& fn) {
      tbb::parallel_for(0, bands, [&](int band) {
        const int row_lo = static_cast<int>(static_cast<long long>(face.nv) * band / bands);
        const int row_hi = static_cast<int>(static_cast<long long>(face.nv) * (band + 1) / bands);
        for (std::size_t k = 0; k < placed.size(); ++k) {
          if (placed[k].placement.placement != Placement::Boxed) continue;
          const CellSpan& sp = spans[k];
          for (int j = std::max(sp.j0, row_lo); j <= std::min(sp.j1, row_hi - 1); ++j)
            for (int i = sp.i0; i <= sp.i1; ++i) fn(k, static_cast<std::size_t>(j) * face.nu + i);
        }
      });
    };
    for_band_cells([&](std::size_t, std::size_t c) { ++counts[c]; });
    for (const Placed& p : placed)
      if (p.placement.placement != Placement::Boxed)
        whole.push_back({triangles[p.index].id, p.placement.axis_lower_bound});
    constexpr float kInf = std::numeric_limits<float>::infinity();
    // Only ids listed in a cell are ever looked up: a face that lists none
    // needs no boxes.
    face.box_of = VectorPool<std::array<float, 4>>::instance().take(placed.empty() ? 0 : std::size_t{max_id} + 1);
    face.box_of.assign(placed.empty() ? 0 : static_cast<std::size_t>(max_id) + 1,
                       std::array<float, 4>{kInf, -kInf, kInf, -kInf});
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, placed.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t k = r.begin(); k < r.end(); ++k) {
                          const Placed& p = placed[k];
                          std::array<float, 4>& b = face.box_of[triangles[p.index].id];
                          if (p.placement.placement == Placement::Whole) {
                            b = {-kInf, kInf, -kInf, kInf};
                          } else {
                            const Box& x = p.placement.box;
                            b = {float_below(x.u_lo), float_above(x.u_hi), float_below(x.v_lo), float_above(x.v_hi)};
                          }
                        }
                      });
    face.offsets = VectorPool<std::uint32_t>::instance().take(cell_count + 2);  // + the whole-face list
    face.offsets.assign(cell_count + 1, 0);
    for (std::size_t c = 0; c < cell_count; ++c)
      face.offsets[c + 1] = face.offsets[c] + counts[c] + static_cast<std::uint32_t>(whole.size());
    face.entries = VectorPool<Entry>::instance().take(std::size_t{face.offsets[cell_count]} + whole.size());
    face.entries.resize(face.offsets[cell_count]);
    PooledVector<std::uint32_t> fill_storage(cell_count);
    std::vector<std::uint32_t>& fill = *fill_storage;
    fill.assign(face.offsets.begin(), face.offsets.end() - 1);
    for_band_cells([&](std::size_t k, std::size_t c) {
      face.entries[fill[c]++] = {triangles[placed[k].index].id, placed[k].placement.axis_lower_bound};
    });
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, cell_count, 256), [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t c = r.begin(); c < r.end(); ++c) {
            for (const Entry& e : whole) face.entries[fill[c]++] = e;
            std::sort(face.entries.begin() + face.offsets[c], face.entries.begin() + face.offsets[c + 1],
                      [](const Entry& a, const Entry& b) { return a.axis_lower_bound < b.axis_lower_bound; });
          }
        });
    // Directions outside the grid's extent can only lie in whole-face triangles:
    // they sit in an extra last "cell".
    std::sort(whole.begin(), whole.end(),
              [](const Entry& a, const Entry& b) { return a.axis_lower_bound < b.axis_lower_bound; });
    face.offsets.push_back(face.offsets.back() + static_cast<std::uint32_t>(whole.size()));
    face.entries.insert(face.entries.end(), whole.begin(), whole.end());
  }
}

CentralGrid::EntryRange CentralGrid::candidates(const Vec3d& w, double w_error) const {
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (std::fabs(w[a]) > std::fabs(w[axis])) axis = a;
  const double m = std::fabs(w[axis]);
  const double err = w_error + centre_error_;
  if (!(m > 2.0 * err) || !std::isfinite(m)) return all();
  const int f = 2 * axis + (w[axis] >= 0 ? 0 : 1);
  const FaceAxes ax = face_axes(f);
  const double u = w[ax.u] / m, v = w[ax.v] / m;
  const double denom = m - err;
  const double eu = projection_error(u, err, denom), ev = projection_error(v, err, denom);
  if (eu > kQueryMargin || ev > kQueryMargin) return all();
  const Face& face = this->face(f);
  const double fi = std::floor((u - face.u0) / face.du), fj = std::floor((v - face.v0) / face.dv);
  std::size_t cell;
  if (fi < 0 || fj < 0 || fi >= face.nu || fj >= face.nv)
    cell = static_cast<std::size_t>(face.nu) * static_cast<std::size_t>(face.nv);  // the whole-face list
  else
    cell = static_cast<std::size_t>(fj) * face.nu + static_cast<std::size_t>(fi);
  // Every id a cell lists has its box on this face (whole-face ones an
  // infinite one).
  return {face.entries.data() + face.offsets[cell], face.entries.data() + face.offsets[cell + 1], face.box_of.data(), u,
          v};
}

bool CentralGrid::candidates_in(const Vec3d& w, double w_error, std::vector<std::uint32_t>& ids) const {
  ids.clear();
  const double mag = std::max({std::fabs(w.x), std::fabs(w.y), std::fabs(w.z)});
  // Each exact coordinate of the region lies in [w_a - err, w_a + err]: the
  // caller's bound, the centre's, and the rounding of these few operations.
  const double err = (w_error + centre_error_) * (1.0 + kRounding) + kRounding * mag;
  if (!std::isfinite(mag) || !std::isfinite(err)) return false;
  // Every direction lies in the exact cone of at least one face, and the
  // binning of a face is complete for the directions of its cone, so the
  // region is covered by querying, on every face whose cone it may meet, the
  // cells its directions there may project to.
  struct FaceQuery {
    int face;
    Box box;
  };
  std::array<FaceQuery, 6> queries{};
  std::size_t query_count = 0;
  long long cells = 0;
  constexpr long long kMaxCells = 4096;
  for (int f = 0; f < 6; ++f) {
    const FaceAxes ax = face_axes(f);
    const double m_lo = ax.sign * w[ax.axis] - err, m_hi = ax.sign * w[ax.axis] + err;
    // The cone holds directions with sign * w_axis >= |w_u|, |w_v|: none of
    // the region's when its largest axis coordinate stays below the smallest
    // |w_u| or |w_v| it holds (or is not positive).
    const double min_u = std::fabs(w[ax.u]) - err, min_v = std::fabs(w[ax.v]) - err;
    if (!(m_hi > 0) || m_hi < min_u || m_hi < min_v) continue;
    Box b{-kFaceRange, kFaceRange, -kFaceRange, kFaceRange};
    if (m_lo > 0) {
      // u = w_u / m over the box: interval division by a positive interval,
      // rounded outward.
      auto range = [&](double lo, double hi, double& out_lo, double& out_hi) {
        out_lo = lo >= 0 ? lo / m_hi : lo / m_lo;
        out_hi = hi >= 0 ? hi / m_lo : hi / m_hi;
        out_lo -= kRounding * std::fabs(out_lo) + 0x1p-1000;
        out_hi += kRounding * std::fabs(out_hi) + 0x1p-1000;
      };
      range(w[ax.u] - err, w[ax.u] + err, b.u_lo, b.u_hi);
      range(w[ax.v] - err, w[ax.v] + err, b.v_lo, b.v_hi);
      // Directions of the cone have |u|, |v| <= 1.
      if (b.u_lo > kFaceRange || b.u_hi < -kFaceRange || b.v_lo > kFaceRange || b.v_hi < -kFaceRange) continue;
      b = {std::max(b.u_lo, -kFaceRange), std::min(b.u_hi, kFaceRange), std::max(b.v_lo, -kFaceRange),
           std::min(b.v_hi, kFaceRange)};
    }
    const Face& face = this->face(f);
    const int i0 = cell_index(b.u_lo, face.u0, face.du, face.nu), i1 = cell_index(b.u_hi, face.u0, face.du, face.nu);
    const int j0 = cell_index(b.v_lo, face.v0, face.dv, face.nv), j1 = cell_index(b.v_hi, face.v0, face.dv, face.nv);
    cells += static_cast<long long>(i1 - i0 + 1) * (j1 - j0 + 1);
    if (cells > kMaxCells) return false;
    queries[query_count++] = {f, b};
  }
  for (std::size_t q = 0; q < query_count; ++q) {
    const Face& face = faces_[static_cast<std::size_t>(queries[q].face)];  // built above
    const Box& b = queries[q].box;
    const int i0 = cell_index(b.u_lo, face.u0, face.du, face.nu), i1 = cell_index(b.u_hi, face.u0, face.du, face.nu);
    const int j0 = cell_index(b.v_lo, face.v0, face.dv, face.nv), j1 = cell_index(b.v_hi, face.v0, face.dv, face.nv);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const std::size_t cell = static_cast<std::size_t>(j) * face.nu + static_cast<std::size_t>(i);
        for (std::uint32_t k = face.offsets[cell]; k < face.offsets[cell + 1]; ++k) {
          // Directions beyond the grid's extent lie only in whole-face
          // triangles, which every cell lists too.  Only triangles whose own
          // box meets the region's can contain one of its directions.
          const std::uint32_t id = face.entries[k].id;
          const std::array<float, 4>& tb = face.box_of[id];
          if (!(tb[1] < b.u_lo || tb[0] > b.u_hi || tb[3] < b.v_lo || tb[2] > b.v_hi)) ids.push_back(id);
        }
      }
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return true;
}

std::size_t CentralGrid::listed_entries() const {
  std::size_t n = 0;
  for (int f = 0; f < 6; ++f) n += face(f).entries.size();
  return n;
}

}  // namespace nearcap
