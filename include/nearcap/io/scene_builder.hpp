// nearcap/io/scene_builder.hpp — a scene built in memory, validated like a file.
//
// For a program that already holds its meshes (as OpenMesh or CGAL meshes:
// io/openmesh_adapter.hpp, io/cgal_adapter.hpp) and has no reason to write
// them to disk.  build() applies every check load_scene applies: finite,
// in-range camera and transforms, invertible matrices, every face a triangle
// with distinct in-range vertices, occluders closed outward 2-manifolds, each
// light strictly outside every occluder.  Faults are nearcap::Error naming the
// builder's `source` and the element ("my scene: objects[1] (occluder): ...").
//
//   Scene scene = SceneBuilder("my scene")
//                     .camera(look_at_camera(eye, target, up, 50, 0.1, 100, 640, 480))
//                     .light({2, 5, 1.5})
//                     .object(mesh_from_openmesh(bunny, "bunny"), transform)
//                     .receiver(ground)
//                     .build();
#pragma once

#include <string>
#include <vector>

#include "nearcap/scene/scene.hpp"

namespace nearcap {

// The checks of SceneBuilder::build() that read no mesh: lights and objects
// present, the camera (a finite, invertible view; a frustum as build()
// accepts it; a viewport of 1 to 16384 pixels), finite lights, and each
// object with a mesh and a finite, invertible transform.  Microseconds: the
// front door (nearcap.hpp) runs them on every scene it is given, so that a
// Scene edited after loading fails with an Error here rather than deep in
// the exact kernel.  Throws Error naming scene.source and the element.
void check_scene_fields(const Scene& scene);
// The scene as messages name it: its source, or "in-memory scene" when it has none.
std::string scene_name(const Scene& scene);

class SceneBuilder {
 public:
  explicit SceneBuilder(std::string source = "in-memory scene");
  SceneBuilder& camera(const Camera& camera);
  SceneBuilder& light(const Vec3d& position);
  // An occluder (casts and receives shadows).  `mesh.source` names it in messages.
  SceneBuilder& object(TriangleMesh mesh, const Affine3d& object_to_world = Affine3d::identity());
  // A receiver only (need not be closed).
  SceneBuilder& receiver(TriangleMesh mesh, const Affine3d& object_to_world = Affine3d::identity());
  // Validates and returns the scene; throws nearcap::Error.
  Scene build() const;

 private:
  struct Pending {
    TriangleMesh mesh;
    Affine3d object_to_world;
    bool occluder;
  };
  std::string source_;
  bool has_camera_ = false;
  Camera camera_;
  std::vector<Light> lights_;
  std::vector<Pending> objects_;
};

}  // namespace nearcap
