// The near-cap arrangement (see near_cap.hpp).  The only translation unit that
// includes CGAL: Epeck with mpq_class as its exact type (CGAL_USE_GMPXX), so
// nearcap's Rational and CGAL's exact numbers are the same type.
#include "nearcap/near_cap.hpp"

#include <CGAL/Arr_extended_dcel.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arr_walk_along_line_point_location.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <algorithm>
#include <limits>

#include "nearcap/error.hpp"
#include "nearcap/light_facing.hpp"
#include "nearcap/segment_crossing.hpp"
#include "nearcap/silhouette.hpp"

namespace nearcap {
namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Point2 = Kernel::Point_2;
using Segment2 = Kernel::Segment_2;
using Traits = CGAL::Arr_segment_traits_2<Kernel>;
using Dcel = CGAL::Arr_face_extended_dcel<Traits, std::size_t>;
using Arrangement = CGAL::Arrangement_2<Traits, Dcel>;
using PointLocation = CGAL::Arr_walk_along_line_point_location<Arrangement>;

static_assert(std::is_same_v<Kernel::FT::Exact_type, Rational>, "Epeck must run on mpq_class (CGAL_USE_GMPXX)");

Rational exact_of(const Kernel::FT& v) { return CGAL::exact(v); }
Kernel::FT ft(const Rational& r) { return Kernel::FT(r); }

// A 3-D segment in camera space, exact.
struct Segment3 {
  RationalVec3 a, b;
};

// Clips [s.a, s.b] to the closed half-space f(x) >= 0, f affine (h.x + h0).
bool clip(Segment3& s, const RationalVec3& h, const Rational& h0) {
  const Rational fa = dot(h, s.a) + h0, fb = dot(h, s.b) + h0;
  if (sgn(fa) < 0 && sgn(fb) < 0) return false;
  if (sgn(fa) >= 0 && sgn(fb) >= 0) return true;
  const Rational t = fa / (fa - fb);
  const RationalVec3 x{s.a.x + t * (s.b.x - s.a.x), s.a.y + t * (s.b.y - s.a.y), s.a.z + t * (s.b.z - s.a.z)};
  if (sgn(fa) < 0)
    s.a = x;
  else
    s.b = x;
  return true;
}

// The light pyramid: convex hull of l and the near rectangle, as half-spaces.
struct Pyramid {
  std::vector<std::pair<RationalVec3, Rational>> halfspaces;  // h.x + h0 >= 0
};

Pyramid light_pyramid(const RationalVec3& l, const Frustum& fr) {
  const Rational z0(-fr.near);
  const std::array<RationalVec3, 4> corner{RationalVec3{Rational(fr.left), Rational(fr.bottom), z0},
                                           RationalVec3{Rational(fr.right), Rational(fr.bottom), z0},
                                           RationalVec3{Rational(fr.right), Rational(fr.top), z0},
                                           RationalVec3{Rational(fr.left), Rational(fr.top), z0}};
  const RationalVec3 centre{(Rational(fr.left) + Rational(fr.right)) / 2, (Rational(fr.bottom) + Rational(fr.top)) / 2,
                            z0};
  Pyramid p;
  for (int k = 0; k < 4; ++k) {
    RationalVec3 n = cross(corner[k] - l, corner[(k + 1) % 4] - l);
    Rational h0 = -dot(n, l);
    if (sgn(Rational(dot(n, centre) + h0)) < 0) {
      n = RationalVec3{-n.x, -n.y, -n.z};
      h0 = -h0;
    }
    p.halfspaces.emplace_back(n, h0);
  }
  // The near plane's side holding the light: s (z - z0) >= 0.
  const int s = sgn(Rational(l.z - z0));
  p.halfspaces.emplace_back(RationalVec3{Rational(0), Rational(0), Rational(s)}, Rational(-s) * z0);
  return p;
}

bool clip_to_rectangle(Rational& x0, Rational& y0, Rational& x1, Rational& y1, const Frustum& fr) {
  Segment3 s{{x0, y0, Rational(0)}, {x1, y1, Rational(0)}};
  const Rational l(fr.left), r(fr.right), b(fr.bottom), t(fr.top);
  const Rational zero(0), one(1), minus_one(-1);
  if (!clip(s, {one, zero, zero}, -l) || !clip(s, {minus_one, zero, zero}, r) || !clip(s, {zero, one, zero}, -b) ||
      !clip(s, {zero, minus_one, zero}, t))
    return false;
  x0 = s.a.x;
  y0 = s.a.y;
  x1 = s.b.x;
  y1 = s.b.y;
  return !(x0 == x1 && y0 == y1);
}

NearCapPoint to_point(const Point2& p) { return {exact_of(p.x()), exact_of(p.y())}; }

double shoelace(const std::vector<NearCapPoint>& ring) {
  double a = 0;
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const NearCapPoint& p = ring[k];
    const NearCapPoint& q = ring[(k + 1) % ring.size()];
    a += p.x.get_d() * q.y.get_d() - q.x.get_d() * p.y.get_d();
  }
  return a / 2;
}

// An interior point of a bounded face: from the midpoint m of a non-vertical
// edge of its outer boundary, go vertically into the face (a counter-clockwise
// outer boundary has the face on its left) halfway to the next edge.
Point2 interior_point(const Arrangement& arr, Arrangement::Face_const_handle f) {
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
      // A vertical edge on the line: its nearest end.
      y = up ? CGAL::min(a.y(), b.y()) : CGAL::max(a.y(), b.y());
    } else {
      y = a.y() + (b.y() - a.y()) * (m.x() - a.x()) / (b.x() - a.x());
    }
    if (up ? !(y > m.y()) : !(y < m.y())) continue;
    if (!nearest || (up ? y < *nearest : y > *nearest)) nearest = y;
  }
  const Kernel::FT other = nearest ? *nearest : (up ? m.y() + 1 : m.y() - 1);
  return Point2(m.x(), (m.y() + other) / 2);
}

SamplePoint sample_at(const Point2& p, const Frustum& fr) {
  SamplePoint s;
  s.exact = RationalVec3{exact_of(p.x()), exact_of(p.y()), Rational(-fr.near)};
  auto bounded = [](const Rational& r) {
    const double v = r.get_d();  // truncation: |error| < one ulp of v
    return BoundedDouble(v, std::fabs(v) * 0x1p-52 + std::numeric_limits<double>::denorm_min());
  };
  s.approx = BoundedVec3{bounded(s.exact.x), bounded(s.exact.y), BoundedDouble(-fr.near)};
  return s;
}

}  // namespace

struct NearCap::Impl {
  Arrangement arr;
  std::unique_ptr<PointLocation> locator;
  Frustum frustum;
};

NearCap::NearCap() : impl_(std::make_unique<Impl>()) {}
NearCap::NearCap(NearCap&&) noexcept = default;
NearCap& NearCap::operator=(NearCap&&) noexcept = default;
NearCap::~NearCap() = default;

NearCap NearCap::build(const CameraSpaceScene& cs, std::size_t light, FilterStats* stats) {
  const Frustum& fr = cs.frustum();
  const Rational z0(-fr.near);
  const RationalVec3& l = cs.exact_light(light);
  if (l.z == z0)
    throw Error(ErrorKind::Degenerate,
                cs.scene().source + ": lights[" + std::to_string(light) +
                    "] lies in the near plane: its near-cap pyramid is flat (ZP+ falls back to Z-fail for it)");

  NearCap cap;
  cap.impl_->frustum = fr;
  std::vector<Segment2> curves;
  auto add_curve = [&](Rational x0, Rational y0, Rational x1, Rational y1) {
    if (!clip_to_rectangle(x0, y0, x1, y1, fr)) return false;
    curves.emplace_back(Point2(ft(x0), ft(y0)), Point2(ft(x1), ft(y1)));
    return true;
  };
  // The rectangle.
  const Rational L(fr.left), R(fr.right), B(fr.bottom), T(fr.top);
  curves.emplace_back(Point2(ft(L), ft(B)), Point2(ft(R), ft(B)));
  curves.emplace_back(Point2(ft(R), ft(B)), Point2(ft(R), ft(T)));
  curves.emplace_back(Point2(ft(R), ft(T)), Point2(ft(L), ft(T)));
  curves.emplace_back(Point2(ft(L), ft(T)), Point2(ft(L), ft(B)));

  const Pyramid pyramid = light_pyramid(l, fr);
  const Rational depth = z0 - l.z;  // projection: x -> l + (x - l) depth / (x.z - l.z)
  std::vector<std::vector<Facing>> facing(cs.object_count());
  for (std::size_t o = 0; o < cs.object_count(); ++o) {
    if (!cs.object(o).occluder) continue;
    facing[o] = light_facing(cs, o, light, stats);
    const TriangleMesh& mesh = cs.mesh(o);
    // (1) Silhouette edges inside the pyramid, projected from the light.
    for (const SilhouetteEdge& e : silhouette_edges(mesh, facing[o])) {
      Segment3 s{cs.exact_vertex(o, e.a), cs.exact_vertex(o, e.d)};
      bool inside = true;
      for (const auto& [h, h0] : pyramid.halfspaces)
        if (!(inside = clip(s, h, h0))) break;
      if (!inside) continue;
      auto project = [&](const RationalVec3& x) {
        const Rational t = depth / (x.z - l.z);
        return std::pair<Rational, Rational>{l.x + (x.x - l.x) * t, l.y + (x.y - l.y) * t};
      };
      const auto [x0, y0] = project(s.a);
      const auto [x1, y1] = project(s.b);
      if (add_curve(x0, y0, x1, y1)) ++cap.silhouette_curves_;
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
      if (zmin - err > -fr.near || zmax + err < -fr.near) continue;
      const std::array<RationalVec3, 3> v{cs.exact_vertex(o, t[0]), cs.exact_vertex(o, t[1]), cs.exact_vertex(o, t[2])};
      std::array<int, 3> side{};
      for (int k = 0; k < 3; ++k) side[k] = sgn(Rational(v[k].z - z0));
      if (side[0] == 0 && side[1] == 0 && side[2] == 0) {
        // The face lies in the near plane: its edges bound its region.
        for (int k = 0; k < 3; ++k)
          if (add_curve(v[k].x, v[k].y, v[(k + 1) % 3].x, v[(k + 1) % 3].y)) ++cap.near_plane_cuts_;
        continue;
      }
      std::vector<std::pair<Rational, Rational>> pts;
      for (int k = 0; k < 3; ++k) {
        const int k2 = (k + 1) % 3;
        if (side[k] == 0) pts.emplace_back(v[k].x, v[k].y);
        if (side[k] * side[k2] < 0) {
          const Rational u = (z0 - v[k].z) / (v[k2].z - v[k].z);
          pts.emplace_back(v[k].x + u * (v[k2].x - v[k].x), v[k].y + u * (v[k2].y - v[k].y));
        }
      }
      if (pts.size() < 2) continue;
      std::sort(pts.begin(), pts.end());
      if (add_curve(pts.front().first, pts.front().second, pts.back().first, pts.back().second)) ++cap.near_plane_cuts_;
    }
  }

  Arrangement& arr = cap.impl_->arr;
  CGAL::insert(arr, curves.begin(), curves.end());
  cap.impl_->locator = std::make_unique<PointLocation>(arr);

  for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
    if (f->is_unbounded()) continue;
    const Point2 p = interior_point(arr, f);
    const std::size_t count = near_cap_count_brute_force(cs, light, facing, sample_at(p, fr), stats);
    f->set_data(count);
    NearCapFace face;
    face.count = count;
    auto he = f->outer_ccb();
    do {
      face.outer.push_back(to_point(he->source()->point()));
    } while (++he != f->outer_ccb());
    face.area_estimate = shoelace(face.outer);
    for (auto hole = f->holes_begin(); hole != f->holes_end(); ++hole) {
      std::vector<NearCapPoint> ring;
      auto h = *hole;
      do {
        ring.push_back(to_point(h->source()->point()));
      } while (++h != *hole);
      face.area_estimate += shoelace(ring);  // clockwise: negative
      face.holes.push_back(std::move(ring));
    }
    cap.faces_.push_back(std::move(face));
  }
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
    if (!(*f)->is_unbounded()) return (*f)->data();
  return std::nullopt;
}

}  // namespace nearcap
