// The engines' Z-pass / Z-fail rules (see engine_policies.hpp).  Written from
// the published descriptions and sources' behaviour, in float32 as the
// engines compute.
#include "nearcap/analysis/engine_policies.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace nearcap::analysis {
namespace {

struct Box {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};
  Box grown(float by) const { return {lo - glm::vec3(by), hi + glm::vec3(by)}; }
  bool contains(const glm::vec3& p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  }
};

glm::vec3 to_float(const Vec3d& p) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}

std::vector<glm::vec3> world_vertices(const SceneObject& o) {
  std::vector<glm::vec3> out;
  out.reserve(o.mesh->positions.size());
  for (const Vec3d& p : o.mesh->positions) out.push_back(to_float(o.object_to_world.apply(p)));
  return out;
}

Box box_of(const std::vector<glm::vec3>& points) {
  Box b;
  for (const glm::vec3& p : points) {
    b.lo = glm::min(b.lo, p);
    b.hi = glm::max(b.hi, p);
  }
  return b;
}

// Does the segment [a, b] meet the box (slab test)?
bool segment_meets_box(const glm::vec3& a, const glm::vec3& b, const Box& box) {
  float t0 = 0.0f, t1 = 1.0f;
  const glm::vec3 d = b - a;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0f) {
      if (a[k] < box.lo[k] || a[k] > box.hi[k]) return false;
      continue;
    }
    float ta = (box.lo[k] - a[k]) / d[k], tb = (box.hi[k] - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// Squared distance between segments [p1, q1] and [p2, q2] (closest points of
// two segments, as in Ericson, Real-Time Collision Detection, 5.1.9).
float segment_distance_squared(const glm::vec3& p1, const glm::vec3& q1, const glm::vec3& p2, const glm::vec3& q2) {
  const glm::vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const float a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
  float s = 0.0f, t = 0.0f;
  if (a <= 0.0f && e <= 0.0f) return glm::dot(r, r);
  if (a <= 0.0f) {
    t = std::clamp(f / e, 0.0f, 1.0f);
  } else {
    const float c = glm::dot(d1, r);
    if (e <= 0.0f) {
      s = std::clamp(-c / a, 0.0f, 1.0f);
    } else {
      const float b = glm::dot(d1, d2), denom = a * e - b * b;
      s = denom != 0.0f ? std::clamp((b * f - c * e) / denom, 0.0f, 1.0f) : 0.0f;
      t = (b * s + f) / e;
      if (t < 0.0f) {
        t = 0.0f;
        s = std::clamp(-c / a, 0.0f, 1.0f);
      } else if (t > 1.0f) {
        t = 1.0f;
        s = std::clamp((b - c) / a, 0.0f, 1.0f);
      }
    }
  }
  const glm::vec3 c1 = p1 + d1 * s, c2 = p2 + d2 * t;
  return glm::dot(c1 - c2, c1 - c2);
}

// Does the segment [a, b] meet triangle (v0, v1, v2) grown by a sphere of
// radius r: crossing it, or passing within r of one of its edges?
bool segment_meets_grown_triangle(const glm::vec3& a, const glm::vec3& b, float r, const glm::vec3& v0,
                                  const glm::vec3& v1, const glm::vec3& v2) {
  const glm::vec3 dir = b - a, e1 = v1 - v0, e2 = v2 - v0;
  const glm::vec3 p = glm::cross(dir, e2);
  const float det = glm::dot(e1, p);
  if (std::fabs(det) > std::numeric_limits<float>::min()) {
    const glm::vec3 s = a - v0;
    const float u = glm::dot(s, p) / det;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(dir, q) / det;
    const float t = glm::dot(e2, q) / det;
    if (u >= 0.0f && v >= 0.0f && u + v <= 1.0f && t >= 0.0f && t <= 1.0f) return true;
  }
  const float r2 = r * r;
  return segment_distance_squared(a, b, v0, v1) < r2 || segment_distance_squared(a, b, v1, v2) < r2 ||
         segment_distance_squared(a, b, v2, v0) < r2;
}

struct Plane {
  glm::vec3 n;
  float d;  // inside: dot(n, p) + d >= 0
  float at(const glm::vec3& p) const { return glm::dot(n, p) + d; }
};
Plane plane_through(const glm::vec3& normal, const glm::vec3& point) { return {normal, -glm::dot(normal, point)}; }

// The box entirely on the outside of the plane.
bool box_outside(const Box& b, const Plane& pl) {
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p{(c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z};
    if (pl.at(p) >= 0.0f) return false;
  }
  return true;
}

struct CameraFrame {
  glm::vec3 eye, forward;                // world space
  std::array<glm::vec3, 4> near_corner;  // counter-clockwise seen from the eye
  glm::vec3 near_centre;
  float light_to_near;  // the light's signed distance beyond the near plane (eye space)
  float near;
};

CameraFrame camera_frame(const Scene& scene, std::size_t light) {
  const Affine3d& v = scene.camera.view;
  const Frustum& f = scene.camera.frustum;
  // The inverse of the view's affine map, in double (the engine has the
  // camera's world position and axes as floats).
  glm::dmat4 m(1.0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = v.rows[r][c];
  const glm::dmat4 inv = glm::inverse(m);
  auto to_world = [&](double x, double y, double z) {
    const glm::dvec4 p = inv * glm::dvec4(x, y, z, 1.0);
    return glm::vec3(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
  };
  CameraFrame c;
  c.eye = to_world(0, 0, 0);
  c.forward = glm::normalize(to_world(0, 0, -1) - c.eye);
  c.near_corner = {to_world(f.left, f.bottom, -f.near), to_world(f.right, f.bottom, -f.near),
                   to_world(f.right, f.top, -f.near), to_world(f.left, f.top, -f.near)};
  c.near_centre = 0.25f * (c.near_corner[0] + c.near_corner[1] + c.near_corner[2] + c.near_corner[3]);
  const Vec3d l = v.apply(scene.lights[light].position);
  c.light_to_near = static_cast<float>(-l.z - f.near);
  c.near = static_cast<float>(f.near);
  return c;
}

// `w`: the object's world-space vertices (world_vertices).
OccluderChoice doom3(const std::vector<glm::vec3>& w, std::size_t index, const glm::vec3& eye, const glm::vec3& light,
                     float stretch) {
  const Box box = box_of(w).grown(stretch);
  if (box.contains(eye)) return {index, true, "view in the grown box"};
  if (box.contains(light)) return {index, true, "light in the grown box"};
  if (segment_meets_box(light, eye, box)) return {index, true, "light-view segment crosses the grown box"};
  return {index, false, "no test met"};
}

OccluderChoice doom3_bfg(const SceneObject& o, std::size_t index, const glm::vec3& eye, const glm::vec3& light,
                         float stretch) {
  const std::vector<glm::vec3> w = world_vertices(o);  // once, for both tests
  const OccluderChoice coarse = doom3(w, index, eye, light, stretch);
  if (!coarse.zfail) return coarse;
  for (const auto& t : o.mesh->triangles) {
    const glm::vec3 &a = w[t[0]], &b = w[t[1]], &c = w[t[2]];
    if (glm::dot(glm::cross(b - a, c - a), light - a) <= 0.0f) continue;  // not facing the light
    if (segment_meets_grown_triangle(eye, light, stretch, a, b, c))
      return {index, true, "view-light segment meets a grown light-facing triangle"};
  }
  return {index, false, "grown box met, precise test not"};
}

OccluderChoice ogre(const SceneObject& o, std::size_t index, const CameraFrame& cam, const glm::vec3& light) {
  if (std::fabs(cam.light_to_near) <= 1e-6f) return {index, true, "light within 1e-6 of the near plane"};
  std::vector<Plane> planes;
  for (int i = 0; i < 4; ++i) {
    const glm::vec3 &c0 = cam.near_corner[static_cast<std::size_t>(i)],
                    &c1 = cam.near_corner[static_cast<std::size_t>((i + 1) % 4)];
    Plane p = plane_through(glm::cross(c1 - c0, light - c0), c0);
    if (p.at(cam.near_centre) < 0.0f) p = {-p.n, -p.d};  // the rectangle inside
    planes.push_back(p);
  }
  const glm::vec3 n = cam.light_to_near > 0 ? cam.forward : -cam.forward;
  planes.push_back(plane_through(n, cam.eye));
  planes.push_back(plane_through(-n, light));
  const Box box = box_of(world_vertices(o));
  for (const Plane& p : planes)
    if (box_outside(box, p)) return {index, false, "box outside the near-clip volume"};
  return {index, true, "box meets the near-clip volume"};
}

}  // namespace

std::string_view to_string(EnginePolicy p) { return name_of(p); }

std::optional<EnginePolicy> engine_policy_from_string(std::string_view name) { return value_named<EnginePolicy>(name); }

std::vector<OccluderChoice> engine_choices(EnginePolicy policy, const Scene& scene, std::size_t light) {
  const CameraFrame cam = camera_frame(scene, light);
  const glm::vec3 l = to_float(scene.lights[light].position);
  std::vector<OccluderChoice> out;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    const SceneObject& obj = scene.objects[o];
    if (!obj.occluder) continue;
    switch (policy) {
      case EnginePolicy::Doom3:
        out.push_back(doom3(world_vertices(obj), o, cam.eye, l, 2.0f * cam.near));
        break;
      case EnginePolicy::Doom3BFG:
        out.push_back(doom3_bfg(obj, o, cam.eye, l, 4.0f * cam.near));
        break;
      case EnginePolicy::Ogre:
        out.push_back(ogre(obj, o, cam, l));
        break;
      case EnginePolicy::AlwaysZFail:
        out.push_back({o, true, "always"});
        break;
    }
  }
  return out;
}

std::vector<gl::ShadowMethod> object_methods(const Scene& scene, const std::vector<OccluderChoice>& choices) {
  std::vector<gl::ShadowMethod> methods(scene.objects.size(), gl::ShadowMethod::ZPass);
  for (const OccluderChoice& c : choices)
    methods[c.object] = c.zfail ? gl::ShadowMethod::ZFail : gl::ShadowMethod::ZPass;
  return methods;
}

}  // namespace nearcap::analysis
