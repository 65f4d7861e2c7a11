// Exact placement of a light relative to a closed occluder (see the header).
#include "nearcap/exact/light_validation.hpp"

#include <cmath>
#include <sstream>

#include "nearcap/error.hpp"
#include "nearcap/exact/light_facing.hpp"
#include "nearcap/exact/segment_crossing.hpp"

namespace nearcap {
namespace {

bool on_closed_segment(const RationalVec3& l, const RationalVec3& a, const RationalVec3& b) {
  const RationalVec3 c = cross(b - a, l - a);
  if (sgn(c.x) != 0 || sgn(c.y) != 0 || sgn(c.z) != 0) return false;
  return sgn(Rational(dot(l - a, l - b))) <= 0;
}

// l lies in the plane of (a, b, c): is it in the closed triangle?
bool in_closed_triangle(const RationalVec3& l, const RationalVec3& a, const RationalVec3& b, const RationalVec3& c) {
  const RationalVec3 n = cross(b - a, c - a);
  if (sgn(n.x) == 0 && sgn(n.y) == 0 && sgn(n.z) == 0)
    return on_closed_segment(l, a, b) || on_closed_segment(l, b, c) || on_closed_segment(l, c, a);
  return sgn(Rational(dot(n, cross(a - l, b - l)))) >= 0 && sgn(Rational(dot(n, cross(b - l, c - l)))) >= 0 &&
         sgn(Rational(dot(n, cross(c - l, a - l)))) >= 0;
}

}  // namespace

LightPlacement light_placement(const CameraSpaceScene& scene, std::size_t o, std::size_t light, FaceIndex* face,
                               FilterStats* stats) {
  const TriangleMesh& mesh = scene.mesh(o);
  const std::vector<Facing> facing = light_facing(scene, o, light, stats);
  const BoundedVec3& l = scene.light(light);
  const RationalVec3& le = scene.exact_light(light);
  for (FaceIndex f = 0; f < mesh.triangle_count(); ++f) {
    if (facing[f] != Facing::EdgeOn) continue;
    const auto& t = mesh.triangles[f];
    if (in_closed_triangle(le, scene.exact_vertex(o, t[0]), scene.exact_vertex(o, t[1]), scene.exact_vertex(o, t[2]))) {
      if (face) *face = f;
      return LightPlacement::OnSurface;
    }
  }
  // Probe point straight below the bounding box (camera-space -y... any
  // direction works; we use -z, then the perturbation tilts it).
  double lowest = l.z.v - l.z.e;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) lowest = std::fmin(lowest, scene.vertex(o, t[k]).z.v - scene.vertex(o, t[k]).z.e);
  const double probe_z = std::floor(lowest) - 1.0;
  const BoundedVec3 p{l.x, l.y, BoundedDouble(probe_z)};
  const RationalVec3 pe{le.x, le.y, Rational(probe_z)};

  const SamplePoint probe{p, pe};
  long winding = 0;
  for (FaceIndex f = 0; f < mesh.triangle_count(); ++f) {
    if (facing[f] == Facing::EdgeOn) continue;
    const auto& t = mesh.triangles[f];
    const BoundedVec3 a = scene.vertex(o, t[0]), b = scene.vertex(o, t[1]), c = scene.vertex(o, t[2]);
    // Quick certain rejection: the probe segment stays within x = l.x, y = l.y
    // (up to the infinitesimal tilt), so a triangle certainly on one side of it
    // in x or y cannot be crossed.
    auto certainly_below = [](const BoundedDouble& u, const BoundedDouble& v) { return u.v + u.e < v.v - v.e; };
    if ((certainly_below(a.x, l.x) && certainly_below(b.x, l.x) && certainly_below(c.x, l.x)) ||
        (certainly_below(l.x, a.x) && certainly_below(l.x, b.x) && certainly_below(l.x, c.x)) ||
        (certainly_below(a.y, l.y) && certainly_below(b.y, l.y) && certainly_below(c.y, l.y)) ||
        (certainly_below(l.y, a.y) && certainly_below(l.y, b.y) && certainly_below(l.y, c.y)))
      continue;
    if (segment_crosses_triangle(scene, o, f, light, facing[f], probe, stats))
      winding += facing[f] == Facing::Front ? -1 : +1;
  }
  return winding != 0 ? LightPlacement::Inside : LightPlacement::Outside;
}

void validate_float_range(const Scene& scene, const CameraSpaceScene& cs) {
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    if (!(cs.max_abs(o) <= kFloatPipelineCoordinateLimit)) {  // NaN too
      std::ostringstream s;
      s << scene.source << ": objects[" << o << "] (" << scene.objects[o].mesh_path
        << ") reaches camera-space coordinate " << cs.max_abs(o)
        << ", beyond the float32 pipeline's limit 2^40 = " << kFloatPipelineCoordinateLimit
        << " (scale or move the scene)";
      throw Error(ErrorKind::Range, s.str());
    }
  }
  for (std::size_t k = 0; k < scene.lights.size(); ++k) {
    const BoundedVec3& l = cs.light(k);
    for (int i = 0; i < 3; ++i)
      if (!(std::fabs(l[i].v) <= kFloatPipelineCoordinateLimit)) {
        std::ostringstream s;
        s << scene.source << ": lights[" << k << "] has camera-space coordinate " << l[i].v
          << ", beyond the float32 pipeline's limit 2^40 = " << kFloatPipelineCoordinateLimit;
        throw Error(ErrorKind::Range, s.str());
      }
  }
}

void validate_scene_geometry(const Scene& scene) {
  const CameraSpaceScene cs(scene);
  validate_float_range(scene, cs);
  validate_lights(scene, cs);
}

void validate_lights(const Scene& scene, const CameraSpaceScene& cs) {
  for (std::size_t k = 0; k < scene.lights.size(); ++k) {
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      if (!scene.objects[o].occluder) continue;
      FaceIndex face = kNoFace;
      const LightPlacement where = light_placement(cs, o, k, &face, nullptr);
      const std::string who = scene.source + ": lights[" + std::to_string(k) + "]";
      const std::string what = "objects[" + std::to_string(o) + "] (" + scene.objects[o].mesh_path + ")";
      if (where == LightPlacement::OnSurface)
        throw Error(ErrorKind::Light, who + " lies exactly on the surface of " + what + ", on face " +
                                          std::to_string(face) + "; a light must lie strictly outside every occluder");
      if (where == LightPlacement::Inside)
        throw Error(ErrorKind::Light,
                    who + " lies inside " + what + "; a light must lie strictly outside every occluder");
    }
  }
}

}  // namespace nearcap
