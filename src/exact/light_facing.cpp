// Light facing: a three-stage filter, as CGAL's filtered kernels do it.
//   1. static filter: the orientation determinant in plain double, against one
//      bound per (object, light) derived from the largest coordinate and the
//      largest input error (no per-call bound arithmetic);
//   2. semi-static: the same determinant in BoundedDouble;
//   3. exact: rationals.
#include "nearcap/exact/light_facing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

namespace nearcap {
namespace {

// Bound on |orient(a,b,c,l) - fl(det of rounded differences)| when every
// coordinate estimate is within `e` of its exact value and within `m` in
// magnitude.  Differences are within 2m of zero and carry error
// delta = 2e + 2u(2m) (inputs plus the subtraction's rounding).  The
// determinant is a sum of six triple products: perturbing each factor by delta
// changes it by at most (K^3 - (2m)^3) with K = 2m + delta, and evaluating it
// in double (products, then two levels of sums) costs at most gamma_5 * 6 K^3.
double orientation_static_bound(double m, double e) {
  constexpr double u = 0x1p-53;
  constexpr double gamma5 = 5 * u / (1 - 5 * u);
  const double two_m = 2 * m;
  const double delta = 2 * e + 2 * u * two_m;
  const double k = two_m * (1 + 2 * u) + delta;
  const double bound = 6 * (k * k * k - two_m * two_m * two_m) + 6 * gamma5 * k * k * k;
  return bound * (1 + 0x1p-40);  // covers the rounding of this computation
}

struct StaticOrientationFilter {
  double bound;
  Vec3d l;  // the light's estimate
  std::optional<Sign> operator()(const Vec3d& a, const Vec3d& b, const Vec3d& c) const {
    const double ax = b.x - a.x, ay = b.y - a.y, az = b.z - a.z;
    const double bx = c.x - a.x, by = c.y - a.y, bz = c.z - a.z;
    const double cx = l.x - a.x, cy = l.y - a.y, cz = l.z - a.z;
    const double det = ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
    if (det > bound) return Sign::Positive;
    if (det < -bound) return Sign::Negative;
    return std::nullopt;
  }
};

StaticOrientationFilter static_filter(const CameraSpaceScene& scene, std::size_t o, std::size_t light) {
  const BoundedVec3& l = scene.light(light);
  double m = scene.max_abs(o), e = scene.max_error(o);
  for (int i = 0; i < 3; ++i) {
    m = std::max(m, std::fabs(l[i].v) + l[i].e);
    e = std::max(e, l[i].e);
  }
  return {orientation_static_bound(m, e), Vec3d{l.x.v, l.y.v, l.z.v}};
}

Sign light_side_filtered(const CameraSpaceScene& scene, std::size_t o, FaceIndex f, std::size_t light,
                         const StaticOrientationFilter& fast, FilterStats* stats) {
  const auto& t = scene.mesh(o).triangles[f];
  if (const auto s =
          fast(scene.vertex_estimate(o, t[0]), scene.vertex_estimate(o, t[1]), scene.vertex_estimate(o, t[2]))) {
    if (stats) stats->record(Predicate::LightFacing, false);
    return *s * scene.handedness(o);
  }
  const BoundedVec3 a = scene.vertex(o, t[0]), b = scene.vertex(o, t[1]), c = scene.vertex(o, t[2]);
  const BoundedVec3& l = scene.light(light);
  const Sign s = filtered_sign(
      Predicate::LightFacing, stats, [&] { return orientation_determinant(a, b, c, l); },
      [&] {
        return orientation_determinant(scene.exact_vertex(o, t[0]), scene.exact_vertex(o, t[1]),
                                       scene.exact_vertex(o, t[2]), scene.exact_light(light));
      });
  // A mirroring map (negative determinant) reverses the winding: undo it.
  return s * scene.handedness(o);
}

Facing facing_of(Sign outer_side) {
  return outer_side == Sign::Positive ? Facing::Front : (outer_side == Sign::Negative ? Facing::Back : Facing::EdgeOn);
}

// The light in object space, exactly: solve L x = l_world - t by Cramer's
// rule over rationals (once per object and light).
RationalVec3 light_in_object_space(const CameraSpaceScene& scene, std::size_t o, std::size_t light) {
  const auto& m = scene.object(o).object_to_world.rows;
  const Vec3d& lw = scene.scene().lights[light].position;
  Rational a[3][3], r[3];
  const double lwv[3] = {lw.x, lw.y, lw.z};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) a[i][j] = m[i][j];
    r[i] = Rational(lwv[i]) - Rational(m[i][3]);
  }
  auto det3 = [](const Rational(&c)[3][3]) {
    return Rational(c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1]) -
                    c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0]) +
                    c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]));
  };
  const Rational det = det3(a);  // non-zero: scenes reject singular object maps
  RationalVec3 x;
  for (int k = 0; k < 3; ++k) {
    Rational c[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) c[i][j] = j == k ? r[i] : a[i][j];
    x[k] = det3(c) / det;
  }
  return x;
}

// Object-space facing with the mesh's precomputed planes: n . l - d per face,
// read sequentially, against one static bound.  Returns false when the mesh
// has no planes (meshes not loaded through a scene).
bool light_facing_object_space(const CameraSpaceScene& scene, std::size_t o, std::size_t light,
                               const StaticOrientationFilter& fast, FilterStats* stats, std::vector<Facing>& facing) {
  const TriangleMesh& mesh = scene.mesh(o);
  const FacePlanes& fp = mesh.face_planes;
  const std::size_t n = mesh.triangles.size();
  if (fp.plane.size() != n) return false;
  const RationalVec3 exact = light_in_object_space(scene, o, light);
  double l[3], l_error = 0, l_max = 0;
  for (int i = 0; i < 3; ++i) {
    const BoundedDouble b = bounded_estimate(exact[i]);
    l[i] = b.v;
    const double e = b.e;
    l_error = std::fmax(l_error, e);
    l_max = std::fmax(l_max, std::fabs(l[i]) + e);
  }
  // |exact - computed| for n . l - d: input errors, then six roundings.
  constexpr double gamma6 = 6 * 0x1p-53 / (1 - 6 * 0x1p-53);
  const double bound = (3 * (fp.n_max * l_error + l_max * fp.n_error + fp.n_error * l_error) + fp.d_error +
                        gamma6 * (3 * fp.n_max * l_max + fp.d_max)) *
                       (1 + 0x1p-40);
  facing.resize(n);
  Facing* const out = facing.data();
  const std::array<double, 4>* const plane = fp.plane.data();
  std::uint64_t decided_fast = 0;
  for (FaceIndex f = 0; f < n; ++f) {
    const std::array<double, 4>& p = plane[f];
    const double det = p[0] * l[0] + p[1] * l[1] + p[2] * l[2] - p[3];
    const bool positive = det > bound, negative = det < -bound;
    if (__builtin_expect(!(positive || negative), 0)) {
      // The camera-space cascade decides the same sign (orientation in object
      // space = orientation in camera space x handedness, which light_side
      // already multiplies in).
      out[f] = facing_of(light_side_filtered(scene, o, f, light, fast, stats));
      continue;
    }
    ++decided_fast;
    static_assert(static_cast<int>(Facing::Front) == 0 && static_cast<int>(Facing::Back) == 1);
    out[f] = static_cast<Facing>(!positive);  // outer side: Front
  }
  if (stats) stats->filtered[static_cast<int>(Predicate::LightFacing)] += decided_fast;
  return true;
}

}  // namespace

Sign light_side(const CameraSpaceScene& scene, std::size_t o, FaceIndex f, std::size_t light, FilterStats* stats) {
  return light_side_filtered(scene, o, f, light, static_filter(scene, o, light), stats);
}

std::vector<Facing> light_facing(const CameraSpaceScene& scene, std::size_t o, std::size_t light, FilterStats* stats) {
  const auto& triangles = scene.mesh(o).triangles;
  const std::size_t n = triangles.size();
  const StaticOrientationFilter fast = static_filter(scene, o, light);
  std::vector<Facing> facing;
  if (light_facing_object_space(scene, o, light, fast, stats, facing)) return facing;
  // A mesh without precomputed planes (not loaded through a scene): the
  // camera-space cascade, triangle by triangle.
  facing.resize(n);
  for (FaceIndex f = 0; f < n; ++f) facing[f] = facing_of(light_side_filtered(scene, o, f, light, fast, stats));
  return facing;
}

}  // namespace nearcap
