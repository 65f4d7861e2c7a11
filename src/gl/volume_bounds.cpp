// The scissor rectangle and depth bounds of one shadow volume (see
// volume_bounds.hpp).
#include "nearcap/gl/volume_bounds.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "glm_affine.hpp"

namespace nearcap::gl {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::array<Vec3d, 8> world_corners(const SceneObject& obj) {
  const FacePlanes& fp = obj.mesh->face_planes;
  Vec3d lo = fp.box_lo, hi = fp.box_hi;
  if (fp.plane.empty()) {  // no face planes computed: the positions' box
    lo = {kInf, kInf, kInf};
    hi = -1.0 * lo;
    for (const Vec3d& p : obj.mesh->positions)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], p[a]);
        hi[a] = std::max(hi[a], p[a]);
      }
  }
  std::array<Vec3d, 8> c;
  for (int k = 0; k < 8; ++k)
    c[k] = obj.object_to_world.apply({(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z});
  return c;
}

// The distance from p to the axis-aligned box of `points`.
double distance_to_box(const Vec3d& p, const std::array<Vec3d, 8>& points) {
  Vec3d lo{kInf, kInf, kInf}, hi = -1.0 * lo;
  for (const Vec3d& q : points)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], q[a]);
      hi[a] = std::max(hi[a], q[a]);
    }
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::max({lo[a] - p[a], 0.0, p[a] - hi[a]});
    d2 += d * d;
  }
  return std::sqrt(d2);
}

}  // namespace

std::optional<VolumeBounds> shadow_volume_bounds(const Scene& scene, std::size_t object, const Vec3d& light,
                                                 const Mat4f& projection, DepthMapping mapping) {
  const SceneObject& obj = scene.objects.at(object);
  if (!obj.mesh || obj.mesh->positions.empty()) return std::nullopt;
  const std::array<Vec3d, 8> q = world_corners(obj);
  const double to_occluder = distance_to_box(light, q);

  // B: every object's box and the near rectangle, in world space.
  std::vector<Vec3d> b_points;
  for (const SceneObject& o : scene.objects)
    if (o.mesh && !o.mesh->positions.empty())
      for (const Vec3d& c : world_corners(o)) b_points.push_back(c);
  // The near rectangle's corners, camera space to world space.
  const Affine3d& view = scene.camera.view;
  const Frustum& f = scene.camera.frustum;
  const glm::dmat4 to_world = glm::inverse(to_glm(view));
  for (const double x : {f.left, f.right})
    for (const double y : {f.bottom, f.top}) {
      const glm::dvec4 w = to_world * glm::dvec4(x, y, -f.near, 1.0);
      b_points.push_back({w.x, w.y, w.z});
    }
  double magnitude = std::max({std::fabs(light.x), std::fabs(light.y), std::fabs(light.z)});
  Vec3d b_lo{kInf, kInf, kInf}, b_hi = -1.0 * b_lo;
  for (const Vec3d& p : b_points)
    for (int a = 0; a < 3; ++a) {
      b_lo[a] = std::min(b_lo[a], p[a]);
      b_hi[a] = std::max(b_hi[a], p[a]);
      magnitude = std::max(magnitude, std::fabs(p[a]));
    }
  // The farthest point of B from the light.
  double reach2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::max(std::fabs(b_lo[a] - light[a]), std::fabs(b_hi[a] - light[a]));
    reach2 += d * d;
  }
  const double reach = std::sqrt(reach2), scale = magnitude + reach;
  // The float32 pipeline's positions, matrices and light are rounded to
  // float32 from coordinates up to `magnitude` (2^-24 each; far-from-origin
  // scenes: tenths of a unit at 3e6): its surfaces and volumes lie within
  // slack_b of the exact ones.
  const double slack_b = 0x1p-20 * magnitude + 0x1p-30 * scale;
  // The light in, on or within 4 slack_b of the occluder's box: R is everything.
  if (!(to_occluder > 4 * slack_b)) return std::nullopt;

  // R = cone(l, Q) ∩ B ∩ {beyond Q's nearest corner along l's axis to Q},
  // each plane moved out to hold the float pipeline's volume and surfaces
  // too: the vertices of the polytope these planes bound, by enumerating
  // every triple of planes (at most 19 planes: 969 triples, microseconds).
  struct Plane {
    Vec3d n;
    double d;  // inside: dot(n, x) + d >= 0
  };
  std::vector<Plane> planes;
  for (int a = 0; a < 3; ++a) {
    Vec3d n{0, 0, 0};
    n[a] = 1;
    planes.push_back({n, -(b_lo[a] - slack_b)});
    n[a] = -1;
    planes.push_back({n, b_hi[a] + slack_b});
  }
  // The float pipeline's volume is {l' + t (p' - l') : t >= 1} over its
  // light l' and points p' of its mesh, each within slack_b of the exact l
  // and a point p of Q.  For a unit normal n,
  //   n . (x' - l) = (1 - t) n . (l' - l) + t n . (p' - l)
  //               >= t n . (p - l) - (2t - 1) slack_b,
  // and within B grown by slack_b, t = |x' - l'| / |p' - l'| is at most
  // t_max below (|x' - l'| <= reach + (sqrt(3) + 1) slack_b).
  const double t_max = (reach + 3 * slack_b) / (to_occluder - 2 * slack_b);
  // The cone's facets: the planes through l and an edge of Q with every
  // corner of Q on one side, up to the double rounding of the sides (a
  // plane with a corner on its far side, however little, does not hold the
  // rays through that corner far beyond Q).  n . (p - l) >= -facet_rounding
  // on Q, so the float volume lies within (2 t_max - 1) slack_b + t_max
  // facet_rounding of each; each is moved out by slack_b more than that.
  const double facet_rounding = 0x1p-40 * scale;
  const double slack_cone = 2 * t_max * slack_b + t_max * facet_rounding;
  for (int i = 0; i < 8; ++i)
    for (int bit = 1; bit < 8; bit <<= 1) {
      const int j = i | bit;
      if (j == i) continue;
      Vec3d n = cross(q[i] - light, q[j] - light);
      const double length = std::sqrt(dot(n, n));
      if (!(length > 0)) continue;
      n = (1.0 / length) * n;
      double lo = kInf, hi = -kInf;
      for (const Vec3d& c : q) {
        const double side = dot(n, c - light);
        lo = std::min(lo, side);
        hi = std::max(hi, side);
      }
      if (lo >= -facet_rounding) {
        planes.push_back({n, -dot(n, light) + slack_cone});
      } else if (hi <= facet_rounding) {
        planes.push_back({-1.0 * n, dot(n, light) + slack_cone});
      }
    }
  {
    Vec3d centre{0, 0, 0};
    for (const Vec3d& c : q) centre = centre + 0.125 * c;
    Vec3d n = centre - light;
    const double length = std::sqrt(dot(n, n));
    if (length > 0) {
      n = (1.0 / length) * n;
      double nearest = kInf;
      for (const Vec3d& c : q) nearest = std::min(nearest, dot(n, c - light));
      // n . (x' - l) >= t (nearest - 2 slack_b) + slack_b >= nearest - slack_b.
      if (nearest > 2 * slack_b) planes.push_back({n, -dot(n, light) - nearest + slack_b});
    }
  }
  std::vector<Vec3d> vertices;
  for (std::size_t a = 0; a < planes.size(); ++a)
    for (std::size_t b = a + 1; b < planes.size(); ++b)
      for (std::size_t c = b + 1; c < planes.size(); ++c) {
        const Vec3d &na = planes[a].n, &nb = planes[b].n, &nc = planes[c].n;
        const Vec3d bc = cross(nb, nc);
        const double det = dot(na, bc);
        if (!(std::fabs(det) > 1e-12)) continue;
        const Vec3d x = (1.0 / det) * (-planes[a].d * bc - planes[b].d * cross(nc, na) - planes[c].d * cross(na, nb));
        bool inside = std::isfinite(x.x + x.y + x.z);
        for (std::size_t k = 0; k < planes.size() && inside; ++k)
          inside = dot(planes[k].n, x) + planes[k].d >= -0x1p-24 * scale;
        if (inside) vertices.push_back(x);
      }

  // R's vertices in clip space (double, through the uploaded projection).
  std::vector<std::array<double, 4>> clip(vertices.size());
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const Vec3d c = view.apply(vertices[k]);
    const double in[4] = {c.x, c.y, c.z, 1.0};
    for (int r = 0; r < 4; ++r) {
      double v = 0;
      for (int col = 0; col < 4; ++col) v += double{projection.at(r, col)} * in[col];
      clip[k][r] = v;
    }
  }
  auto near_distance = [&](const std::array<double, 4>& v) {
    return mapping == DepthMapping::Standard ? v[2] + v[3] : v[3] - v[2];
  };
  const int width = scene.camera.width, height = scene.camera.height;
  VolumeBounds out;
  double x_lo = kInf, x_hi = -kInf, y_lo = kInf, y_hi = -kInf, z_lo = kInf, z_hi = -kInf;
  bool any = false;
  auto add = [&](const std::array<double, 4>& v) {
    if (!(v[3] > 0)) return;  // a cut on the near plane has w > 0 unless the frustum is degenerate
    any = true;
    const double x = (v[0] / v[3] + 1) * 0.5 * width, y = (v[1] / v[3] + 1) * 0.5 * height;
    const double z = mapping == DepthMapping::Standard ? (v[2] / v[3] + 1) * 0.5 : v[2] / v[3];
    x_lo = std::min(x_lo, x);
    x_hi = std::max(x_hi, x);
    y_lo = std::min(y_lo, y);
    y_hi = std::max(y_hi, y);
    z_lo = std::min(z_lo, z);
    z_hi = std::max(z_hi, z);
  };
  for (std::size_t i = 0; i < clip.size(); ++i) {
    const double di = near_distance(clip[i]);
    if (di >= 0) add(clip[i]);
    out.meets_near_plane = out.meets_near_plane || !(di > 0);
    for (std::size_t j = i + 1; j < clip.size(); ++j) {
      const double dj = near_distance(clip[j]);
      if ((di >= 0) == (dj >= 0)) continue;
      const double t = di / (di - dj);
      std::array<double, 4> cut;
      for (int r = 0; r < 4; ++r) cut[r] = clip[i][r] + t * (clip[j][r] - clip[i][r]);
      add(cut);
    }
  }
  if (!any || !std::isfinite(x_lo + x_hi + y_lo + y_hi + z_lo + z_hi)) {
    if (!any) return out;  // R lies behind the near plane: no pixel can change
    return std::nullopt;
  }
  auto clamp_pixel = [](double v, int size) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(size))); };
  out.scissor = {clamp_pixel(std::floor(x_lo) - 2, width), clamp_pixel(std::floor(y_lo) - 2, height),
                 clamp_pixel(std::ceil(x_hi) + 2, width), clamp_pixel(std::ceil(y_hi) + 2, height)};
  const double slack = 0x1p-16 + 8.0 / 16777215.0;
  out.depth_min = std::clamp(z_lo - slack, 0.0, 1.0);
  out.depth_max = std::clamp(z_hi + slack, 0.0, 1.0);
  return out;
}

}  // namespace nearcap::gl
