// The light-independent eye side of the exact reference (see eye_setup.hpp).
#include "nearcap/exact/eye_setup.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <utility>

#include "pixel_tracer_impl.hpp"
#include "uncancelled.hpp"
#include "vector_pool.hpp"

namespace nearcap {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_bits(const Affine3d& a, const Affine3d& b) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      if (!same_bits(a.rows[i][j], b.rows[i][j])) return false;
  return true;
}

// Whether no view ray's first hit can be one of object o's faces turned away
// from the eye: o is an occluder that bounds outward solids
// (TriangleMesh::bounds_outward_solids: closed, embedded, every component
// outward) and lies wholly beyond the near plane, so a ray, which starts
// there, enters it through a face turned toward the eye before it meets one
// turned away (where it grazes a silhouette edge the perturbation sends it
// in through the face turned toward the eye first, pixel_reference.hpp).
bool back_faces_never_seen_first(const CameraSpaceScene& cs, std::size_t o) {
  if (!cs.object(o).occluder) return false;
  // Each exact z is at most its estimate plus max_error; e is at least that,
  // and rounding to nearest is monotonic, so a computed v.z + e below the
  // near plane's z (an exact double) certifies the exact z below it.
  const double beyond = -cs.frustum().near;
  const double e = cs.max_error(o) * (1.0 + 0x1p-40);
  const std::size_t n = cs.mesh(o).positions.size();
  for (VertexIndex v = 0; v < n; ++v)
    if (!(cs.vertex_estimate(o, v).z + e < beyond)) return false;
  // Asked last: its first call on a mesh runs the self-intersection test.
  return cs.mesh(o).bounds_outward_solids();
}

// Face f of object o certainly turned away from the eye: det(a, b, c) has
// the sign of o's handedness.
bool certainly_turned_away(const CameraSpaceScene& cs, std::size_t o, const std::array<VertexIndex, 3>& t) {
  const BoundedDouble d = plane_data(cs.vertex(o, t[0]), cs.vertex(o, t[1]), cs.vertex(o, t[2])).d;
  return d.sign() == cs.handedness(o);
}

// The eye grid and the triangle table of `cs` (the triangles' own data is
// left to their first read).
std::shared_ptr<const EyeSetup> build_eye_setup(const CameraSpaceScene& cs) {
  auto setup = std::make_shared<EyeSetup>();
  const std::size_t objects = cs.object_count();
  setup->first_face.assign(objects + 1, 0);
  for (std::size_t o = 0; o < objects; ++o)
    setup->first_face[o + 1] = setup->first_face[o] + cs.mesh(o).triangles.size();
  const std::size_t total = setup->first_face.back();
  // Storage an earlier grid gave back (vector_pool.hpp).
  std::vector<CentralGrid::Triangle> items = VectorPool<CentralGrid::Triangle>::instance().take(total);
  items.resize(total);
  constexpr std::uint32_t kLeftOut = ~std::uint32_t{0};
  bool left_out = false;
  for (std::size_t o = 0; o < objects; ++o) {
    const TriangleMesh& mesh = cs.mesh(o);
    const std::size_t first = setup->first_face[o];
    const bool cull = back_faces_never_seen_first(cs, o);
    left_out = left_out || cull;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t f = r.begin(); f < r.end(); ++f) {
            const auto& t = mesh.triangles[f];
            items[first + f] = CentralGrid::Triangle{
                {cs.vertex_estimate(o, t[0]), cs.vertex_estimate(o, t[1]), cs.vertex_estimate(o, t[2])},
                cs.max_error(o),
                cull && certainly_turned_away(cs, o, t) ? kLeftOut : static_cast<std::uint32_t>(first + f)};
          }
        });
  }
  if (left_out)
    items.erase(
        std::remove_if(items.begin(), items.end(), [](const CentralGrid::Triangle& t) { return t.id == kLeftOut; }),
        items.end());
  // Half a cell per triangle around the eye: building the grid is a large
  // part of a small frame, and tracing 1920x1080 is no slower for it
  // (measured on the bunny).
  setup->grid = std::make_unique<CentralGrid>(Vec3d{0, 0, 0}, 0.0, std::move(items), 0.5);
  setup->triangles = LazyTable<EyeTriangle>(total);
  return setup;
}

}  // namespace

bool EyeSetupCache::Key::operator==(const Key& o) const {
  if (!same_bits(view, o.view) || !same_bits(near, o.near) || objects.size() != o.objects.size()) return false;
  for (std::size_t k = 0; k < objects.size(); ++k)
    if (objects[k].mesh != o.objects[k].mesh || !same_bits(objects[k].object_to_world, o.objects[k].object_to_world))
      return false;
  return true;
}

EyeSetupCache::EyeSetupCache(std::size_t capacity) : capacity_(capacity) {}

EyeSetupCache::Counts EyeSetupCache::counts() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return counts_;
}

std::shared_ptr<const EyeSetup> eye_setup(const CameraSpaceScene& cs, EyeSetupCache* cache) {
  if (!cache) return build_eye_setup(cs);
  const Scene& scene = cs.scene();
  EyeSetupCache::Key key{scene.camera.view, scene.camera.frustum.near, {}};
  key.objects.reserve(scene.objects.size());
  for (const SceneObject& o : scene.objects) key.objects.push_back({o.mesh, o.object_to_world});
  {
    const std::lock_guard<std::mutex> lock(cache->mutex_);
    auto& entries = cache->entries_;
    for (std::size_t k = 0; k < entries.size(); ++k)
      if (entries[k].key == key) {
        ++cache->counts_.hits;
        // Most recently used last.
        std::rotate(entries.begin() + static_cast<std::ptrdiff_t>(k),
                    entries.begin() + static_cast<std::ptrdiff_t>(k) + 1, entries.end());
        return entries.back().setup;
      }
  }
  // Uncancelled: the setup stays in the cache for the frame's other lights.
  std::shared_ptr<const EyeSetup> setup;
  run_uncancelled([&] { setup = build_eye_setup(cs); });
  const std::lock_guard<std::mutex> lock(cache->mutex_);
  ++cache->counts_.builds;
  if (cache->capacity_ == 0) return setup;
  auto& entries = cache->entries_;
  for (const EyeSetupCache::Entry& e : entries)
    if (e.key == key) return e.setup;  // another thread stored one meanwhile: keep the first
  if (entries.size() >= cache->capacity_) entries.erase(entries.begin());
  entries.push_back({std::move(key), setup});
  return setup;
}

}  // namespace nearcap
