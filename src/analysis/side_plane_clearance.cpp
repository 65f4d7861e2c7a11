// The eye's clearance from the side planes of a shadow volume
// (side_plane_clearance.hpp).
//
// Why the clip coordinates' rounding decides the frame near a side plane.
// In clip space's (x, y, w) — a linear image of camera space in which the
// eye is the origin — a side quad's triangle covers a pixel by the signs of
// three edge functions det(p_i, p_j, r), r the pixel's ray, and it faces
// the eye as the sign of det(p0, p1, p2), which is the camera-space triple
// product T = det(a, d, l) times the projection's determinant (subtracting
// multiples of l from the rows of det(a - l, d - l, l) leaves det(a, d, l)).
// Each float32 clip coordinate is a sum of products whose terms are at
// most M in magnitude (M: side_plane_magnitude), rounded a few times (the
// float modelview product, the projection product, the four-term sum of
// the vertex program: about 8 roundings), so each quad vertex moves by up
// to about 8 * 2^-24 * M, the extruded ones in direction by as much
// relative to |a - l|.  The float quad's plane then passes the eye on
// either side of the exact one where the eye is within a few such units of
// it, and the quad's image, bounded by that plane's image, moves over
// pixels.  The bound takes kSidePlaneBoundUnits units of 2^-24 M; the
// measurement (tests/atomiczp_side_plane_test.cpp) places the wrong frames
// of the sampled configurations within it.
//
// The decision, exact: with n = (a - l) x (d - l) the side plane's normal,
// the eye's distance to the plane is |n . l| / |n| = |T| / |n| (n . l =
// det(a - l, d - l, l) = T), so "distance < b" is b^2 |n|^2 - T^2 > 0,
// evaluated on the certified estimates and, where the filter cannot tell,
// in rationals.  b = bound_units * 2^-24 * M is a double, exact as it is.
#include "nearcap/analysis/side_plane_clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "nearcap/gl/engine_classification.hpp"

namespace nearcap::analysis {
namespace {

// |A| |B| for two affine maps, as a 3x4 of absolute values (the translation
// column: |A's linear part| |B's translation| + |A's translation|).
Affine3d absolute_product(const Affine3d& a, const Affine3d& b) {
  Affine3d out;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double s = j == 3 ? std::fabs(a.rows[i][3]) : 0.0;
      for (int k = 0; k < 3; ++k) s += std::fabs(a.rows[i][k]) * std::fabs(b.rows[k][j]);
      out.rows[i][j] = s;
    }
  }
  return out;
}

double largest_row_sum(const Affine3d& abs_map, const Vec3d& p) {
  double m = 0;
  for (int i = 0; i < 3; ++i)
    m = std::max(m, abs_map.rows[i][0] * std::fabs(p.x) + abs_map.rows[i][1] * std::fabs(p.y) +
                        abs_map.rows[i][2] * std::fabs(p.z) + abs_map.rows[i][3]);
  return m;
}

double light_magnitude(const Scene& scene, std::size_t light) {
  Affine3d abs_view;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) abs_view.rows[i][j] = std::fabs(scene.camera.view.rows[i][j]);
  return largest_row_sum(abs_view, scene.lights[light].position);
}

}  // namespace

double side_plane_magnitude(const Scene& scene, std::size_t o, VertexIndex a, VertexIndex d, std::size_t light) {
  const Affine3d abs_mv = absolute_product(scene.camera.view, scene.objects[o].object_to_world);
  const TriangleMesh& mesh = *scene.objects[o].mesh;
  return std::max({largest_row_sum(abs_mv, mesh.positions[a]), largest_row_sum(abs_mv, mesh.positions[d]),
                   light_magnitude(scene, light)});
}

double side_plane_lever(const CameraSpaceScene& cs, std::size_t o, VertexIndex a, VertexIndex d, std::size_t light) {
  const Vec3d& pa = cs.vertex_estimate(o, a);
  const Vec3d& pd = cs.vertex_estimate(o, d);
  const BoundedVec3& lb = cs.light(light);
  const Vec3d l{lb.x.v, lb.y.v, lb.z.v};
  auto length = [](const Vec3d& v) { return std::sqrt(dot(v, v)); };
  const double reach = std::max(length(pa), length(pd));
  const double edge = length(pd - pa), to_light = std::min(length(pa - l), length(pd - l));
  if (!(edge > 0) || !(to_light > 0)) return std::numeric_limits<double>::infinity();
  return 1 + reach / edge + reach / to_light;
}

double side_plane_unit(const CameraSpaceScene& cs, std::size_t o, VertexIndex a, VertexIndex d, std::size_t light) {
  return std::ldexp(side_plane_magnitude(cs.scene(), o, a, d, light), -24) * side_plane_lever(cs, o, a, d, light);
}

SidePlaneClearance side_plane_clearance(const CameraSpaceScene& cs, std::size_t o, std::size_t light,
                                        double bound_units) {
  const Scene& scene = cs.scene();
  const TriangleMesh& mesh = cs.mesh(o);
  const EngineSilhouette silhouette = engine_silhouette(scene, o, light);
  const Affine3d abs_mv = absolute_product(scene.camera.view, scene.objects[o].object_to_world);
  const double light_m = light_magnitude(scene, light);
  const BoundedVec3& l = cs.light(light);
  SidePlaneClearance out;
  out.edges = silhouette.edges.size();
  for (const SilhouetteEdge& e : silhouette.edges) {
    const double m =
        std::max({largest_row_sum(abs_mv, mesh.positions[e.a]), largest_row_sum(abs_mv, mesh.positions[e.d]), light_m});
    const double unit = std::ldexp(m, -24) * side_plane_lever(cs, o, e.a, e.d, light);
    if (!std::isfinite(unit)) continue;  // a degenerate quad: no area
    const double b = bound_units * unit;
    // The estimate, for the report: in double, or in rationals where the
    // double triple product cannot tell the eye from the plane.
    const BoundedVec3 ab = cs.vertex(o, e.a), db = cs.vertex(o, e.d);
    const BoundedDouble t_bounded = dot(ab, cross(db, l));
    const BoundedVec3 n_bounded = cross(ab - l, db - l);
    double t_est = t_bounded.v;
    if (!t_bounded.sign()) {
      const RationalVec3 a = cs.exact_vertex(o, e.a), d = cs.exact_vertex(o, e.d);
      t_est = to_double(Rational(dot(a, cross(d, cs.exact_light(light)))));
    }
    const double n_est = std::sqrt(
        dot(Vec3d{n_bounded.x.v, n_bounded.y.v, n_bounded.z.v}, Vec3d{n_bounded.x.v, n_bounded.y.v, n_bounded.z.v}));
    if (n_est > 0) out.nearest_units = std::min(out.nearest_units, std::fabs(t_est) / n_est / unit);
    if (out.within_bound) continue;  // decided; the estimate above still reports the nearest
    bool fell_back = false;
    // Not counted in FilterStats (no caller passes one); exact_fallbacks counts.
    const Sign within = filtered_sign(
        Predicate::ShadowCrossing, nullptr,
        [&] {
          const BoundedDouble bb(b);
          return bb * bb * dot(n_bounded, n_bounded) - t_bounded * t_bounded;
        },
        [&] {
          fell_back = true;
          const RationalVec3 a = cs.exact_vertex(o, e.a), d = cs.exact_vertex(o, e.d);
          const RationalVec3& lr = cs.exact_light(light);
          const Rational t = dot(a, cross(d, lr));
          const RationalVec3 n = cross(a - lr, d - lr);
          const Rational bb(b);
          return Rational(bb * bb * dot(n, n) - t * t);
        });
    out.exact_fallbacks += fell_back ? 1 : 0;
    if (within == Sign::Positive) out.within_bound = true;
  }
  return out;
}

}  // namespace nearcap::analysis
