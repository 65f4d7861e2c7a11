// AtomicZP's eye count in float32 (see eye_count.hpp).
#include "nearcap/gl/eye_count.hpp"

#include <cmath>

#include "nearcap/gl/light_frustum.hpp"

namespace nearcap::gl {
namespace {

struct V3 {
  float x, y, z;
};

V3 xyz(const Vec4f& v) { return {v.x, v.y, v.z}; }
V3 minus(const V3& a, const V3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }

// a * b - c * d: two products and a difference, or one product fused into
// the difference (what a contracting shader compiler emits).
float difference_of_products(float a, float b, float c, float d, Arithmetic ar) {
  if (ar == Arithmetic::Fused) return std::fma(a, b, -(c * d));
  return a * b - c * d;
}

V3 cross(const V3& a, const V3& b, Arithmetic ar) {
  return {difference_of_products(a.y, b.z, a.z, b.y, ar), difference_of_products(a.z, b.x, a.x, b.z, ar),
          difference_of_products(a.x, b.y, a.y, b.x, ar)};
}

// x x' + y y' + z z', left to right, or as an fma chain.
float dot(const V3& a, const V3& b, Arithmetic ar) {
  if (ar == Arithmetic::Fused) return std::fma(a.z, b.z, std::fma(a.y, b.y, a.x * b.x));
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

// The sign of the 3x3 part of a float32 modelview: does it mirror?
bool mirrors(const Mat4f& m) {
  const float det = m.at(0, 0) * (m.at(1, 1) * m.at(2, 2) - m.at(1, 2) * m.at(2, 1)) -
                    m.at(0, 1) * (m.at(1, 0) * m.at(2, 2) - m.at(1, 2) * m.at(2, 0)) +
                    m.at(0, 2) * (m.at(1, 0) * m.at(2, 1) - m.at(1, 1) * m.at(2, 0));
  return det < 0.0f;
}

}  // namespace

bool float_eye_segment_crosses(const Vec4f& p0, const Vec4f& p1, const Vec4f& p2, const Vec4f& light, bool mirrored,
                               Arithmetic ar) {
  const V3 a = xyz(p0), b = xyz(p1), c = xyz(p2), l = xyz(light);
  const V3 n = cross(minus(b, a), minus(c, a), ar);
  const float h = mirrored ? -1.0f : 1.0f;
  if (!(h * dot(n, minus(l, a), ar) > 0.0f)) return false;            // not facing the light
  if (!(h * dot(n, minus(V3{0, 0, 0}, a), ar) < 0.0f)) return false;  // the eye not behind the plane
  const float s0 = dot(l, cross(a, b, ar), ar), s1 = dot(l, cross(b, c, ar), ar), s2 = dot(l, cross(c, a, ar), ar);
  return (s0 > 0.0f && s1 > 0.0f && s2 > 0.0f) || (s0 < 0.0f && s1 < 0.0f && s2 < 0.0f);
}

EyeCountObject eye_count_object(const Scene& scene, std::size_t object, Arithmetic ar) {
  EyeCountObject out;
  out.modelview = multiply(to_mat4f(scene.camera.view), to_mat4f(scene.objects[object].object_to_world), ar);
  out.mirrored = mirrors(out.modelview);
  return out;
}

FloatEyeCount float_eye_count(const Scene& scene, std::size_t light, Arithmetic ar) {
  std::vector<std::size_t> occluders;
  for (std::size_t o = 0; o < scene.objects.size(); ++o)
    if (scene.objects[o].occluder) occluders.push_back(o);
  return float_eye_count(scene, light, occluders, ar);
}

FloatEyeCount float_eye_count(const Scene& scene, std::size_t light, const std::vector<std::size_t>& objects,
                              Arithmetic ar) {
  FloatEyeCount out;
  const Vec4f l = light_in_camera_space(scene, light);
  for (std::size_t o : objects) {
    const SceneObject& obj = scene.objects[o];
    if (!obj.occluder) continue;
    const EyeCountObject uniforms = eye_count_object(scene, o, ar);
    const TriangleMesh& mesh = *obj.mesh;
    std::vector<Vec4f> p(mesh.positions.size());
    for (std::size_t v = 0; v < p.size(); ++v) {
      const Vec3d& q = mesh.positions[v];
      p[v] = transform(uniforms.modelview,
                       {static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z), 1.0f}, ar);
    }
    for (const auto& t : mesh.triangles) {
      ++out.triangles;
      if (float_eye_segment_crosses(p[t[0]], p[t[1]], p[t[2]], l, uniforms.mirrored, ar)) ++out.count;
    }
  }
  return out;
}

}  // namespace nearcap::gl
