// The camera-independent light side of the exact reference (see light_setup.hpp).
#include "nearcap/exact/light_setup.hpp"

#include <tbb/blocked_range.h>
#include <tbb/collaborative_call_once.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "nearcap/check.hpp"
#include "vector_pool.hpp"

namespace nearcap {
namespace {

constexpr double kSlack = 1.0 + 0x1p-40;  // covers the rounding of the bounds' own arithmetic

bool same_point(const Vec3d& a, const Vec3d& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// Moves entry k to the back (most recently used) and returns it.
template <class T>
T& touch(std::vector<T>& entries, std::size_t k) {
  std::rotate(entries.begin() + static_cast<std::ptrdiff_t>(k), entries.begin() + static_cast<std::ptrdiff_t>(k) + 1,
              entries.end());
  return entries.back();
}

template <class T>
void store(std::vector<T>& entries, T entry, std::size_t capacity) {
  if (capacity == 0) return;
  if (entries.size() >= capacity) entries.erase(entries.begin());
  entries.push_back(std::move(entry));
}

// World-space estimates of object o's vertices with one certified bound per
// coordinate: object_to_world has exact double entries, so each coordinate is
// a dot product of length 4 in double, within gamma_4 max|M| (|v|_1 + 1).
struct WorldVertices {
  std::vector<Vec3d> position;
  double error = 0;
};
WorldVertices world_vertices(const SceneObject& object) {
  const auto& m = object.object_to_world.rows;
  const auto& positions = object.mesh->positions;
  double m_max = 0;
  for (const auto& row : m)
    for (double x : row) m_max = std::fmax(m_max, std::fabs(x));
  WorldVertices out;
  out.position.resize(positions.size());
  double v1 = 1.0;
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const Vec3d& p = positions[v];
    out.position[v] = object.object_to_world.apply(p);
    v1 = std::max(v1, std::fabs(p.x) + std::fabs(p.y) + std::fabs(p.z) + 1.0);
  }
  constexpr double kGamma4 = 4 * 0x1p-53 / (1 - 4 * 0x1p-53);
  out.error = kGamma4 * m_max * v1 * kSlack;
  return out;
}

// The grid of the lit triangles around the light's world position.
std::unique_ptr<CentralGrid> world_light_grid(const Scene& scene, std::size_t light,
                                              const std::vector<std::uint32_t>& lit,
                                              const std::vector<std::size_t>& first_face) {
  std::vector<WorldVertices> world(scene.objects.size());
  for (std::size_t o = 0; o < scene.objects.size(); ++o)
    if (scene.objects[o].occluder) world[o] = world_vertices(scene.objects[o]);
  std::vector<CentralGrid::Triangle> items = VectorPool<CentralGrid::Triangle>::instance().take(lit.size());
  items.resize(lit.size());
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, lit.size(), 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t o = 0;
        for (std::size_t m = r.begin(); m < r.end(); ++m) {
          while (lit[m] >= first_face[o + 1]) ++o;
          const auto& t = scene.objects[o].mesh->triangles[lit[m] - first_face[o]];
          const WorldVertices& w = world[o];
          items[m] = CentralGrid::Triangle{
              {w.position[t[0]], w.position[t[1]], w.position[t[2]]}, w.error, static_cast<std::uint32_t>(m)};
        }
      });
  return std::make_unique<CentralGrid>(scene.lights[light].position, 0.0, std::move(items), 1.0);
}

}  // namespace

WorldDirections::WorldDirections(const Affine3d& view) {
  const auto& v = view.rows;
  // A = V^-1 by cofactors, in double.
  const double c00 = v[1][1] * v[2][2] - v[1][2] * v[2][1], c01 = v[1][2] * v[2][0] - v[1][0] * v[2][2],
               c02 = v[1][0] * v[2][1] - v[1][1] * v[2][0];
  const double det = v[0][0] * c00 + v[0][1] * c01 + v[0][2] * c02;
  if (!(std::fabs(det) > 0) || !std::isfinite(det)) return;
  const double inv = 1.0 / det;
  a_ = {{{c00 * inv, (v[0][2] * v[2][1] - v[0][1] * v[2][2]) * inv, (v[0][1] * v[1][2] - v[0][2] * v[1][1]) * inv},
         {c01 * inv, (v[0][0] * v[2][2] - v[0][2] * v[2][0]) * inv, (v[0][2] * v[1][0] - v[0][0] * v[1][2]) * inv},
         {c02 * inv, (v[0][1] * v[2][0] - v[0][0] * v[2][1]) * inv, (v[0][0] * v[1][1] - v[0][1] * v[1][0]) * inv}}};
  // d >= ||I - A V||, evaluated with certified bounds.
  double d = 0;
  for (int i = 0; i < 3; ++i) {
    double row = 0, a_row = 0;
    for (int j = 0; j < 3; ++j) {
      BoundedDouble e(i == j ? 1.0 : 0.0);
      for (int k = 0; k < 3; ++k) e -= BoundedDouble(a_[i][k]) * BoundedDouble(v[k][j]);
      row += (std::fabs(e.v) + e.e) * kSlack;
      a_row += std::fabs(a_[i][j]);
    }
    d = std::fmax(d, row * kSlack);
    a_norm_ = std::fmax(a_norm_, a_row * kSlack);
  }
  if (!(d < 0.5) || !std::isfinite(a_norm_)) return;
  inverse_norm_ = a_norm_ / (1.0 - d) * kSlack * kSlack;
  difference_norm_ = d * a_norm_ / (1.0 - d) * kSlack * kSlack;
  certified_ = true;
}

Vec3d WorldDirections::apply(const Vec3d& w, double w_error, double& world_error) const {
  // V^-1 W - fl(A w) = V^-1 (W - w) + (V^-1 - A) w + (A w - fl(A w)).
  const Vec3d y{a_[0][0] * w.x + a_[0][1] * w.y + a_[0][2] * w.z, a_[1][0] * w.x + a_[1][1] * w.y + a_[1][2] * w.z,
                a_[2][0] * w.x + a_[2][1] * w.y + a_[2][2] * w.z};
  const double w_max = std::max({std::fabs(w.x), std::fabs(w.y), std::fabs(w.z)});
  constexpr double kGamma3 = 3 * 0x1p-53 / (1 - 3 * 0x1p-53);
  world_error = certified_ ? (inverse_norm_ * w_error + (difference_norm_ + kGamma3 * a_norm_) * w_max) * kSlack +
                                 std::numeric_limits<double>::denorm_min()
                           : std::numeric_limits<double>::infinity();
  if (!std::isfinite(world_error)) world_error = std::numeric_limits<double>::infinity();
  return y;
}

bool LightSetupCache::ObjectKey::operator==(const ObjectKey& o) const {
  if (mesh != o.mesh || occluder != o.occluder) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      if (!(object_to_world.rows[i][j] == o.object_to_world.rows[i][j])) return false;
  return true;
}

LightSetupCache::LightSetupCache(std::size_t setups, std::size_t facings)
    : setup_capacity_(setups), facing_capacity_(facings) {}

LightSetupCache::Counts LightSetupCache::counts() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return counts_;
}

struct LightSetupCache::PendingSetup {
  tbb::collaborative_once_flag built;
  std::shared_ptr<const LightSetup> setup;  // set once `built` has run
};

std::shared_ptr<const LightSetup> light_setup(const CameraSpaceScene& cs, std::size_t light, LightSetupCache* cache) {
  const Scene& scene = cs.scene();
  const Vec3d& l = scene.lights[light].position;
  std::vector<LightSetupCache::ObjectKey> keys;
  keys.reserve(scene.objects.size());
  for (const SceneObject& o : scene.objects) keys.push_back({o.mesh, o.object_to_world, o.occluder});
  if (!cache) return LightSetupCache::build(cs, light, keys, nullptr);
  std::shared_ptr<LightSetupCache::PendingSetup> pending;
  {
    const std::lock_guard<std::mutex> lock(cache->mutex_);
    for (std::size_t k = 0; k < cache->setups_.size() && !pending; ++k) {
      const LightSetupCache::SetupEntry& e = cache->setups_[k];
      if (same_point(e.light, l) && e.objects == keys) {
        ++cache->counts_.setup_hits;
        pending = touch(cache->setups_, k).pending;
      }
    }
    if (!pending) {
      pending = std::make_shared<LightSetupCache::PendingSetup>();
      store(cache->setups_, LightSetupCache::SetupEntry{keys, l, pending}, cache->setup_capacity_);
    }
  }
  // The first caller builds; a caller that arrives meanwhile works on the
  // same build's parallel loops and returns when it is done.  The build
  // runs in a context of collaborative_call_once's own, which a
  // cancellation of the caller's tasks does not reach: the setup stays
  // whole in the cache for later frames (uncancelled.hpp).
  tbb::collaborative_call_once(pending->built, [&] {
    pending->setup = LightSetupCache::build(cs, light, keys, cache);
    const std::lock_guard<std::mutex> lock(cache->mutex_);
    ++cache->counts_.setup_builds;
  });
  NEARCAP_CHECK(pending->setup != nullptr);
  return pending->setup;
}

std::shared_ptr<const LightSetup> LightSetupCache::build(const CameraSpaceScene& cs, std::size_t light,
                                                         const std::vector<ObjectKey>& keys, LightSetupCache* cache) {
  const Scene& scene = cs.scene();
  const Vec3d& l = scene.lights[light].position;
  auto setup = std::make_shared<LightSetup>();
  const std::size_t objects = scene.objects.size();
  setup->facing.resize(objects);
  std::vector<std::size_t> first_face(objects + 1, 0);
  for (std::size_t o = 0; o < objects; ++o) first_face[o + 1] = first_face[o] + scene.objects[o].mesh->triangles.size();
  for (std::size_t o = 0; o < objects; ++o) {
    if (!scene.objects[o].occluder) continue;
    if (cache) {
      const std::lock_guard<std::mutex> lock(cache->mutex_);
      for (std::size_t k = 0; k < cache->facings_.size(); ++k) {
        const LightSetupCache::FacingEntry& e = cache->facings_[k];
        if (same_point(e.light, l) && e.object == keys[o]) {
          ++cache->counts_.facing_hits;
          setup->facing[o] = touch(cache->facings_, k).facing;
          break;
        }
      }
    }
    if (setup->facing[o]) continue;
    setup->facing[o] = std::make_shared<const std::vector<Facing>>(light_facing(cs, o, light, nullptr));
    if (cache) {
      const std::lock_guard<std::mutex> lock(cache->mutex_);
      ++cache->counts_.facing_builds;
      store(cache->facings_, LightSetupCache::FacingEntry{keys[o], l, setup->facing[o]}, cache->facing_capacity_);
    }
  }
  for (std::size_t o = 0; o < objects; ++o)
    if (setup->facing[o]) {
      const std::vector<Facing>& facing = *setup->facing[o];
      for (std::size_t f = 0; f < facing.size(); ++f)
        if (facing[f] == Facing::Front) setup->lit.push_back(static_cast<std::uint32_t>(first_face[o] + f));
    }
  setup->grid = world_light_grid(scene, light, setup->lit, first_face);
  // Segments from the light go every way: every face is built here, with the
  // rest of the light side.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  setup->grid->build_faces_meeting({-kInf, -kInf, -kInf}, {kInf, kInf, kInf});
  return setup;
}

}  // namespace nearcap
