// nearcap/exact/camera_space.hpp — the scene's geometry in camera space, certified.
//
// Every exact predicate in nearcap works in camera space (OpenGL eye space:
// camera at the origin looking down -z; near plane z = -near), where pixel
// centres and the near plane have simple coordinates.  A camera-space vertex is
// the exact rational view * object_to_world * v.  CameraSpaceScene stores, for
// every vertex of every object and for every light, a BoundedDouble estimate of
// that rational (the filter's input) and recomputes the rational itself on
// demand (the exact path, rare).  The rational maps and lights are composed
// the first time an exact_*() asks (once, thread-safe), so a frame whose
// filters all decide builds none of them.  Nothing here rounds the scene: the
// estimates carry certified error bounds, and exact_*() are exact.
#pragma once

#include <cstddef>
#include <mutex>
#include <vector>

#include "nearcap/numeric/bounded_double.hpp"
#include "nearcap/numeric/filter_stats.hpp"
#include "nearcap/numeric/rational.hpp"
#include "nearcap/numeric/sign.hpp"
#include "nearcap/scene/scene.hpp"

namespace nearcap {

using BoundedVec3 = Vec3<BoundedDouble>;
using RationalVec3 = Vec3<Rational>;

// An affine map with exact rational entries (composition of double maps).
struct RationalAffine {
  Rational m[3][4];
  static RationalAffine from(const Affine3d& a);
  RationalAffine then(const RationalAffine& outer) const;  // outer * this
  RationalVec3 apply(const RationalVec3& p) const;
  Sign linear_determinant_sign() const;
};

class CameraSpaceScene {
 public:
  // Keeps a pointer to `scene`, which must outlive it and stay in place.
  explicit CameraSpaceScene(const Scene& scene);
  CameraSpaceScene(const CameraSpaceScene&) = delete;
  CameraSpaceScene& operator=(const CameraSpaceScene&) = delete;

  const Scene& scene() const { return *scene_; }
  std::size_t object_count() const { return objects_.size(); }
  std::size_t light_count() const { return lights_.size(); }
  const SceneObject& object(std::size_t o) const { return scene_->objects[o]; }
  const TriangleMesh& mesh(std::size_t o) const { return *scene_->objects[o].mesh; }

  // Certified estimate of a vertex.  All vertices of an object share one error
  // bound (max_error), derived once from the map's bound and the largest input
  // coordinate, so the transform is plain double arithmetic.
  BoundedVec3 vertex(std::size_t o, VertexIndex v) const {
    const Vec3d& p = objects_[o].estimates[v];
    const double e = objects_[o].max_error;
    return {BoundedDouble(p.x, e), BoundedDouble(p.y, e), BoundedDouble(p.z, e)};
  }
  // The estimate alone (within max_error(o) of the exact vertex, per coordinate).
  const Vec3d& vertex_estimate(std::size_t o, VertexIndex v) const { return objects_[o].estimates[v]; }
  // Bounds over all vertex estimates of object o: |coordinate| <= max_abs(o),
  // |estimate - exact| <= max_error(o).  Inputs of the static filters.
  double max_abs(std::size_t o) const { return objects_[o].max_abs; }
  double max_error(std::size_t o) const { return objects_[o].max_error; }
  RationalVec3 exact_vertex(std::size_t o, VertexIndex v) const;
  // +1 when view * object_to_world preserves orientation (counter-clockwise
  // triangles stay counter-clockwise seen from outside), -1 when it mirrors.
  Sign handedness(std::size_t o) const { return objects_[o].handedness; }

  const BoundedVec3& light(std::size_t k) const { return lights_[k]; }
  const RationalVec3& exact_light(std::size_t k) const { return exact().lights[k]; }

  // The near plane is z = -near; near and the frustum bounds are exact doubles.
  const Frustum& frustum() const { return scene_->camera.frustum; }

 private:
  struct ObjectData {
    std::vector<Vec3d> estimates;
    Sign handedness = Sign::Positive;
    double max_abs = 0;
    double max_error = 0;
  };
  // The exact side: each object's view * object_to_world, each light in camera space.
  struct ExactData {
    std::vector<RationalAffine> to_camera;
    std::vector<RationalVec3> lights;
  };
  const ExactData& exact() const;
  const Scene* scene_;
  std::vector<ObjectData> objects_;
  std::vector<BoundedVec3> lights_;
  mutable std::once_flag exact_once_;
  mutable ExactData exact_;
};

// Filtered evaluation: `approx()` returns a BoundedDouble; when its sign is
// uncertain, `exact()` returns the same expression as a Rational.
template <class Approx, class Exact>
Sign filtered_sign(Predicate p, FilterStats* stats, Approx&& approx, Exact&& exact) {
  if (const auto s = approx().sign()) {
    if (stats) stats->record(p, false);
    return *s;
  }
  if (stats) stats->record(p, true);
  return sign_of(exact());
}

}  // namespace nearcap
