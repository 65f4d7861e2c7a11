// In-memory scenes, validated like scene files (see scene_builder.hpp).
#include "nearcap/io/scene_builder.hpp"

#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include "mesh_reading.hpp"
#include "nearcap/error.hpp"
#include "nearcap/exact/light_validation.hpp"
#include "scene_checks.hpp"

namespace nearcap {
namespace {

bool finite(const Affine3d& m) {
  for (const auto& row : m.rows)
    for (double v : row)
      if (!std::isfinite(v)) return false;
  return true;
}

void check_camera(const Camera& camera, const std::string& source) {
  using scene_checks::fail;
  if (!finite(camera.view)) fail(source, ErrorKind::NonFinite, "camera.view", "a matrix entry is not finite");
  if (!scene_checks::invertible(camera.view))
    fail(source, ErrorKind::Camera, "camera.view",
         "the matrix is not invertible (its 3x3 linear part has determinant 0)");
  scene_checks::check_frustum(camera.frustum, source, "camera.frustum");
  for (const auto& [name, pixels] : {std::pair<const char*, int>{"width", camera.width}, {"height", camera.height}})
    if (pixels < 1 || pixels > 16384)
      fail(source, ErrorKind::Camera, std::string("camera.") + name,
           "viewport size " + std::to_string(pixels) + " is outside [1, 16384] pixels");
}

void check_light(const Light& light, std::size_t k, const std::string& source) {
  const Vec3d& p = light.position;
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
    scene_checks::fail(source, ErrorKind::NonFinite, "lights[" + std::to_string(k) + "].position",
                       "a coordinate is not finite");
}

void check_transform(const Affine3d& object_to_world, const std::string& source, const std::string& where) {
  if (!finite(object_to_world))
    scene_checks::fail(source, ErrorKind::NonFinite, where + ".matrix", "a matrix entry is not finite");
  if (!scene_checks::invertible(object_to_world))
    scene_checks::fail(source, ErrorKind::Schema, where + ".matrix",
                       "the matrix is not invertible (its 3x3 linear part has determinant 0)");
}

}  // namespace

std::string scene_name(const Scene& scene) { return scene.source.empty() ? "in-memory scene" : scene.source; }

void check_scene_fields(const Scene& scene) {
  using scene_checks::fail;
  const std::string source = scene_name(scene);
  if (scene.lights.empty()) fail(source, ErrorKind::Schema, "lights", "the scene has no light");
  if (scene.objects.empty()) fail(source, ErrorKind::Schema, "objects", "the scene has no object");
  check_camera(scene.camera, source);
  for (std::size_t k = 0; k < scene.lights.size(); ++k) check_light(scene.lights[k], k, source);
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const std::string where = "objects[" + std::to_string(k) + "]";
    if (scene.objects[k].mesh == nullptr) fail(source, ErrorKind::Schema, where + ".mesh", "no mesh");
    check_transform(scene.objects[k].object_to_world, source, where);
  }
}

SceneBuilder::SceneBuilder(std::string source) : source_(std::move(source)) {}

SceneBuilder& SceneBuilder::camera(const Camera& camera) {
  camera_ = camera;
  has_camera_ = true;
  return *this;
}

SceneBuilder& SceneBuilder::light(const Vec3d& position) {
  lights_.push_back(Light{position});
  return *this;
}

SceneBuilder& SceneBuilder::object(TriangleMesh mesh, const Affine3d& object_to_world) {
  objects_.push_back({std::move(mesh), object_to_world, true});
  return *this;
}

SceneBuilder& SceneBuilder::receiver(TriangleMesh mesh, const Affine3d& object_to_world) {
  objects_.push_back({std::move(mesh), object_to_world, false});
  return *this;
}

Scene SceneBuilder::build() const {
  using scene_checks::fail;
  if (!has_camera_) fail(source_, ErrorKind::Schema, "camera", "no camera was given");
  if (lights_.empty()) fail(source_, ErrorKind::Schema, "lights", "no light was given");
  if (objects_.empty()) fail(source_, ErrorKind::Schema, "objects", "no object was given");
  Scene scene;
  scene.source = source_;
  scene.camera = camera_;
  check_camera(camera_, source_);
  for (std::size_t k = 0; k < lights_.size(); ++k) {
    check_light(lights_[k], k, source_);
    scene.lights.push_back(lights_[k]);
  }
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    const Pending& p = objects_[k];
    const std::string where = "objects[" + std::to_string(k) + "]";
    check_transform(p.object_to_world, source_, where);
    auto mesh = std::make_shared<TriangleMesh>(p.mesh);
    if (mesh->source.empty()) mesh->source = where;
    try {
      mesh_reading::check_read_mesh(*mesh);
      if (p.occluder) validate_occluder(*mesh);
    } catch (const Error& e) {
      throw Error(e.kind(), source_ + ": " + where + (p.occluder ? " (occluder)" : "") + ": " + e.what());
    }
    if (!mesh->has_adjacency()) build_adjacency(*mesh);
    compute_face_planes(*mesh);
    SceneObject o;
    o.mesh_path = mesh->source;
    o.mesh = mesh;
    o.object_to_world = p.object_to_world;
    o.occluder = p.occluder;
    scene.objects.push_back(std::move(o));
  }
  validate_scene_geometry(scene);
  return scene;
}

}  // namespace nearcap
