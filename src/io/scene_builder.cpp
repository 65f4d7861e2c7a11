// In-memory scenes, validated like scene files (see scene_builder.hpp).
#include "nearcap/io/scene_builder.hpp"

#include <cmath>
#include <memory>
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

}  // namespace

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
  if (!finite(camera_.view)) fail(source_, ErrorKind::NonFinite, "camera.view", "a matrix entry is not finite");
  if (!scene_checks::invertible(camera_.view))
    fail(source_, ErrorKind::Camera, "camera.view",
         "the matrix is not invertible (its 3x3 linear part has determinant 0)");
  scene_checks::check_frustum(camera_.frustum, source_, "camera.frustum");
  for (const auto& [name, pixels] : {std::pair<const char*, int>{"width", camera_.width}, {"height", camera_.height}})
    if (pixels < 1 || pixels > 16384)
      fail(source_, ErrorKind::Camera, std::string("camera.") + name,
           "viewport size " + std::to_string(pixels) + " is outside [1, 16384] pixels");
  for (std::size_t k = 0; k < lights_.size(); ++k) {
    const Vec3d& p = lights_[k].position;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail(source_, ErrorKind::NonFinite, "lights[" + std::to_string(k) + "].position", "a coordinate is not finite");
    scene.lights.push_back(lights_[k]);
  }
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    const Pending& p = objects_[k];
    const std::string where = "objects[" + std::to_string(k) + "]";
    if (!finite(p.object_to_world))
      fail(source_, ErrorKind::NonFinite, where + ".matrix", "a matrix entry is not finite");
    if (!scene_checks::invertible(p.object_to_world))
      fail(source_, ErrorKind::Schema, where + ".matrix",
           "the matrix is not invertible (its 3x3 linear part has determinant 0)");
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
