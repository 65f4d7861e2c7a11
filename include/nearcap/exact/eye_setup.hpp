// nearcap/exact/eye_setup.hpp — what the exact reference builds for a camera
// that does not depend on the light, and a cache that keeps it across lights
// and frames.
//
// The eye side of the per-pixel reference (pixel_reference.hpp) is, in camera
// space:
//   - the grid around the eye: the triangles a view ray can meet first,
//     binned by their direction from the eye (a CentralGrid): every triangle
//     of every object, but for an occluder wholly beyond the near plane that
//     bounds outward solids (TriangleMesh::bounds_outward_solids) only the
//     faces not certainly turned away from the eye (a view ray enters it
//     through one of those first), about half of a large mesh;
//   - per triangle, the edge and plane vectors the view-ray predicates read
//     (a x b, b x c, c x a, n, d), computed when a trace first reads them
//     (most triangles of a large mesh are never read at a small resolution).
// None of it depends on the light, so one eye setup serves every light of a
// frame, and a later frame whose camera and objects have not moved (only the
// light did).  The light side is light_setup.hpp's.
//
// What it is built from, and so the cache's key: the camera's view matrix and
// near distance (a triangle wholly before the near plane is flagged; the
// far plane, the field of view and the resolution are not used), and each
// object's mesh and object_to_world.  A cached setup is reused only when all
// of these are bit for bit equal (doubles compared as bit patterns), so it is
// the setup a fresh build gives, with the per-triangle data some earlier
// frame already computed (the same values: they are functions of the key).
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include "nearcap/exact/camera_space.hpp"

namespace nearcap {

struct EyeSetup;  // src/exact/pixel_tracer_impl.hpp

// Eye setups kept across lights and frames.  Thread-safe: two threads that
// miss the same entry both build it, and the first one stored is kept.
// Bounded: the least recently used entries are dropped beyond the capacity.
class EyeSetupCache {
 public:
  explicit EyeSetupCache(std::size_t capacity = 2);

  // How often a lookup found its entry, and how often it had to build.
  struct Counts {
    std::size_t hits = 0, builds = 0;
  };
  Counts counts() const;

 private:
  friend std::shared_ptr<const EyeSetup> eye_setup(const CameraSpaceScene& scene, EyeSetupCache* cache);
  struct ObjectKey {
    std::shared_ptr<const TriangleMesh> mesh;  // held, so that its address stays its identity
    Affine3d object_to_world;
  };
  struct Key {
    Affine3d view;
    double near = 0;
    std::vector<ObjectKey> objects;
    bool operator==(const Key& o) const;  // bit for bit
  };
  struct Entry {
    Key key;
    std::shared_ptr<const EyeSetup> setup;
  };
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::vector<Entry> entries_;  // most recently used last
  Counts counts_;
};

// The eye setup of `scene`: from `cache` when it holds one built from the same
// camera and objects (then also stored there), built here when `cache` is null.
std::shared_ptr<const EyeSetup> eye_setup(const CameraSpaceScene& scene, EyeSetupCache* cache = nullptr);

}  // namespace nearcap
