// The near-cap pass's light-pyramid filter (see light_pyramid_cull.hpp).
#include "nearcap/gl/light_pyramid_cull.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace nearcap::gl {
namespace {

// Float32 rounding allowance: far above the few float32 roundings between a
// coordinate and the vertex program's output (2^-24 each).
constexpr double kFloatAllowance = 0x1p-16;

}  // namespace

bool certainly_misses_light_pyramid(const Scene& scene, std::size_t object, const Vec3d& light, double margin_x,
                                    double margin_y, std::size_t* faces_examined) {
  std::size_t examined_here = 0;
  std::size_t& examined = faces_examined ? *faces_examined : examined_here;
  examined = 0;
  const SceneObject& obj = scene.objects.at(object);
  if (!obj.mesh) return false;
  const FacePlanes& fp = obj.mesh->face_planes;
  if (fp.chunk_box.empty() || fp.chunk_faces.size() != obj.mesh->triangles.size()) return false;

  // The pyramid in camera space: apex l, the grown near rectangle at z = -n.
  const Affine3d& view = scene.camera.view;
  const Frustum& f = scene.camera.frustum;
  const Vec3d l = view.apply(light);
  const double n = f.near;
  const double cx = 0.5 * (f.left + f.right), cy = 0.5 * (f.bottom + f.top);
  const double hx = 0.5 * (f.right - f.left) * (1 + margin_x), hy = 0.5 * (f.top - f.bottom) * (1 + margin_y);
  const std::array<Vec3d, 4> corner{Vec3d{cx - hx, cy - hy, -n}, Vec3d{cx + hx, cy - hy, -n},
                                    Vec3d{cx + hx, cy + hy, -n}, Vec3d{cx - hx, cy + hy, -n}};
  const Vec3d centre{cx, cy, -n};
  double light_mag = std::max(
      {std::fabs(light.x), std::fabs(light.y), std::fabs(light.z), std::fabs(l.x), std::fabs(l.y), std::fabs(l.z)});
  // The light within rounding of the near plane: a flat pyramid, not decided.
  const double axial = l.z + n;
  if (!(std::fabs(axial) > kFloatAllowance * (light_mag + n))) return false;
  // Planes as (normal, point): inside where dot(normal, p - point) >= 0.
  std::array<Vec3d, 6> normal;
  std::array<Vec3d, 6> through;
  for (int k = 0; k < 4; ++k) {
    Vec3d nk = cross(corner[k] - l, corner[(k + 1) % 4] - l);
    if (dot(nk, centre - l) < 0) nk = -1.0 * nk;
    normal[k] = nk;
    through[k] = l;
  }
  // The near plane: the light's side of it.
  normal[4] = Vec3d{0, 0, axial > 0 ? 1.0 : -1.0};
  through[4] = centre;
  // And the plane through the light parallel to it: the near plane's side.
  normal[5] = -1.0 * normal[4];
  through[5] = l;

  // The planes' lengths, once: every box below is measured against them.
  std::array<double, 6> length;
  std::array<bool, 6> plane_usable;
  for (int k = 0; k < 6; ++k) {
    length[k] = std::sqrt(dot(normal[k], normal[k]));
    plane_usable[k] = length[k] > 0 && std::isfinite(length[k]);
  }

  const Affine3d& model = obj.object_to_world;
  double model_mag = 0;
  for (const auto& row : model.rows)
    for (double v : row) model_mag = std::max(model_mag, std::fabs(v));

  // Certainly outside one plane: every corner of the box's camera-space
  // image (which holds the image of the box) beyond it by more than the
  // allowance, measured in the plane's own units.
  auto outside = [&](const Vec3d& lo, const Vec3d& hi) {
    std::array<Vec3d, 8> p;
    double mag = light_mag + n;
    for (int c = 0; c < 8; ++c) {
      const Vec3d o{(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
      const Vec3d w = model.apply(o);
      p[c] = view.apply(w);
      mag = std::max({mag, model_mag * std::max({std::fabs(o.x), std::fabs(o.y), std::fabs(o.z)}), std::fabs(w.x),
                      std::fabs(w.y), std::fabs(w.z), std::fabs(p[c].x), std::fabs(p[c].y), std::fabs(p[c].z)});
    }
    // Any point of the box, as the float pipeline sees it, within `slack` of
    // its exact camera-space position.
    const double slack = kFloatAllowance * mag;
    for (int k = 0; k < 6; ++k) {
      if (!plane_usable[k]) return false;
      bool all_beyond = true;
      for (int c = 0; c < 8 && all_beyond; ++c) all_beyond = dot(normal[k], p[c] - through[k]) < -slack * length[k];
      if (all_beyond) return true;
    }
    return false;
  };

  // The near plane too close to the eye for the float32 cut (see header):
  // the box's depth bounds the occluder's.
  {
    double depth = 0;
    for (int c = 0; c < 8; ++c) {
      const Vec3d o{(c & 1) ? fp.box_hi.x : fp.box_lo.x, (c & 2) ? fp.box_hi.y : fp.box_lo.y,
                    (c & 4) ? fp.box_hi.z : fp.box_lo.z};
      const Vec3d p = view.apply(model.apply(o));
      depth = std::max({depth, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    }
    if (!(n >= 0x1p-10 * depth)) return false;
  }

  if (outside(fp.box_lo, fp.box_hi)) return true;
  // Then chunk by chunk, and face by face in a chunk not decided whole: a
  // face's points lie in its vertices' box.
  const TriangleMesh& mesh = *obj.mesh;
  for (std::size_t chunk = 0; chunk < fp.chunk_box.size(); ++chunk) {
    if (outside(fp.chunk_box[chunk][0], fp.chunk_box[chunk][1])) continue;
    const std::size_t end = std::min(fp.chunk_faces.size(), (chunk + 1) * FacePlanes::kFacesPerChunk);
    for (std::size_t slot = chunk * FacePlanes::kFacesPerChunk; slot < end; ++slot) {
      const auto& t = mesh.triangles[fp.chunk_faces[slot]];
      const Vec3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
      const Vec3d lo{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})};
      const Vec3d hi{std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})};
      ++examined;
      if (!outside(lo, hi)) return false;
    }
  }
  return true;
}

}  // namespace nearcap::gl
