// nearcap/scene/scene.hpp — what a scene is: a camera, point lights, mesh objects.
//
// Frames: object space (mesh files) --object_to_world--> world space
// --camera.view--> camera space (OpenGL eye space: the camera at the origin
// looking down -z, y up).  The near plane is camera-space z = -frustum.near.
//
// Exactness convention (docs/scene-format.md): every number read from a scene file is an
// exact binary64 rational.  What needs a transcendental function (the lookAt
// basis, tan(fovy/2), an Euler rotation) is computed once, in double, and those
// doubles then ARE the scene.  The exact kernel never rounds after that.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "nearcap/numeric/vec3.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap {

// glFrustum's parameters; near and far are positive distances.
struct Frustum {
  double left = -1, right = 1, bottom = -1, top = 1, near = 1, far = 100;
};

struct Camera {
  Affine3d view;  // world -> camera space
  Frustum frustum;
  int width = 0;  // pixels
  int height = 0;
};

struct Light {
  Vec3d position;  // world space
};

struct SceneObject {
  std::string mesh_path;                     // as resolved (relative to the scene file)
  std::shared_ptr<const TriangleMesh> mesh;  // object space; validated if occluder
  Affine3d object_to_world;
  bool occluder = true;  // casts shadows (every object receives them)
};

struct Scene {
  std::string source;  // the scene file, for messages
  Camera camera;
  std::vector<Light> lights;
  std::vector<SceneObject> objects;
};

// Builds view + frustum from the convenient form (computed in double, once).
Camera look_at_camera(const Vec3d& eye, const Vec3d& target, const Vec3d& up, double fovy_deg, double near, double far,
                      int width, int height);

}  // namespace nearcap
