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
  // allowance, measured in the plane's own units.  `box_slack`: where given,
  // the allowance (which holds for every point of the box).
  auto outside = [&](const Vec3d& lo, const Vec3d& hi, double* box_slack = nullptr) {
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
    if (box_slack) *box_slack = slack;
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

  // A face of a chunk by its three vertices: the float pipeline draws the
  // triangle their images span, so with each image beyond one plane by more
  // than the chunk's allowance (its vertices lie in the chunk's box), the
  // whole triangle is.  The planes before the first unusable one, as the
  // boxes test them, starting from the one that decided the last face (a
  // chunk's faces lie near each other); rounding in double is far below the
  // allowance.
  const Affine3d modelview = compose_rounded(view, model);
  int usable = 0;
  while (usable < 6 && plane_usable[usable]) ++usable;
  std::array<double, 6> offset{};
  for (int k = 0; k < usable; ++k) offset[k] = dot(normal[k], through[k]);
  int last = 0;
  auto face_outside = [&](const std::array<VertexIndex, 3>& t, double slack) {
    const Vec3d a = modelview.apply(obj.mesh->positions[t[0]]), b = modelview.apply(obj.mesh->positions[t[1]]),
                c = modelview.apply(obj.mesh->positions[t[2]]);
    for (int i = 0; i < usable; ++i) {
      const int k = (last + i) % usable;
      const double limit = offset[k] - slack * length[k];
      if (dot(normal[k], a) < limit && dot(normal[k], b) < limit && dot(normal[k], c) < limit) {
        last = k;
        return true;
      }
    }
    return false;
  };

  if (outside(fp.box_lo, fp.box_hi)) return true;
  // Then chunk by chunk, and face by face in a chunk not decided whole.
  const TriangleMesh& mesh = *obj.mesh;
  for (std::size_t chunk = 0; chunk < fp.chunk_box.size(); ++chunk) {
    double slack = 0;
    if (outside(fp.chunk_box[chunk][0], fp.chunk_box[chunk][1], &slack)) continue;
    const std::size_t end = std::min(fp.chunk_faces.size(), (chunk + 1) * FacePlanes::kFacesPerChunk);
    for (std::size_t slot = chunk * FacePlanes::kFacesPerChunk; slot < end; ++slot) {
      ++examined;
      if (!face_outside(mesh.triangles[fp.chunk_faces[slot]], slack)) return false;
    }
  }
  return true;
}

}  // namespace nearcap::gl
