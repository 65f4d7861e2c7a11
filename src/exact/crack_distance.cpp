// The crack distance: the exact shadow status proven constant over squares
// around a pixel centre (see crack_distance.hpp for the argument).
#include "nearcap/exact/crack_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "pixel_tracer_impl.hpp"
#include "square_sign_filter.hpp"

namespace nearcap {
namespace {

// A square on the near plane: its four corners, and its centre and
// half-sides (square_sign_filter.hpp).
struct Corners {
  std::array<PixelPoint, 4> at;
  BoundedVec3 centre;            // encloses the exact centre
  BoundedDouble half_x, half_y;  // enclose the exact half-sides (camera x and y)
  std::size_t size() const { return at.size(); }
  const PixelPoint& operator[](std::size_t k) const { return at[k]; }
};

// The strict sign an affine form has at all four corners (then over the whole
// square), or Zero when the corners disagree or one of them is zero: from
// the centre where square_sign_filter decides it, else corner by corner,
// filtered, then exact.
template <class ApproxForm, class ExactForm>
Sign uniform_sign(Predicate pred, FilterStats* stats, const Corners& corners, ApproxForm&& approx_form,
                  ExactForm&& exact_form) {
  const BoundedForm fa = approx_form();
  if (const std::optional<Sign> s = square_sign_filter(fa, corners.centre, corners.half_x, corners.half_y)) {
    if (stats) stats->record(pred, false);
    return *s;
  }
  std::optional<AffineForm<Rational>> fe;
  Sign common = Sign::Zero;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    Sign s;
    if (const auto v = fa.at(corners[k].approx()).sign(); v && *v != Sign::Zero) {
      if (stats) stats->record(pred, false);
      s = *v;
    } else {
      if (stats) stats->record(pred, true);
      if (!fe) fe = exact_form();
      s = sign_of(Rational(fe->at(corners[k].exact())));
    }
    if (s == Sign::Zero || (k > 0 && s != common)) return Sign::Zero;
    common = s;
  }
  return common;
}

class SquareProof {
 public:
  SquareProof(const PixelReferenceTracer::Impl& t, const Corners& corners, FilterStats* stats)
      : t_(t), c_(corners), stats_(stats) {}

  // The uniform signs of triangle e's view-ray forms.
  Sign edge(const EyeTriangle& e, int k) const {
    return uniform_sign(
        Predicate::RayHit, stats_, c_,
        [&] {
          return BoundedForm{e.edge[k], BoundedDouble(0.0)};
        },
        [&] {
          const auto v = t_.exact_triangle(e.object, e.face);
          return ExactForm{cross(v[k], v[(k + 1) % 3]), Rational(0)};
        });
  }
  Sign beyond_near(const EyeTriangle& e) const {
    if (e.in_near_plane) return e.sigma;  // kept, as GL's closed clip volume keeps it
    return uniform_sign(
        Predicate::RayHit, stats_, c_,
        [&] {
          return BoundedForm{BoundedDouble(-1.0) * e.plane.n, e.plane.d};
        },
        [&] {
          const auto pl = t_.exact_plane(e.object, e.face);
          return ExactForm{Rational(-1) * pl.n, pl.d};
        });
  }
  Sign before_far(const EyeTriangle& e) const {
    const Frustum& fr = t_.cs.frustum();
    return uniform_sign(
        Predicate::RayHit, stats_, c_,
        [&] {
          return BoundedForm{BoundedDouble(fr.far) * e.plane.n, BoundedDouble(-fr.near) * e.plane.d};
        },
        [&] {
          const auto pl = t_.exact_plane(e.object, e.face);
          return ExactForm{Rational(fr.far) * pl.n, Rational(-fr.near) * pl.d};
        });
  }
  // sign((d_a n_b - d_b n_a) . P) over the square, for the planes of two
  // triangles' faces (eye or light triangles): which plane a ray through P
  // meets first, up to the signs of d_a and d_b.
  template <class A, class B>
  Sign plane_pair(Predicate predicate, const A& a, const B& b) const {
    return uniform_sign(
        predicate, stats_, c_,
        [&] {
          return BoundedForm{a.plane.d * b.plane.n - b.plane.d * a.plane.n, BoundedDouble(0.0)};
        },
        [&] {
          const auto pa = t_.exact_plane(a.object, a.face), pb = t_.exact_plane(b.object, b.face);
          return ExactForm{pa.d * pb.n - pb.d * pa.n, Rational(0)};
        });
  }
  // sign((d1 n2 - d2 n1) . P): times sign(d1 d2), negative when e1 is hit first.
  Sign order(const EyeTriangle& e1, const EyeTriangle& e2) const { return plane_pair(Predicate::RayHit, e1, e2); }

  // 1. T is hit over the whole square.
  bool hit_everywhere(const EyeTriangle& e) const {
    for (int k = 0; k < 3; ++k)
      if (edge(e, k) != e.sigma) return false;
    return beyond_near(e) == e.sigma && before_far(e) == e.sigma;
  }
  // 2. Another triangle is never seen in front of T over the square.
  bool hidden_everywhere(const EyeTriangle& other, const EyeTriangle& seen) const {
    if (other.sigma == Sign::Zero || other.before_near) return true;  // edge-on, or all before the near plane
    const Sign miss = -other.sigma;
    if (order(seen, other) * seen.sigma * other.sigma == Sign::Negative) return true;
    if (beyond_near(other) == miss) return true;
    for (int k = 0; k < 3; ++k)
      if (edge(other, k) == miss) return true;
    return before_far(other) == miss;
  }

  enum class Crossing { Always, Never, Unknown };
  // 3. Does (l, q(P)) cross light triangle L for every P, for none, or not proven?
  Crossing crossing(const LightTriangle& lt, const EyeTriangle& q, std::uint32_t q_index) const {
    if (lt.eye_index == q_index) return q.sigma == lt.light_side ? Crossing::Always : Crossing::Never;
    std::array<Sign, 3> s{};
    for (int k = 0; k < 3; ++k) {
      s[k] = uniform_sign(
          Predicate::ShadowCrossing, stats_, c_,
          [&] {
            return BoundedForm{q.plane.d * lt.g[k] + lt.g0[k] * q.plane.n, BoundedDouble(0.0)};
          },
          [&] {
            const auto pq = t_.exact_plane(q.object, q.face);
            const Vec3<Rational> g = t_.exact_g(lt, k);
            const Rational g0 = -dot(g, t_.cs.exact_light(t_.light));
            return ExactForm{pq.d * g + g0 * pq.n, Rational(0)};
          });
      for (int m = 0; m < k; ++m)
        if (s[k] != Sign::Zero && s[m] == -s[k]) return Crossing::Never;  // never all one sign
    }
    if (t_.coplanar(lt, q_index)) return Crossing::Never;  // q lies in L's plane
    const Sign side = plane_pair(Predicate::ShadowCrossing, q, lt);
    if (side != Sign::Zero && side * q.sigma != -lt.light_side) return Crossing::Never;
    if (side != Sign::Zero && s[0] != Sign::Zero && s[0] == s[1] && s[1] == s[2]) return Crossing::Always;
    return Crossing::Unknown;
  }

 private:
  const PixelReferenceTracer::Impl& t_;
  const Corners& c_;
  FilterStats* stats_;
};

// The box, in estimated coordinates, that holds every point of a set of
// certified points: centre and half-extent per coordinate (worst axis).
struct Region {
  Vec3d centre;
  double half_extent;
};
Region region_of(const std::array<BoundedVec3, 4>& points) {
  Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3d hi = -1.0 * lo;
  for (const BoundedVec3& p : points)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a].v - p[a].e);
      hi[a] = std::max(hi[a], p[a].v + p[a].e);
    }
  Region r{{0, 0, 0}, 0};
  for (int a = 0; a < 3; ++a) {
    r.centre[a] = 0.5 * lo[a] + 0.5 * hi[a];
    r.half_extent = std::max(r.half_extent, (hi[a] - lo[a]) * (0.5 + 0x1p-40) + 1e-300);
  }
  return r;
}

// The candidate lists of a proof: a buffer per thread, kept with its capacity
// from one proof to the next (the squares of a frame and of later frames), so
// that a proof allocates nothing.  A proof takes the buffer out while it runs
// and puts it back when done: a proof that starts on the same thread meanwhile
// (a task run while this one waits) finds none and uses a buffer of its own.
// Every list is cleared before it is filled, so what a buffer held before
// never reaches a proof.
class CandidateBuffer {
 public:
  CandidateBuffer() : ids_(std::move(kept())) { ids_.clear(); }
  ~CandidateBuffer() {
    if (ids_.capacity() > kept().capacity()) kept() = std::move(ids_);
  }
  CandidateBuffer(const CandidateBuffer&) = delete;
  CandidateBuffer& operator=(const CandidateBuffer&) = delete;
  std::vector<std::uint32_t>& ids() { return ids_; }

 private:
  static std::vector<std::uint32_t>& kept() {
    thread_local std::vector<std::uint32_t> buffer;
    return buffer;
  }
  std::vector<std::uint32_t> ids_;
};

}  // namespace

std::optional<bool> PixelReferenceTracer::proven_status_over_square(const WindowPoint& c, std::int64_t half_width,
                                                                    FilterStats* stats, std::uint32_t* last_shadower,
                                                                    CentreHit* centre_hit,
                                                                    std::optional<bool> status_inside) const {
  const Impl& t = *impl_;
  const Scene& scene = t.cs.scene();
  const int width = scene.camera.width, height = scene.camera.height;
  const Frustum& fr = t.cs.frustum();
  const PixelPoint centre(fr, width, height, c);
  const BoundedVec3 half = window_offset_estimate(fr, width, height, {half_width, half_width, c.shift});
  const Corners corners{{PixelPoint(fr, width, height, {c.x - half_width, c.y - half_width, c.shift}),
                         PixelPoint(fr, width, height, {c.x + half_width, c.y - half_width, c.shift}),
                         PixelPoint(fr, width, height, {c.x + half_width, c.y + half_width, c.shift}),
                         PixelPoint(fr, width, height, {c.x - half_width, c.y + half_width, c.shift})},
                        centre.approx(),
                        half.x,
                        half.y};
  const SquareProof proof(t, corners, stats);

  // The triangle seen at the centre, seen over the whole square.
  std::optional<Hit> hit;
  if (centre_hit && centre_hit->known) {
    if (centre_hit->found) {
      hit = Hit{centre_hit->eye_index, centre_hit->sigma, BoundedDouble(centre_hit->t_value, centre_hit->t_error)};
    }
  } else {
    hit = t.first_hit(t.eye_grid->candidates(centre.estimate(), centre.error()), centre, true, stats);
    if (centre_hit) {
      centre_hit->known = true;
      centre_hit->found = hit.has_value();
      if (hit) {
        centre_hit->eye_index = hit->eye_index;
        centre_hit->sigma = hit->sigma;
        centre_hit->t_value = hit->t.v;
        centre_hit->t_error = hit->t.e;
      }
    }
  }
  if (!hit) return std::nullopt;
  const EyeTriangle& seen = t.eye(hit->eye_index);
  if (!proof.hit_everywhere(seen)) return std::nullopt;
  CandidateBuffer buffer;
  std::vector<std::uint32_t>& ids = buffer.ids();
  const Region directions =
      region_of({corners[0].approx(), corners[1].approx(), corners[2].approx(), corners[3].approx()});
  if (!t.eye_grid->candidates_in(directions.centre, directions.half_extent, ids)) {
    ids.clear();
    for (const auto& e : t.eye_grid->all()) ids.push_back(e.id);
  }
  for (std::uint32_t id : ids)
    if (id != hit->eye_index && !proof.hidden_everywhere(t.eye(id), seen)) return std::nullopt;

  // q(P) over the square: the convex hull of the corners' hits on T's plane.
  std::array<BoundedVec3, 4> q;
  bool bounded = true;
  for (std::size_t k = 0; k < 4; ++k) {
    const BoundedDouble tk = t.hit_parameter(seen, corners[k]);
    bounded = bounded && std::isfinite(tk.e) && std::isfinite(tk.v);
    q[k] = tk * corners[k].approx();
  }
  const BoundedVec3& l = t.cs.light(t.light);
  bool listed = false;
  if (bounded) {
    const Region points = region_of(q);
    const Vec3d w{points.centre.x - l.x.v, points.centre.y - l.y.v, points.centre.z - l.z.v};
    const double err = points.half_extent + std::max({l.x.e, l.y.e, l.z.e}) * (1.0 + 0x1p-40);
    listed = t.region_light_grid().candidates_in(w, err, ids);
  }
  if (!listed) {
    ids.clear();
    for (const auto& e : t.light_grid->all()) ids.push_back(e.id);
  }
  // Never crossed anywhere in the square: the square is lit.
  const auto lit_everywhere = [&] {
    for (std::uint32_t id : ids)
      if (proof.crossing(t.light_triangle(id), seen, hit->eye_index) != SquareProof::Crossing::Never) return false;
    return true;
  };
  // A point of the square known lit: only a lit proof can succeed, and it
  // needs every triangle never crossed (one crossed at the centre is not).
  if (status_inside == false) return lit_everywhere() ? std::optional<bool>(false) : std::nullopt;
  // The status at the centre decides which proof can succeed.  In shadow:
  // only a triangle crossed at the centre can be crossed everywhere, so those
  // are tried as they are found, and the first crossed everywhere ends the
  // proof.  Lit: every triangle must be proven never crossed, and the first
  // that is not ends the proof.
  // The centre's hit point, when certified, lets the shadow tests at the
  // centre reject most candidates with one bounded dot product per edge
  // instead of a form in P (the pixel trace's fast path; exact either way).
  std::optional<BoundedVec3> q_centre_value;
  if (std::isfinite(hit->t.e) && std::isfinite(hit->t.v)) q_centre_value = hit->t * centre.approx();
  const BoundedVec3* q_centre = q_centre_value ? &*q_centre_value : nullptr;
  // The hint first.  The loop below returns true exactly when some listed
  // triangle crossed at the centre is crossed over the whole square; a listed
  // hint that is both gives that answer without the search.
  if (last_shadower && *last_shadower != kNoShadower &&
      std::find(ids.begin(), ids.end(), *last_shadower) != ids.end()) {
    const LightTriangle& lt = t.light_triangle(*last_shadower);
    if (t.shadow_crosses(lt, *hit, centre, stats, q_centre) &&
        proof.crossing(lt, seen, hit->eye_index) == SquareProof::Crossing::Always)
      return true;
  }
  bool shadowed_at_centre = false;
  for (std::uint32_t id : ids)
    if (t.shadow_crosses(t.light_triangle(id), *hit, centre, stats, q_centre)) {
      if (proof.crossing(t.light_triangle(id), seen, hit->eye_index) == SquareProof::Crossing::Always) {
        if (last_shadower) *last_shadower = id;
        return true;
      }
      shadowed_at_centre = true;
    }
  // A point of the square known in shadow: a lit proof cannot succeed.
  if (shadowed_at_centre || status_inside == true) return std::nullopt;
  return lit_everywhere() ? std::optional<bool>(false) : std::nullopt;
}

}  // namespace nearcap
