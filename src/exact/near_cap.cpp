// The near-cap arrangement (see near_cap.hpp).  The only translation unit that
// includes CGAL: Epeck with mpq_class as its exact type (CGAL_USE_GMPXX), so
// nearcap's Rational and CGAL's exact numbers are the same type.
//
// How the counts are found (ZP+ section 3: the near-cap is what the stencil
// should hold at the near plane).  The count is a sum over front faces F of the
// indicator I_F(p) = [segment [l, p] crosses F].  Inside the near rectangle R,
// I_F jumps only across
//   - the central projection from l of F's edges, clipped to the light pyramid
//     P (the part of F between l and the near plane N is what [l, p] can meet):
//     crossing into F's "cone side" adds 1;
//   - the cut F ∩ N, where p passes from l's side of F's plane to the far side:
//     that adds 1.
// Summed over F, the projected edge between two front faces cancels (both are
// front-facing, so from l they lie on opposite sides of it), leaving the
// silhouette edges.  Every curve therefore gets an integer delta (count on its
// left minus count on its right, for the curve directed lexicographically), the
// arrangement sums the deltas of overlapping curves (Arr_curve_data_traits_2
// with an additive merge), and the counts follow from ONE brute-force count and
// a breadth-first walk over the faces: O(n log n) instead of a brute-force
// count per face.  The walk checks itself: a face reached twice must get the
// same count both times (NEARCAP_CHECK), so a wrong delta cannot pass silently.
//
// Additivity holds when, for each F, at most one of its two conditions (cone,
// plane) changes across a curve.  Both change together only along an edge e of
// F lying in N (the projection of e is e, and so is the cut).  With c the third
// vertex of F:
//   - c on l's side of N: the cone side of e is the far side of F's plane, the
//     true jump is 1 = the cone delta alone: the cut's delta is 0;
//   - c beyond N: the two sides are opposite, the true jump 0 = cone + cut
//     deltas: the generic rule holds;
//   - F inside N: generic points of F are crossed iff l lies on the camera's
//     side of N (the perturbation moves p away from the camera, perturbation.hpp),
//     so the true jump into F is 1 or 0.  The cone delta gives 1; when l lies
//     beyond N a correction of -1 into F runs along F's edges.
//
// Lower-dimensional features.  The count at a point p of N is the count at p
// perturbed off N, away from the camera (perturbation.hpp).  Where no front
// face passes through p, that is the count of a face next to p (the segment
// to the perturbed point and the segment to its projection on N differ only
// near p).  Where one does, i.e. on F ∩ N, it may differ from every face
// around p (a box touching N along an edge, from beyond: count 1 on the edge,
// 0 on both sides).  So every cut stays an edge even when its delta is 0, and
// a vertex where F only touches N is an isolated vertex: count_at says nothing
// there, and the brute force decides.
// Each delta is evaluated as a sign at a point to the curve's left, never read
// off a winding convention, so mirrored objects (handedness -1) and lights on
// either side of N need no special case.
#include "nearcap/exact/near_cap.hpp"

#include <CGAL/Arr_curve_data_traits_2.h>
#include <CGAL/Arr_extended_dcel.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arr_walk_along_line_point_location.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <algorithm>
#include <cstdint>
#include <deque>
#include <limits>
#include <string>

#include "nearcap/check.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/light_facing.hpp"
#include "nearcap/exact/segment_crossing.hpp"
#include "nearcap/exact/silhouette.hpp"

namespace nearcap {
namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Point2 = Kernel::Point_2;
using Segment2 = Kernel::Segment_2;
using SegmentTraits = CGAL::Arr_segment_traits_2<Kernel>;

// What a curve carries: the change of the count across it (left minus right,
// for the curve directed lexicographically), and whether it lies on the cut of
// a front face by the near plane.  The count ON such a curve is decided by the
// perturbation (p moves off the near plane, through the face) and may differ
// from both sides, so it stays an edge even where its delta is 0.
struct CurveData {
  int delta = 0;
  bool on_cut = false;
  bool operator==(const CurveData& o) const { return delta == o.delta && on_cut == o.on_cut; }
};
// Overlapping curves add their deltas.
struct MergeCurveData {
  CurveData operator()(const CurveData& a, const CurveData& b) const {
    return {a.delta + b.delta, a.on_cut || b.on_cut};
  }
};
using Traits = CGAL::Arr_curve_data_traits_2<SegmentTraits, CurveData, MergeCurveData>;
using Curve = Traits::Curve_2;

// A face's count, unknown until the walk reaches it.
struct FaceCount {
  bool known = false;
  std::int64_t value = 0;
};
using Dcel = CGAL::Arr_face_extended_dcel<Traits, FaceCount>;
using Arrangement = CGAL::Arrangement_2<Traits, Dcel>;
using PointLocation = CGAL::Arr_walk_along_line_point_location<Arrangement>;

static_assert(std::is_same_v<Kernel::FT::Exact_type, Rational>, "Epeck must run on mpq_class (CGAL_USE_GMPXX)");

Rational exact_of(const Kernel::FT& v) { return CGAL::exact(v); }
Kernel::FT ft(const Rational& r) { return Kernel::FT(r); }

// The side of plane (o, a, b) that p lies on.
Sign orientation(const RationalVec3& o, const RationalVec3& a, const RationalVec3& b, const RationalVec3& p) {
  return sign_of(orientation_determinant(o, a, b, p));
}

// A 3-D segment in camera space, exact.
struct Segment3 {
  RationalVec3 a, b;
};

// An affine function h . x + h0 on camera space; its half-space is >= 0.
struct HalfSpace {
  RationalVec3 h;
  Rational h0;
  BoundedVec3 h_approx;  // the same, certified doubles: the filter
  BoundedDouble h0_approx;
};

// Clips [s.a, s.b] to the closed half-space; false when nothing is left.
bool clip(Segment3& s, const HalfSpace& half) {
  const Rational fa = dot(half.h, s.a) + half.h0, fb = dot(half.h, s.b) + half.h0;
  if (sgn(fa) < 0 && sgn(fb) < 0) return false;
  if (sgn(fa) >= 0 && sgn(fb) >= 0) return true;
  const Rational t = fa / (fa - fb);
  const RationalVec3 x{s.a.x + t * (s.b.x - s.a.x), s.a.y + t * (s.b.y - s.a.y), s.a.z + t * (s.b.z - s.a.z)};
  (sgn(fa) < 0 ? s.a : s.b) = x;
  return true;
}

// The light pyramid P: the convex hull of l and the near rectangle R, as five
// closed half-spaces (four through l and an edge of R, and N's side holding l).
std::vector<HalfSpace> light_pyramid(const RationalVec3& l, const Frustum& fr) {
  const Rational z0(-fr.near);
  const std::array<RationalVec3, 4> corner{RationalVec3{Rational(fr.left), Rational(fr.bottom), z0},
                                           RationalVec3{Rational(fr.right), Rational(fr.bottom), z0},
                                           RationalVec3{Rational(fr.right), Rational(fr.top), z0},
                                           RationalVec3{Rational(fr.left), Rational(fr.top), z0}};
  const RationalVec3 centre{(Rational(fr.left) + Rational(fr.right)) / 2, (Rational(fr.bottom) + Rational(fr.top)) / 2,
                            z0};
  std::vector<HalfSpace> p;
  auto add = [&](RationalVec3 h, Rational h0) {
    HalfSpace half{h, h0, {bounded_estimate(h.x), bounded_estimate(h.y), bounded_estimate(h.z)}, bounded_estimate(h0)};
    p.push_back(std::move(half));
  };
  for (int k = 0; k < 4; ++k) {
    RationalVec3 n = cross(corner[k] - l, corner[(k + 1) % 4] - l);
    Rational h0 = -dot(n, l);
    if (sgn(Rational(dot(n, centre) + h0)) < 0) {
      n = RationalVec3{-n.x, -n.y, -n.z};
      h0 = -h0;
    }
    add(n, h0);
  }
  const int s = sgn(Rational(l.z - z0));  // s (z - z0) >= 0
  add(RationalVec3{Rational(0), Rational(0), Rational(s)}, Rational(-s) * z0);
  return p;
}

// Filter: is the segment (certified estimates) surely outside one half-space?
bool surely_outside(const std::vector<HalfSpace>& pyramid, const BoundedVec3& a, const BoundedVec3& b) {
  for (const HalfSpace& half : pyramid) {
    const BoundedDouble fa = dot(half.h_approx, a) + half.h0_approx;
    const BoundedDouble fb = dot(half.h_approx, b) + half.h0_approx;
    const auto sa = fa.sign(), sb = fb.sign();
    if (sa == Sign::Negative && sb == Sign::Negative) return true;
  }
  return false;
}

// Clips a near-plane segment to R; false when less than a segment is left.
bool clip_to_rectangle(Rational& x0, Rational& y0, Rational& x1, Rational& y1, const Frustum& fr) {
  Segment3 s{{x0, y0, Rational(0)}, {x1, y1, Rational(0)}};
  const Rational zero(0), one(1), minus_one(-1);
  const std::array<HalfSpace, 4> sides{HalfSpace{{one, zero, zero}, -Rational(fr.left), {}, {}},
                                       HalfSpace{{minus_one, zero, zero}, Rational(fr.right), {}, {}},
                                       HalfSpace{{zero, one, zero}, -Rational(fr.bottom), {}, {}},
                                       HalfSpace{{zero, minus_one, zero}, Rational(fr.top), {}, {}}};
  for (const HalfSpace& side : sides)
    if (!clip(s, side)) return false;
  x0 = s.a.x;
  y0 = s.a.y;
  x1 = s.b.x;
  y1 = s.b.y;
  return !(x0 == x1 && y0 == y1);
}

// A curve of the near plane, directed lexicographically (x, then y), with the
// point to its left that its delta is evaluated at.
struct PlanarSegment {
  Rational x0, y0, x1, y1;
  RationalVec3 left_point;  // on N, strictly left of the supporting line
};

// Clips to R and directs lexicographically; nothing when degenerate or outside.
std::optional<PlanarSegment> planar_segment(Rational x0, Rational y0, Rational x1, Rational y1, const Frustum& fr) {
  if (!clip_to_rectangle(x0, y0, x1, y1, fr)) return std::nullopt;
  if (x1 < x0 || (x1 == x0 && y1 < y0)) {
    std::swap(x0, x1);
    std::swap(y0, y1);
  }
  // Midpoint plus the left normal (-dy, dx).
  const Rational mx = (x0 + x1) / 2, my = (y0 + y1) / 2;
  RationalVec3 left{mx - (y1 - y0), my + (x1 - x0), Rational(-fr.near)};
  return PlanarSegment{x0, y0, x1, y1, left};
}

Curve make_curve(const PlanarSegment& s, CurveData data) {
  return Curve(Segment2(Point2(ft(s.x0), ft(s.y0)), Point2(ft(s.x1), ft(s.y1))), data);
}

NearCapPoint to_point(const Point2& p) { return {exact_of(p.x()), exact_of(p.y())}; }

// Twice the signed area, exact.
Rational twice_signed_area(const std::vector<NearCapPoint>& ring) {
  Rational a(0);
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const NearCapPoint& p = ring[k];
    const NearCapPoint& q = ring[(k + 1) % ring.size()];
    a += p.x * q.y - q.x * p.y;
  }
  return a;
}

// An interior point of a bounded face: from the midpoint m of a non-vertical
// edge of its outer boundary, go vertically into the face (a counter-clockwise
// outer boundary has the face on its left) halfway to the next edge, or a
// third, a quarter, ... of the way until the point is none of `avoid` (sorted).
// O(edges): used once per build, for the face the walk starts from.
Point2 interior_point(const Arrangement& arr, Arrangement::Face_const_handle f,
                      const std::vector<std::pair<Rational, Rational>>& avoid) {
  auto he = f->outer_ccb();
  while (he->source()->point().x() == he->target()->point().x()) ++he;
  const Arrangement::Halfedge_const_handle chosen = he;
  const Point2 m = CGAL::midpoint(he->source()->point(), he->target()->point());
  const bool up = he->source()->point().x() < he->target()->point().x();  // left-to-right: face above
  std::optional<Kernel::FT> nearest;
  for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
    const Arrangement::Halfedge_const_handle eh = e;
    if (eh == chosen || eh == chosen->twin()) continue;
    const Point2& a = e->source()->point();
    const Point2& b = e->target()->point();
    if ((a.x() < m.x() && b.x() < m.x()) || (a.x() > m.x() && b.x() > m.x())) continue;
    Kernel::FT y;
    if (a.x() == b.x()) {
      y = up ? CGAL::min(a.y(), b.y()) : CGAL::max(a.y(), b.y());  // a vertical edge on the line: its nearest end
    } else {
      y = a.y() + (b.y() - a.y()) * (m.x() - a.x()) / (b.x() - a.x());
    }
    if (up ? !(y > m.y()) : !(y < m.y())) continue;
    if (!nearest || (up ? y < *nearest : y > *nearest)) nearest = y;
  }
  const Kernel::FT other = nearest ? *nearest : (up ? m.y() + 1 : m.y() - 1);
  for (int k = 2;; ++k) {
    const Point2 p(m.x(), m.y() + (other - m.y()) / k);
    if (!std::binary_search(avoid.begin(), avoid.end(),
                            std::pair<Rational, Rational>(exact_of(p.x()), exact_of(p.y()))))
      return p;
  }
}

SamplePoint sample_at(const Point2& p, const Frustum& fr) {
  SamplePoint s;
  s.exact = RationalVec3{exact_of(p.x()), exact_of(p.y()), Rational(-fr.near)};
  s.approx = BoundedVec3{bounded_estimate(s.exact.x), bounded_estimate(s.exact.y), BoundedDouble(-fr.near)};
  return s;
}

// The count of the face across halfedge h from h's incident face, whose count
// is `count`: h's face lies on h's left, so for h directed left to right it
// is the curve's left side (count(left) - count(right) = delta).
std::int64_t count_across(Arrangement::Halfedge_const_handle h, std::int64_t count) {
  const int delta = h->curve().data().delta;
  return h->direction() == CGAL::ARR_LEFT_TO_RIGHT ? count - delta : count + delta;
}

}  // namespace

struct NearCap::Impl {
  Arrangement arr;
  std::unique_ptr<PointLocation> locator;
};

NearCap::NearCap() : impl_(std::make_unique<Impl>()) {}
NearCap::NearCap(NearCap&&) noexcept = default;
NearCap& NearCap::operator=(NearCap&&) noexcept = default;
NearCap::~NearCap() = default;

NearCap NearCap::build(const CameraSpaceScene& cs, std::size_t light, FilterStats* stats) {
  const Frustum& fr = cs.frustum();
  const Rational z0(-fr.near);
  const RationalVec3& l = cs.exact_light(light);
  const Sign light_side_of_near = sign_of(Rational(l.z - z0));
  if (light_side_of_near == Sign::Zero)
    throw Error(ErrorKind::Degenerate,
                cs.scene().source + ": lights[" + std::to_string(light) +
                    "] lies in the near plane: its near-cap pyramid is flat (ZP+ falls back to Z-fail for it)");

  NearCap cap;
  std::vector<Curve> curves;
  // The rectangle: delta 0 (its outside is the unbounded face, never counted).
  {
    const Rational L(fr.left), R(fr.right), B(fr.bottom), T(fr.top);
    const std::array<std::array<Rational, 4>, 4> sides{{{L, B, R, B}, {R, B, R, T}, {L, T, R, T}, {L, B, L, T}}};
    for (const auto& s : sides)
      curves.emplace_back(Segment2(Point2(ft(s[0]), ft(s[1])), Point2(ft(s[2]), ft(s[3]))), CurveData{});
  }

  const std::vector<HalfSpace> pyramid = light_pyramid(l, fr);
  const Rational depth = z0 - l.z;  // projection: x -> l + (x - l) depth / (x.z - l.z)
  auto project = [&](const RationalVec3& x) {
    NEARCAP_CHECK(x.z != l.z);  // only l itself projects to infinity; lights on occluders are rejected at load
    const Rational t = depth / (x.z - l.z);
    return std::pair<Rational, Rational>{l.x + (x.x - l.x) * t, l.y + (x.y - l.y) * t};
  };
  auto add_curve = [&](const PlanarSegment& s, int delta, bool on_cut) {
    curves.push_back(make_curve(s, CurveData{delta, on_cut}));
  };
  // Where a front face only touches the near plane at a vertex, inside R: the
  // count at that point may differ from the face around it (the same reason as
  // CurveData::on_cut); it becomes an isolated vertex of the arrangement.
  std::vector<std::pair<Rational, Rational>> touching_points;

  std::vector<std::vector<Facing>> facing(cs.object_count());
  for (std::size_t o = 0; o < cs.object_count(); ++o) {
    if (!cs.object(o).occluder) continue;
    facing[o] = light_facing(cs, o, light, stats);
    const TriangleMesh& mesh = cs.mesh(o);
    // (1) Silhouette edges inside the pyramid, projected from the light.  The
    // cone side of edge a->d of front face (a, d, c) is the side of the plane
    // (l, a, d) holding c.
    for (const SilhouetteEdge& e : silhouette_edges(mesh, facing[o])) {
      const bool outside = surely_outside(pyramid, cs.vertex(o, e.a), cs.vertex(o, e.d));
      if (stats) stats->record(Predicate::Arrangement, !outside);
      if (outside) continue;
      const RationalVec3 a = cs.exact_vertex(o, e.a), d = cs.exact_vertex(o, e.d);
      Segment3 s{a, d};
      bool inside = true;
      for (const HalfSpace& half : pyramid)
        if (!(inside = clip(s, half))) break;
      if (!inside) continue;
      const auto [x0, y0] = project(s.a);
      const auto [x1, y1] = project(s.b);
      const std::optional<PlanarSegment> ps = planar_segment(x0, y0, x1, y1, fr);
      if (!ps) continue;
      const auto& t = mesh.triangles[e.front_face];
      VertexIndex c = t[0];
      for (VertexIndex v : t)
        if (v != e.a && v != e.d) c = v;
      const Sign cone = orientation(l, a, d, cs.exact_vertex(o, c));
      const Sign left = orientation(l, a, d, ps->left_point);
      NEARCAP_CHECK(cone != Sign::Zero && left != Sign::Zero);
      add_curve(*ps, left == cone ? 1 : -1, false);
      ++cap.silhouette_curves_;
    }
    // (2) Near-plane cuts of front faces (double prefilter on the z-range).
    const double err = cs.max_error(o);
    for (FaceIndex f = 0; f < mesh.triangles.size(); ++f) {
      if (facing[o][f] != Facing::Front) continue;
      const auto& t = mesh.triangles[f];
      double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
      for (int k = 0; k < 3; ++k) {
        zmin = std::min(zmin, cs.vertex_estimate(o, t[k]).z);
        zmax = std::max(zmax, cs.vertex_estimate(o, t[k]).z);
      }
      const bool away = zmin - err > -fr.near || zmax + err < -fr.near;
      if (stats) stats->record(Predicate::Arrangement, !away);
      if (away) continue;
      const std::array<RationalVec3, 3> v{cs.exact_vertex(o, t[0]), cs.exact_vertex(o, t[1]), cs.exact_vertex(o, t[2])};
      std::array<Sign, 3> side{};
      int on_plane = 0;
      for (int k = 0; k < 3; ++k) {
        side[k] = sign_of(Rational(v[k].z - z0));
        on_plane += side[k] == Sign::Zero;
      }
      if (on_plane == 3) {
        // F lies in N: the cone deltas of its edges say +1 into F; when l is
        // beyond N, F is never crossed: -1 into F along its edges.  An edge
        // shared with another front face lying in N is left out: the two
        // corrections cancel.  Not cuts in CurveData's sense: at a point on
        // them F is crossed (l on the camera's side) or not (l beyond) as at
        // generic points, the cone test deciding like that of the silhouettes
        // on the same line; a neighbour leaving N there has its own cut.
        if (light_side_of_near == Sign::Positive) continue;
        for (int k = 0; k < 3; ++k) {
          const FaceIndex g = mesh.neighbours[f][k];
          if (facing[o][g] == Facing::Front) {
            bool g_in_plane = true;
            for (VertexIndex w : mesh.triangles[g]) g_in_plane = g_in_plane && cs.exact_vertex(o, w).z == z0;
            if (g_in_plane) continue;
          }
          const RationalVec3 &u = v[k], &w = v[(k + 1) % 3], &third = v[(k + 2) % 3];
          const std::optional<PlanarSegment> ps = planar_segment(u.x, u.y, w.x, w.y, fr);
          if (!ps) continue;
          // 2-D orientation of (u, w, q), through the 3-D one with apex above N.
          const RationalVec3 apex{u.x, u.y, z0 + 1};
          const bool left_is_inside = orientation(apex, u, w, ps->left_point) == orientation(apex, u, w, third);
          add_curve(*ps, left_is_inside ? -1 : 1, false);
          ++cap.near_plane_cuts_;
        }
        continue;
      }
      // An edge of F in N with the third vertex on l's side: the cut is the
      // cone boundary itself and changes nothing across (top of the file).
      bool cut_adds_nothing = false;
      if (on_plane == 2)
        for (int k = 0; k < 3; ++k) cut_adds_nothing = cut_adds_nothing || side[k] == light_side_of_near;
      std::vector<std::pair<Rational, Rational>> pts;
      for (int k = 0; k < 3; ++k) {
        const int k2 = (k + 1) % 3;
        if (side[k] == Sign::Zero) pts.emplace_back(v[k].x, v[k].y);
        if (side[k] * side[k2] == Sign::Negative) {
          const Rational u = (z0 - v[k].z) / (v[k2].z - v[k].z);
          pts.emplace_back(v[k].x + u * (v[k2].x - v[k].x), v[k].y + u * (v[k2].y - v[k].y));
        }
      }
      if (pts.size() == 1) {  // F touches N at a vertex
        const auto& [x, y] = pts.front();
        if (x >= Rational(fr.left) && x <= Rational(fr.right) && y >= Rational(fr.bottom) && y <= Rational(fr.top))
          touching_points.push_back(pts.front());
      }
      if (pts.size() < 2) continue;
      std::sort(pts.begin(), pts.end());
      const std::optional<PlanarSegment> ps =
          planar_segment(pts.front().first, pts.front().second, pts.back().first, pts.back().second, fr);
      if (!ps) continue;
      // +1 into the far side of F's plane from l.
      const Sign l_side = orientation(v[0], v[1], v[2], l);
      const Sign left = orientation(v[0], v[1], v[2], ps->left_point);
      NEARCAP_CHECK(l_side != Sign::Zero && left != Sign::Zero);
      add_curve(*ps, cut_adds_nothing ? 0 : (left == -l_side ? 1 : -1), true);
      ++cap.near_plane_cuts_;
    }
  }

  Arrangement& arr = cap.impl_->arr;
  CGAL::insert(arr, curves.begin(), curves.end());

  // The count at one interior point, then the walk.
  Arrangement::Face_handle start = arr.faces_end();
  for (auto f = arr.faces_begin(); f != arr.faces_end() && start == arr.faces_end(); ++f)
    if (!f->is_unbounded()) start = f;
  NEARCAP_CHECK(start != arr.faces_end());
  std::sort(touching_points.begin(), touching_points.end());
  touching_points.erase(std::unique(touching_points.begin(), touching_points.end()), touching_points.end());
  const Point2 p0 = interior_point(arr, start, touching_points);
  const std::size_t start_count = near_cap_count_brute_force(cs, light, facing, sample_at(p0, fr), stats);
  start->set_data({true, static_cast<std::int64_t>(start_count)});
  std::deque<Arrangement::Face_handle> queue{start};
  auto visit_ccb = [&](Arrangement::Ccb_halfedge_circulator first, std::int64_t count) {
    auto h = first;
    do {
      Arrangement::Face_handle g = h->twin()->face();
      if (g->is_unbounded()) continue;
      const std::int64_t c = count_across(h, count);
      if (g->data().known) {
        NEARCAP_CHECK_EQ(g->data().value, c);
      } else {
        NEARCAP_CHECK(c >= 0);
        g->set_data({true, c});
        queue.push_back(g);
      }
    } while (++h != first);
  };
  while (!queue.empty()) {
    const Arrangement::Face_handle f = queue.front();
    queue.pop_front();
    const std::int64_t count = f->data().value;
    visit_ccb(f->outer_ccb(), count);
    for (auto hole = f->holes_begin(); hole != f->holes_end(); ++hole) visit_ccb(*hole, count);
  }

  // The coarsest partition: drop the edges with the same count on both sides
  // (overlapping silhouettes whose deltas cancel, ...) unless they lie on a
  // cut, then the vertices they leave redundant.
  std::vector<Arrangement::Halfedge_handle> flat;
  for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
    NEARCAP_CHECK(e->face()->is_unbounded() || e->face()->data().known);
    if (e->face()->is_unbounded() || e->twin()->face()->is_unbounded()) continue;
    if (e->face()->data().value == e->twin()->face()->data().value && !e->curve().data().on_cut) flat.push_back(e);
  }
  for (const auto& e : flat) arr.remove_edge(e);
  std::vector<Arrangement::Vertex_handle> redundant;
  for (auto v = arr.vertices_begin(); v != arr.vertices_end(); ++v)
    if (v->degree() == 2) redundant.push_back(v);
  for (const auto& v : redundant) CGAL::remove_vertex(arr, v);  // false (kept) unless the two curves merge
  for (const auto& [x, y] : touching_points) CGAL::insert_point(arr, Point2(ft(x), ft(y)));

  cap.impl_->locator = std::make_unique<PointLocation>(arr);
  Rational area_sum(0);
  for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
    if (f->is_unbounded()) continue;
    NEARCAP_CHECK(f->data().known);
    NearCapFace face;
    face.count = static_cast<std::size_t>(f->data().value);
    auto he = f->outer_ccb();
    do {
      face.outer.push_back(to_point(he->source()->point()));
    } while (++he != f->outer_ccb());
    Rational twice_area = twice_signed_area(face.outer);
    for (auto hole = f->holes_begin(); hole != f->holes_end(); ++hole) {
      std::vector<NearCapPoint> ring;
      auto h = *hole;
      do {
        ring.push_back(to_point(h->source()->point()));
      } while (++h != *hole);
      twice_area += twice_signed_area(ring);  // clockwise: negative
      face.holes.push_back(std::move(ring));
    }
    face.area_estimate = Rational(twice_area / 2).get_d();
    area_sum += twice_area;
    cap.faces_.push_back(std::move(face));
  }
  // The faces tile R exactly.
  NEARCAP_CHECK(area_sum == 2 * (Rational(fr.right) - Rational(fr.left)) * (Rational(fr.top) - Rational(fr.bottom)));
  return cap;
}

std::size_t NearCap::max_count() const {
  std::size_t m = 0;
  for (const NearCapFace& f : faces_) m = std::max(m, f.count);
  return m;
}

std::size_t NearCap::arrangement_edges() const { return impl_->arr.number_of_edges(); }

std::optional<std::size_t> NearCap::count_at(const Rational& x, const Rational& y) const {
  const auto located = impl_->locator->locate(Point2(ft(x), ft(y)));
  if (const auto* f = boost::get<Arrangement::Face_const_handle>(&located))
    if (!(*f)->is_unbounded()) return static_cast<std::size_t>((*f)->data().value);
  return std::nullopt;
}

}  // namespace nearcap
