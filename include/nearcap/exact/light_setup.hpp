// nearcap/exact/light_setup.hpp — what the exact reference builds for a light
// that does not depend on the camera, and a cache that keeps it across frames.
//
// The per-pixel reference (pixel_reference.hpp) needs three kinds of data:
//   - per object: its mesh's face planes and adjacency.  TriangleMesh carries
//     them, built once when the mesh is read (MeshCache keeps one mesh per
//     file for a whole sweep);
//   - per (object, light): which triangles face the light (light_facing.hpp),
//     and, over all objects, the light-front-facing occluder triangles binned
//     by their direction from the light (a CentralGrid).  Both are built in
//     WORLD space here, so they hold while the objects and the light stay put,
//     whatever the camera does;
//   - per frame: the camera-space triangle data of the predicates and the grid
//     around the eye (pixel_tracer_impl.hpp).
//
// Exactness: the facing is exact (light_facing.hpp); the world-space grid is a
// filter like every CentralGrid (central_grid.hpp), queried with camera-space
// directions mapped to world space by WorldDirections below, whose certified
// error bound makes a too-uncertain query return every triangle.  A cached
// item is reused only when every number it was built from is equal (the
// light's world position, each object's mesh, object_to_world and occluder
// flag, compared as doubles with ==), so a moved light or object rebuilds it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "nearcap/exact/camera_space.hpp"
#include "nearcap/exact/central_grid.hpp"
#include "nearcap/exact/light_facing.hpp"

namespace nearcap {

// The light-side data of one (scene objects, light) pair, in world space.
struct LightSetup {
  // Per object: the facing of each triangle for the light; null for an
  // object that is not an occluder (nothing of it faces the light).
  std::vector<std::shared_ptr<const std::vector<Facing>>> facing;
  // The light-front-facing occluder triangles, as indices into the list of
  // every triangle of every object (object by object, faces in order),
  // ascending.
  std::vector<std::uint32_t> lit;
  // Those triangles binned around the light's world position; ids index `lit`.
  std::unique_ptr<CentralGrid> grid;
};

// Directions from camera space to world space with a certified bound: the
// camera maps world to camera space by x_cam = V x_world + t (scene.camera.view,
// exact doubles), so a direction maps back by V^-1.  A, an inverse of V in
// double, is certified by E = I - A V (evaluated in BoundedDouble): with
// d >= ||E|| (max row sum) below 1/2, ||V^-1|| <= ||A|| / (1 - d) and
// ||V^-1 - A|| <= d ||A|| / (1 - d).
class WorldDirections {
 public:
  explicit WorldDirections(const Affine3d& view);
  // The world-space estimate of the exact direction V^-1 W for a camera-space
  // estimate w with |W - w| <= w_error per coordinate, and its bound per
  // coordinate (infinite when V is too close to singular to certify).
  Vec3d apply(const Vec3d& w, double w_error, double& world_error) const;

 private:
  std::array<std::array<double, 3>, 3> a_{};
  double inverse_norm_ = 0, difference_norm_ = 0, a_norm_ = 0;
  bool certified_ = false;
};

// Light setups and facings kept across frames.  Thread-safe: a sweep's
// configurations ask for them from several threads.  A setup is built once:
// the first thread to miss it stores a pending entry and builds it; a thread
// that asks for it meanwhile joins that build (its parallel loops) and gets
// the same setup.  A build that throws leaves the entry pending, and the next
// thread to ask builds it.  Two threads that miss the same facing outside a
// setup build both compute it, and the first one stored is kept.  Bounded:
// the least recently used entries are dropped beyond the capacities.
class LightSetupCache {
 public:
  explicit LightSetupCache(std::size_t setups = 4, std::size_t facings = 64);

  // How often a lookup found its entry, and how often it had to build.
  struct Counts {
    std::size_t setup_hits = 0, setup_builds = 0, facing_hits = 0, facing_builds = 0;
  };
  Counts counts() const;

 private:
  friend std::shared_ptr<const LightSetup> light_setup(const CameraSpaceScene& scene, std::size_t light,
                                                       LightSetupCache* cache);
  struct ObjectKey {
    std::shared_ptr<const TriangleMesh> mesh;  // held, so that its address stays its identity
    Affine3d object_to_world;
    bool occluder = true;
    bool operator==(const ObjectKey& o) const;
  };
  struct FacingEntry {
    ObjectKey object;
    Vec3d light;
    std::shared_ptr<const std::vector<Facing>> facing;
  };
  struct PendingSetup;  // the build's once-flag and its result (light_setup.cpp)
  // The light setup of `scene` for `light` (`keys`: its objects), its
  // facings taken from and stored in `cache` where given.
  static std::shared_ptr<const LightSetup> build(const CameraSpaceScene& scene, std::size_t light,
                                                 const std::vector<ObjectKey>& keys, LightSetupCache* cache);
  struct SetupEntry {
    std::vector<ObjectKey> objects;
    Vec3d light;
    std::shared_ptr<PendingSetup> pending;  // its setup, once built
  };
  std::size_t setup_capacity_, facing_capacity_;
  mutable std::mutex mutex_;
  std::vector<SetupEntry> setups_;    // most recently used last
  std::vector<FacingEntry> facings_;  // most recently used last
  Counts counts_;
};

// The light setup of `scene` for `light`: from `cache` when it holds one built
// from the same objects and light (then also stored there), built here when
// `cache` is null.
std::shared_ptr<const LightSetup> light_setup(const CameraSpaceScene& scene, std::size_t light,
                                              LightSetupCache* cache = nullptr);

}  // namespace nearcap
