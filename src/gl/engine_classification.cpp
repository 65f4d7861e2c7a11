// Plain float32 silhouette extraction and case classification, GLM style.
#include "nearcap/gl/engine_classification.hpp"

#include <glm/glm.hpp>

#include "glm_affine.hpp"
#include "nearcap/gl/light_frustum.hpp"

namespace nearcap {
namespace {

Sign float_side(float v) { return v >= 0.0f ? Sign::Positive : Sign::Negative; }

}  // namespace

EngineSilhouette engine_silhouette(const Scene& scene, std::size_t object, std::size_t light) {
  const SceneObject& obj = scene.objects[object];
  const TriangleMesh& mesh = *obj.mesh;
  const glm::mat4 view = gl::to_glm_float(scene.camera.view);
  const glm::mat4 modelview = view * gl::to_glm_float(obj.object_to_world);
  // The same float32 light position as the light frustum's Delta (one computation).
  const gl::Vec4f light_camera = gl::light_in_camera_space(scene, light);
  const glm::vec3 l(light_camera.x, light_camera.y, light_camera.z);
  const float near = static_cast<float>(scene.camera.frustum.near);
  const float handedness = glm::determinant(glm::mat3(modelview)) >= 0.0f ? 1.0f : -1.0f;

  std::vector<glm::vec3> p(mesh.positions.size());
  for (std::size_t v = 0; v < p.size(); ++v) {
    const Vec3d& q = mesh.positions[v];
    p[v] = glm::vec3(modelview *
                     glm::vec4(static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z), 1.0f));
  }
  EngineSilhouette out;
  out.facing.resize(mesh.triangle_count());
  for (FaceIndex f = 0; f < mesh.triangle_count(); ++f) {
    const auto& t = mesh.triangles[f];
    const glm::vec3 n = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
    out.facing[f] = handedness * glm::dot(n, l - p[t[0]]) > 0.0f ? Facing::Front : Facing::Back;
  }
  out.edges = silhouette_edges(mesh, out.facing);
  out.cases.reserve(out.edges.size());
  for (const SilhouetteEdge& e : out.edges) {
    const glm::vec3& a = p[e.a];
    const glm::vec3& d = p[e.d];
    out.cases.push_back(quad_case_from_sides(
        {float_side(a.z + near), float_side(d.z + near), float_side(a.z - l.z), float_side(d.z - l.z)}));
  }
  return out;
}

}  // namespace nearcap
