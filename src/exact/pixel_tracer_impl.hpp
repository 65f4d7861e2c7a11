// The per-pixel reference tracer's internals (private to src/exact/): the
// triangle lists, grids and filtered predicates that pixel_reference.cpp
// traces pixels with and square_constancy.cpp proves constant statuses with.
// See include/nearcap/exact/pixel_reference.hpp for the forms.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/collaborative_call_once.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "lazy_table.hpp"
#include "nearcap/exact/eye_setup.hpp"
#include "nearcap/exact/light_facing.hpp"
#include "nearcap/exact/light_setup.hpp"
#include "nearcap/exact/perturbation.hpp"
#include "nearcap/exact/pixel_reference.hpp"
#include "nearcap/exact/segment_crossing.hpp"
#include "vector_pool.hpp"

namespace nearcap {

using BoundedForm = AffineForm<BoundedDouble>;
using ExactForm = AffineForm<Rational>;

// dot(a, b) and AffineForm::at in BoundedDouble (the same operations, so
// the same value and bound), written out inline for the per-candidate loops:
// the compiler keeps the template dot out of line, and a call per form (and
// a copy of the form) costs more than its arithmetic.
inline BoundedDouble bounded_dot(const BoundedVec3& a, const BoundedVec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline BoundedDouble form_value_at(const BoundedVec3& h, const BoundedDouble& h0, const BoundedVec3& p) {
  return bounded_dot(h, p) + h0;
}

// perturbed_sign (perturbation.hpp) of the form (h, h0) at p, the filter
// evaluated by form_value_at; `exact_form()` and `exact_point()` as there.
template <class ExactForm, class ExactPoint>
Sign perturbed_form_sign(Predicate pred, FilterStats* stats, const BoundedVec3& p, const BoundedVec3& h,
                         const BoundedDouble& h0, ExactForm&& exact_form, ExactPoint&& exact_point) {
  if (const auto s = form_value_at(h, h0, p).sign(); s && *s != Sign::Zero) {
    if (stats) stats->record(pred, false);
    return *s;
  }
  if (stats) stats->record(pred, true);
  return perturbed_sign(exact_form(), exact_point());
}

// A sample point of the window (a pixel centre, or a sub-pixel point of the
// crack distance): certified estimate now, exact rational on first demand.
class PixelPoint {
 public:
  PixelPoint(const Frustum& fr, int width, int height, const WindowPoint& w)
      : fr_(fr), width_(width), height_(height), w_(w), approx_(window_point_estimate(fr, width, height, w)) {}
  const BoundedVec3& approx() const { return approx_; }
  Vec3d estimate() const { return {approx_.x.v, approx_.y.v, approx_.z.v}; }
  double error() const { return std::max(approx_.x.e, approx_.y.e); }
  const RationalVec3& exact() const {
    if (!exact_) exact_ = window_point_exact(fr_, width_, height_, w_);
    return *exact_;
  }

 private:
  const Frustum& fr_;
  int width_, height_;
  WindowPoint w_;
  BoundedVec3 approx_;
  mutable std::optional<RationalVec3> exact_;
};

// A triangle's camera-space plane data, estimated and exact.
template <class T>
struct PlaneData {
  Vec3<T> n;  // (b - a) x (c - a)
  T d;        // det(a, b, c) = n . a
};
template <class T>
PlaneData<T> plane_data(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c) {
  const Vec3<T> n = cross(b - a, c - a);
  return {n, T(dot(n, a))};
}

// A triangle as the view rays see it.
struct EyeTriangle {
  std::array<BoundedVec3, 3> edge;  // a x b, b x c, c x a
  PlaneData<BoundedDouble> plane;
  std::uint32_t object;
  FaceIndex face;
  Sign sigma;  // sign(d), exact: Zero when the plane passes through the eye
  // Every vertex certainly on the eye's side of the near plane (z > -near):
  // no view ray meets it beyond the near plane (the crack distance's shortcut).
  bool before_near = false;
  // Every vertex exactly in the near plane (z = -near, exact test): GL's
  // clip volume is closed there (-w <= z), so the triangle counts as beyond
  // the near plane, where the perturbed sample point would put it in front.
  bool in_near_plane = false;
};

// A light-front-facing occluder triangle as the segments from the light see it.
struct LightTriangle {
  std::array<BoundedVec3, 3> g;  // (u - l) x (v - l) for edges ab, bc, ca
  std::array<BoundedDouble, 3> g0;
  PlaneData<BoundedDouble> plane;
  std::uint32_t object;
  FaceIndex face;
  Sign light_side;          // orientation sign of the light w.r.t. (a, b, c): handedness
  std::uint32_t eye_index;  // the same triangle in the eye list
};

// The first surface hit along the view ray, with what the shadow test needs.
struct Hit {
  std::uint32_t eye_index;
  Sign sigma;       // sign(d)
  BoundedDouble t;  // d / n.P estimate (may be uncertain)
};

// The sign of d = det(a, b, c) of triangle (object, f): exact.
inline Sign plane_offset_sign(const CameraSpaceScene& cs, std::uint32_t object, FaceIndex f,
                              const PlaneData<BoundedDouble>& plane, FilterStats* stats) {
  return filtered_sign(
      Predicate::RayHit, stats, [&] { return plane.d; },
      [&] {
        const auto& t = cs.mesh(object).triangles[f];
        return plane_data(cs.exact_vertex(object, t[0]), cs.exact_vertex(object, t[1]), cs.exact_vertex(object, t[2]))
            .d;
      });
}

// Triangle f of object o as the view rays see it.
inline EyeTriangle make_eye_triangle(const CameraSpaceScene& cs, std::uint32_t o, FaceIndex f) {
  const auto& t = cs.mesh(o).triangles[f];
  const BoundedVec3 a = cs.vertex(o, t[0]), b = cs.vertex(o, t[1]), c = cs.vertex(o, t[2]);
  EyeTriangle et{{cross(a, b), cross(b, c), cross(c, a)}, plane_data(a, b, c), o, f, Sign::Zero};
  et.sigma = plane_offset_sign(cs, o, f, et.plane, nullptr);
  const BoundedDouble near(cs.frustum().near);
  et.before_near = true;
  bool maybe_in_near_plane = true;
  for (const BoundedVec3* v : {&a, &b, &c}) {
    const std::optional<Sign> s = (v->z + near).sign();
    et.before_near = et.before_near && s == Sign::Positive;
    maybe_in_near_plane = maybe_in_near_plane && (!s || *s == Sign::Zero);
  }
  if (maybe_in_near_plane) {
    const Rational minus_near(-cs.frustum().near);
    et.in_near_plane = true;
    for (int k = 0; k < 3; ++k) et.in_near_plane = et.in_near_plane && cs.exact_vertex(o, t[k]).z == minus_near;
  }
  return et;
}

// The camera-dependent, light-independent side (eye_setup.hpp).  Triangles
// are numbered object by object, faces in order (the eye index).
struct EyeSetup {
  std::vector<std::size_t> first_face;  // per object, then the total
  std::unique_ptr<CentralGrid> grid;    // camera space, around the eye
  LazyTable<EyeTriangle> triangles;     // by eye index, computed on first read

  std::uint32_t object_of(std::uint32_t eye_index) const {
    const auto it = std::upper_bound(first_face.begin(), first_face.end(), static_cast<std::size_t>(eye_index));
    return static_cast<std::uint32_t>(it - first_face.begin() - 1);
  }
  // Eye triangle `i`; `cs` is any camera-space scene with this setup's key.
  const EyeTriangle& triangle(const CameraSpaceScene& cs, std::uint32_t i) const {
    return triangles.get(i, [&] {
      const std::uint32_t o = object_of(i);
      return make_eye_triangle(cs, o, static_cast<FaceIndex>(i - first_face[o]));
    });
  }
};

struct PixelReferenceTracer::Impl {
  const CameraSpaceScene& cs;
  std::size_t light;
  // The light-independent eye side (eye_setup.hpp): the grid around the eye
  // and the eye triangles, in camera space.
  std::shared_ptr<const EyeSetup> eye_side;
  const CentralGrid* eye_grid = nullptr;  // eye_side->grid
  // The camera-independent light side (light_setup.hpp): the facing, the
  // lit triangles and their grid around the light, in world space.
  std::shared_ptr<const LightSetup> setup;
  const CentralGrid* light_grid = nullptr;  // setup->grid
  // The lit triangles' camera-space data, by index into setup->lit,
  // computed on first read.
  LazyTable<LightTriangle> lit;
  WorldDirections to_world;
  double setup_ms = 0;  // building this (PixelReferenceTracer's constructor)
  mutable tbb::collaborative_once_flag region_light_grid_once;
  mutable std::unique_ptr<CentralGrid> region_light_grid_;
  // Exact coplanarity of (light triangle, visible triangle) pairs, per thread:
  // the two triangles of a flat quad make the side form vanish identically,
  // and without this cache each such pixel would pay for rationals.
  mutable tbb::enumerable_thread_specific<std::unordered_map<std::uint64_t, bool>> coplanar_cache;

  Impl(const CameraSpaceScene& scene, std::size_t k, LightSetupCache* cache, EyeSetupCache* eye_cache)
      : cs(scene), light(k), to_world(scene.scene().camera.view) {
    // The light side and the eye side (each from its cache, or built) side
    // by side.  The per-triangle data of both is computed on first read.
    tbb::parallel_invoke([&] { setup = light_setup(cs, light, cache); }, [&] { eye_side = eye_setup(cs, eye_cache); });
    eye_grid = eye_side->grid.get();
    // The faces of the grid around the eye that the pixels' view rays read
    // (those the near rectangle meets), built here so that the setup holds
    // them; other faces are built if a query reaches them.
    const Frustum& fr = cs.frustum();
    eye_grid->build_faces_meeting({fr.left, fr.bottom, -fr.near}, {fr.right, fr.top, -fr.near});
    light_grid = setup->grid.get();
    lit = LazyTable<LightTriangle>(setup->lit.size());
  }

  const EyeTriangle& eye(std::uint32_t eye_index) const { return eye_side->triangle(cs, eye_index); }

  // Lit triangle m (an index into setup->lit) as the segments from the light see it.
  const LightTriangle& light_triangle(std::uint32_t m) const {
    return lit.get(m, [&] {
      const std::uint32_t eye_index = setup->lit[m];
      const EyeTriangle& et = eye(eye_index);
      const auto& t = cs.mesh(et.object).triangles[et.face];
      const std::array<BoundedVec3, 3> v{cs.vertex(et.object, t[0]), cs.vertex(et.object, t[1]),
                                         cs.vertex(et.object, t[2])};
      const BoundedVec3& l = cs.light(light);
      LightTriangle lt;
      for (int e = 0; e < 3; ++e) {
        lt.g[e] = cross(v[e] - l, v[(e + 1) % 3] - l);
        lt.g0[e] = -dot(lt.g[e], l);
      }
      lt.plane = et.plane;
      lt.object = et.object;
      lt.face = et.face;
      lt.light_side = cs.handedness(et.object);
      lt.eye_index = eye_index;
      return lt;
    });
  }

  // ---- exact data, computed only when a filter fails ----------------------
  std::array<RationalVec3, 3> exact_triangle(std::uint32_t object, FaceIndex f) const {
    const auto& t = cs.mesh(object).triangles[f];
    return {cs.exact_vertex(object, t[0]), cs.exact_vertex(object, t[1]), cs.exact_vertex(object, t[2])};
  }
  PlaneData<Rational> exact_plane(std::uint32_t object, FaceIndex f) const {
    const auto v = exact_triangle(object, f);
    return plane_data(v[0], v[1], v[2]);
  }
  Vec3<Rational> exact_g(const LightTriangle& lt, int e) const {
    const auto v = exact_triangle(lt.object, lt.face);
    const RationalVec3& l = cs.exact_light(light);
    return cross(v[e] - l, v[(e + 1) % 3] - l);
  }

  // Does the view ray through P hit t beyond p and before the far plane?
  // Returns sign(d) on a hit, Zero otherwise.
  Sign ray_hits(const EyeTriangle& t, const PixelPoint& p, FilterStats* stats) const {
    const Sign sigma = t.sigma;
    if (sigma == Sign::Zero) return Sign::Zero;
    auto exact_point = [&]() -> const RationalVec3& { return p.exact(); };
    for (int e = 0; e < 3; ++e) {
      const Sign s = perturbed_form_sign(
          Predicate::RayHit, stats, p.approx(), t.edge[e], BoundedDouble(0.0),
          [&] {
            const auto v = exact_triangle(t.object, t.face);
            return ExactForm{cross(v[e], v[(e + 1) % 3]), Rational(0)};
          },
          exact_point);
      if (s != sigma) return Sign::Zero;
    }
    const Frustum& fr = cs.frustum();
    const Sign beyond_p = perturbed_sign(
        Predicate::RayHit, stats, p.approx(),
        [&] {
          return BoundedForm{BoundedDouble(-1.0) * t.plane.n, t.plane.d};
        },
        [&] {
          auto pl = exact_plane(t.object, t.face);
          return ExactForm{Rational(-1) * pl.n, pl.d};
        },
        exact_point);
    if (beyond_p != sigma && !t.in_near_plane) return Sign::Zero;
    const Sign before_far = perturbed_sign(
        Predicate::RayHit, stats, p.approx(),
        [&] {
          return BoundedForm{BoundedDouble(fr.far) * t.plane.n, BoundedDouble(-fr.near) * t.plane.d};
        },
        [&] {
          auto pl = exact_plane(t.object, t.face);
          return ExactForm{Rational(fr.far) * pl.n, Rational(-fr.near) * pl.d};
        },
        exact_point);
    if (before_far != sigma) return Sign::Zero;
    return sigma;
  }

  // Is hit h1 (on t1) strictly before hit h2 (on t2)?  Coplanar: lower index.
  bool before(const EyeTriangle& t1, Sign s1, const EyeTriangle& t2, Sign s2, const PixelPoint& p,
              FilterStats* stats) const {
    const Sign s = perturbed_sign(
        Predicate::RayHit, stats, p.approx(),
        [&] {
          return BoundedForm{t1.plane.d * t2.plane.n - t2.plane.d * t1.plane.n, BoundedDouble(0.0)};
        },
        [&] {
          const auto p1 = exact_plane(t1.object, t1.face), p2 = exact_plane(t2.object, t2.face);
          return ExactForm{p1.d * p2.n - p2.d * p1.n, Rational(0)};
        },
        [&]() -> const RationalVec3& { return p.exact(); });
    if (s == Sign::Zero) return std::make_pair(t1.object, t1.face) < std::make_pair(t2.object, t2.face);
    return s * s1 * s2 == Sign::Negative;
  }

  BoundedDouble hit_parameter(const EyeTriangle& t, const PixelPoint& p) const {
    const BoundedDouble np = dot(t.plane.n, p.approx());
    if (!np.sign() || *np.sign() == Sign::Zero) return BoundedDouble(0.0, std::numeric_limits<double>::infinity());
    return t.plane.d / np;
  }

  template <class Range>
  std::optional<Hit> first_hit(const Range& candidates, const PixelPoint& p, bool early_exit,
                               FilterStats* stats) const {
    std::optional<Hit> best;
    double axis_upper = std::numeric_limits<double>::infinity();
    const Vec3d pe = p.estimate();
    const double m = std::max({std::fabs(pe.x), std::fabs(pe.y), std::fabs(pe.z)}) * (1.0 + 0x1p-40);
    for (const auto& entry : candidates) {
      if (early_exit && entry.axis_lower_bound > axis_upper) break;
      if (!candidates.may_contain(entry.id)) continue;  // the view ray certainly misses it
      const EyeTriangle& t = eye(entry.id);
      const Sign s = ray_hits(t, p, stats);
      if (s == Sign::Zero) continue;
      if (!best || before(t, s, eye(best->eye_index), best->sigma, p, stats)) {
        best = Hit{entry.id, s, hit_parameter(t, p)};
        const double t_hi = best->t.v + best->t.e;
        axis_upper = std::isfinite(t_hi) ? t_hi * m * (1.0 + 0x1p-40) : std::numeric_limits<double>::infinity();
      }
    }
    return best;
  }

  // Does [l, p] cross lt?  (The near-cap test.)
  bool cap_crosses(const LightTriangle& lt, const PixelPoint& p, FilterStats* stats) const {
    auto exact_point = [&]() -> const RationalVec3& { return p.exact(); };
    const Sign side = perturbed_sign(
        Predicate::SegmentCrossing, stats, p.approx(),
        [&] {
          return BoundedForm{lt.plane.n, -lt.plane.d};
        },
        [&] {
          auto pl = exact_plane(lt.object, lt.face);
          return ExactForm{pl.n, Rational(-pl.d)};
        },
        exact_point);
    if (side != -lt.light_side) return false;
    Sign first = Sign::Zero;
    for (int e = 0; e < 3; ++e) {
      const Sign s = perturbed_sign(
          Predicate::SegmentCrossing, stats, p.approx(),
          [&] {
            return BoundedForm{lt.g[e], lt.g0[e]};
          },
          [&] {
            const Vec3<Rational> g = exact_g(lt, e);
            return ExactForm{g, Rational(-dot(g, cs.exact_light(light)))};
          },
          exact_point);
      if (s == Sign::Zero || (e > 0 && s != first)) return false;
      first = s;
    }
    return true;
  }

  bool coplanar(const LightTriangle& lt, std::uint32_t q_index) const {
    // Filter: a vertex of q certainly off T's plane decides (almost always).
    const EyeTriangle& q_tri = eye(q_index);
    const auto& q_vertices = cs.mesh(q_tri.object).triangles[q_tri.face];
    for (int k = 0; k < 3; ++k) {
      const BoundedDouble side = dot(lt.plane.n, cs.vertex(q_tri.object, q_vertices[k])) - lt.plane.d;
      if (const auto s = side.sign(); s && *s != Sign::Zero) return false;
    }
    auto& cache = coplanar_cache.local();
    const std::uint64_t key = (static_cast<std::uint64_t>(lt.eye_index) << 32) | q_index;
    if (const auto it = cache.find(key); it != cache.end()) return it->second;
    const EyeTriangle& q = eye(q_index);
    const auto t = exact_triangle(lt.object, lt.face);
    const auto v = exact_triangle(q.object, q.face);
    bool flat = true;
    for (int k = 0; k < 3 && flat; ++k) flat = sign_of(orientation_determinant(t[0], t[1], t[2], v[k])) == Sign::Zero;
    cache.emplace(key, flat);
    return flat;
  }

  // Does the open segment (l, q) cross lt, q the hit on eye triangle `q_tri`?
  // `q_point`, when given, is a certified estimate of the hit point q = t P
  // (hit.t * p): the forms below are (n_q.P) times forms in q,
  //   (d_q g + g0 n_q).P      = (n_q.P) (g.q + g0),
  //   (d_q n_T - d_T n_q).P   = (n_q.P) (n_T.q - d_T),
  // with sign(n_q.P) = sigma (t > 0), so a certain sign of the forms in q
  // decides with one bounded dot product each; an uncertain one falls back
  // to the forms in P (perturbed, then exact).
  bool shadow_crosses(const LightTriangle& lt, const Hit& hit, const PixelPoint& p, FilterStats* stats,
                      const BoundedVec3* q_point = nullptr) const {
    // q's own triangle: crossed by (l, q-), q- just before q on the view ray,
    // exactly when the eye sees it from behind (sigma = handedness; lit
    // triangles face the light, light_side = handedness).
    if (lt.eye_index == hit.eye_index) return hit.sigma == lt.light_side;
    if (q_point) {
      // The edges: sign(g.q + g0) equal and non-zero for the three edges.
      std::optional<Sign> edge[3];
      for (int e = 0; e < 3; ++e) {
        edge[e] = (dot(lt.g[e], *q_point) + lt.g0[e]).sign();
        if (edge[e] && *edge[e] == Sign::Zero) edge[e].reset();
        for (int k = 0; k < e; ++k)
          if (edge[e] && edge[k] && *edge[e] != *edge[k]) {
            if (stats) stats->record(Predicate::ShadowCrossing, false);
            return false;  // certainly outside one edge
          }
      }
      if (edge[0] && edge[1] && edge[2]) {
        const auto side = (dot(lt.plane.n, *q_point) - lt.plane.d).sign();
        if (side && *side != Sign::Zero) {
          if (stats) stats->record(Predicate::ShadowCrossing, false);
          return *side == -lt.light_side;
        }
      }
    }
    const EyeTriangle& q = eye(hit.eye_index);
    auto exact_point = [&]() -> const RationalVec3& { return p.exact(); };
    // The edge tests first: they reject almost every candidate, and the side
    // test is the one that nears zero (q close to T's plane, e.g. T adjacent
    // to q's own triangle).
    Sign first = Sign::Zero;
    for (int e = 0; e < 3; ++e) {
      const Sign s = perturbed_sign(
          Predicate::ShadowCrossing, stats, p.approx(),
          [&] {
            return BoundedForm{q.plane.d * lt.g[e] + lt.g0[e] * q.plane.n, BoundedDouble(0.0)};
          },
          [&] {
            const auto pq = exact_plane(q.object, q.face);
            const Vec3<Rational> g = exact_g(lt, e);
            const Rational g0 = -dot(g, cs.exact_light(light));
            return ExactForm{pq.d * g + g0 * pq.n, Rational(0)};
          },
          exact_point);
      if (s == Sign::Zero || (e > 0 && s != first)) return false;
      first = s;
    }
    const BoundedDouble side_value = dot(q.plane.d * lt.plane.n - lt.plane.d * q.plane.n, p.approx());
    Sign side;
    if (const auto s = side_value.sign(); s && *s != Sign::Zero) {
      if (stats) stats->record(Predicate::ShadowCrossing, false);
      side = *s;
    } else if (coplanar(lt, hit.eye_index)) {
      return false;  // the form vanishes identically: q lies in T's plane
    } else {
      if (stats) stats->record(Predicate::ShadowCrossing, true);
      const auto pq = exact_plane(q.object, q.face), pt = exact_plane(lt.object, lt.face);
      side = perturbed_sign(ExactForm{pq.d * pt.n - pt.d * pq.n, Rational(0)}, p.exact());
    }
    return side * hit.sigma == -lt.light_side;
  }

  // The light-grid query for direction w = target - l, target's estimate within
  // its certified error: the camera-space direction mapped to world space,
  // where the grid is; nothing certain -> every front-facing triangle.
  CentralGrid::EntryRange light_candidates(const BoundedVec3& target) const {
    const BoundedVec3 w = target - cs.light(light);
    const double err = std::max({w.x.e, w.y.e, w.z.e});
    if (!std::isfinite(err)) return light_grid->all();
    double world_error = 0;
    const Vec3d ww = to_world.apply({w.x.v, w.y.v, w.z.v}, err, world_error);
    if (!std::isfinite(world_error)) return light_grid->all();
    return light_grid->candidates(ww, world_error);
  }
  // The lit triangles binned around the light in CAMERA space, for the crack
  // distance's region queries (crack_distance.cpp).  A region proof fails on
  // any listed triangle it cannot prove never crossed, so a level depends on
  // which candidates a grid lists, not only on the geometry; this is the grid
  // the levels are defined with.  Built on the first region query (a frame
  // whose wrong pixels are measured); the pixel traces use the world-space
  // grid, whose candidates never change an answer.
  const CentralGrid& region_light_grid() const {
    tbb::collaborative_call_once(region_light_grid_once, [&] {
      const BoundedVec3& l = cs.light(light);
      std::vector<CentralGrid::Triangle> items = VectorPool<CentralGrid::Triangle>::instance().take(lit.size());
      items.resize(lit.size());
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lit.size(), 1024),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t m = r.begin(); m < r.end(); ++m) {
                            const std::uint32_t eye_index = setup->lit[m];
                            const std::uint32_t o = eye_side->object_of(eye_index);
                            const auto& t = cs.mesh(o).triangles[eye_index - eye_side->first_face[o]];
                            items[m] = CentralGrid::Triangle{
                                {cs.vertex_estimate(o, t[0]), cs.vertex_estimate(o, t[1]), cs.vertex_estimate(o, t[2])},
                                cs.max_error(o),
                                static_cast<std::uint32_t>(m)};
                          }
                        });
      region_light_grid_ = std::make_unique<CentralGrid>(Vec3d{l.x.v, l.y.v, l.z.v}, std::max({l.x.e, l.y.e, l.z.e}),
                                                         std::move(items), 1.0);
    });
    return *region_light_grid_;
  }

  // No light triangle remembered (ShadowHint).
  static constexpr std::uint32_t kNoShadower = std::numeric_limits<std::uint32_t>::max();

  // content Full: the near-cap count and the stencil count.  ShadowStatus:
  // no near-cap count, and the stencil is 1 at the first crossing found (0
  // when none is); *last_shadower, when given, is the light triangle that
  // shadowed the caller's previous pixel: it is tried first (neighbouring
  // pixels are mostly shadowed by the same triangle) and updated.  Either
  // way every answer is exact; the hint changes only the order of the tests.
  PixelSample trace(const WindowPoint& w, bool accelerated, FilterStats* stats,
                    PixelContent content = PixelContent::Full, std::uint32_t* last_shadower = nullptr) const {
    const Scene& scene = cs.scene();
    const PixelPoint p(cs.frustum(), scene.camera.width, scene.camera.height, w);
    PixelSample out;
    if (content == PixelContent::Full) {
      const auto cap_candidates = accelerated ? light_candidates(p.approx()) : light_grid->all();
      for (const auto& entry : cap_candidates)
        if (const LightTriangle& lt = light_triangle(entry.id); cap_crosses(lt, p, stats)) {
          ++out.cap;
          out.cap_objects.insert(lt.object);
        }
    }

    // The brute-force oracle tests every triangle, also those the grid
    // leaves out (eye_setup.hpp).
    std::vector<CentralGrid::Entry> every;
    if (!accelerated)
      for (std::uint32_t id = 0; id < eye_side->first_face.back(); ++id)
        every.push_back({id, -std::numeric_limits<double>::infinity()});
    const CentralGrid::EntryRange eye_candidates =
        accelerated ? eye_grid->candidates(p.estimate(), p.error())
                    : CentralGrid::EntryRange{every.data(), every.data() + every.size()};
    const std::optional<Hit> hit = first_hit(eye_candidates, p, accelerated, stats);
    if (!hit) return out;
    const EyeTriangle& q = eye(hit->eye_index);
    out.object = static_cast<std::int32_t>(q.object);
    out.face = q.face;
    CentralGrid::EntryRange shadow_candidates = light_grid->all();
    std::optional<BoundedVec3> qpos;
    if (std::isfinite(hit->t.e)) qpos = hit->t * p.approx();
    if (accelerated && qpos) shadow_candidates = light_candidates(*qpos);
    // The brute-force trace keeps the forms in P alone: the oracle the fast
    // path is tested against.
    const BoundedVec3* q_point = accelerated && qpos ? &*qpos : nullptr;
    if (content == PixelContent::ShadowStatus) {
      if (last_shadower && *last_shadower != kNoShadower &&
          shadow_crosses(light_triangle(*last_shadower), *hit, p, stats, q_point)) {
        out.stencil = 1;
        return out;
      }
      for (const auto& entry : shadow_candidates)
        if (shadow_crosses(light_triangle(entry.id), *hit, p, stats, q_point)) {
          if (last_shadower) *last_shadower = entry.id;
          out.stencil = 1;
          return out;
        }
      out.stencil = 0;
      return out;
    }
    std::uint32_t count = 0;
    for (const auto& entry : shadow_candidates)
      if (shadow_crosses(light_triangle(entry.id), *hit, p, stats, q_point)) ++count;
    out.stencil = count;
    return out;
  }
};

}  // namespace nearcap
