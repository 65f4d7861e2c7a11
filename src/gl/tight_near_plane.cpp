// The tight near plane (see tight_near_plane.hpp).
#include "nearcap/gl/tight_near_plane.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "nearcap/check.hpp"

namespace nearcap::gl {
namespace {

// A plane through the eye, a . p >= 0 inside.
using Plane = std::array<double, 3>;

// A triangle clipped by planes.  One clip keeps the k of n vertices inside
// and adds a point per sign change along the loop, of which there are at
// most 2 min(k, n - k) even where rounding makes the signs alternate: at
// most 1.5 n + 0.5 vertices.  A triangle clipped by the five
// planes below: 3, 5, 8, 12, 18, 27.
struct ClippedPolygon {
  static constexpr std::size_t kCapacity = 27;
  std::array<Vec3d, kCapacity> v;
  std::size_t n = 0;
};

void clip(const ClippedPolygon& in, const Plane& plane, ClippedPolygon& out) {
  out.n = 0;
  auto push = [&out](const Vec3d& p) {
    NEARCAP_CHECK(out.n < ClippedPolygon::kCapacity);
    out.v[out.n++] = p;
  };
  for (std::size_t k = 0; k < in.n; ++k) {
    const Vec3d &a = in.v[k], &b = in.v[(k + 1) % in.n];
    const double da = plane[0] * a.x + plane[1] * a.y + plane[2] * a.z,
                 db = plane[0] * b.x + plane[1] * b.y + plane[2] * b.z;
    if (da >= 0) push(a);
    if ((da >= 0) != (db >= 0)) {
      const double t = da / (da - db);
      push(a + t * (b - a));
    }
  }
}

}  // namespace

Frustum tight_frustum(const Scene& scene) {
  const Frustum& f = scene.camera.frustum;
  // The side planes at depth 1 (x = left / near ... at z = -1), each moved
  // out by half a percent of the window's width or height (an off-axis
  // window too; 1 % of a centred window's half-width).
  const double l0 = f.left / f.near, r0 = f.right / f.near, b0 = f.bottom / f.near, t0 = f.top / f.near;
  const double l = l0 - 0.005 * (r0 - l0), r = r0 + 0.005 * (r0 - l0), b = b0 - 0.005 * (t0 - b0),
               t = t0 + 0.005 * (t0 - b0);
  const std::array<Plane, 5> planes{{
      {1, 0, l},    // x >= l (-z):  x + l z >= 0
      {-1, 0, -r},  // x <= r (-z)
      {0, 1, b},
      {0, -1, -t},
      {0, 0, -1},  // in front of the eye: -z >= 0
  }};
  double nearest = std::numeric_limits<double>::infinity();
  std::vector<Vec3d> camera;
  ClippedPolygon first, second;
  for (const SceneObject& o : scene.objects) {
    camera.resize(o.mesh->positions.size());
    for (std::size_t v = 0; v < camera.size(); ++v)
      camera[v] = scene.camera.view.apply(o.object_to_world.apply(o.mesh->positions[v]));
    for (const auto& tri : o.mesh->triangles) {
      ClippedPolygon *poly = &first, *next = &second;
      poly->v[0] = camera[tri[0]];
      poly->v[1] = camera[tri[1]];
      poly->v[2] = camera[tri[2]];
      poly->n = 3;
      for (const Plane& p : planes) {
        clip(*poly, p, *next);
        std::swap(poly, next);
        if (poly->n == 0) break;
      }
      for (std::size_t k = 0; k < poly->n; ++k) nearest = std::min(nearest, -poly->v[k].z);
    }
  }
  Frustum out = f;
  if (!std::isfinite(nearest)) return out;                   // nothing in view
  const double near = std::min(0.5 * nearest, 0.5 * f.far);  // never beyond the far plane
  if (!std::isfinite(near) || !(near > f.near)) return out;
  const double s = near / f.near;
  out.left *= s;
  out.right *= s;
  out.bottom *= s;
  out.top *= s;
  out.near = near;
  return out;
}

}  // namespace nearcap::gl
