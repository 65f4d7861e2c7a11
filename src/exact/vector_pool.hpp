// Vectors whose storage is kept, with its capacity, from one grid build to
// the next (private to src/exact/).
//
// A grid around the eye (central_grid.hpp) is rebuilt whenever the camera
// moves, and a grid around the light whenever the light moves.  Each build
// fills vectors of megabytes (the bunny's 75k triangles: 6.6 MB of triangle
// copies, as much of per-face placements, a few MB of cell entries).  Freshly
// allocated, such a vector comes from mmap and costs the kernel a page fault
// per 4 KB page as the build first writes it, and freeing it returns the pages:
// on two threads that kernel work, serial, is most of an eye side's setup in
// fresh storage (docs/findings/exact-speed.md).  A vector taken from a VectorPool instead
// has the capacity of one an earlier build gave back, its pages already
// mapped.
//
// A vector taken is always empty (size 0), so what a build writes into it is
// what it would write into a fresh one: reuse changes no value, only where
// the values live.  Pools are per element type; together they keep at most
// kMaxKeptBytes (each pool at most kMaxVectors), a pool dropping its smallest
// vectors first.  The bound matters beside the float emulation of a sweep:
// memory a pool keeps is memory malloc cannot hand to the emulation's own
// per-frame vectors, so keeping more raises the peak resident memory.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <mutex>
#include <type_traits>
#include <utility>
#include <vector>

namespace nearcap {

// Whether pools keep and hand out storage (true by default).  Switched off,
// take() returns a new vector and give() frees it: the storage a build sees
// is fresh, for tests that compare a reusing build with a fresh one.
inline std::atomic<bool>& vector_reuse_enabled() {
  static std::atomic<bool> enabled{true};
  return enabled;
}

// The bytes all pools keep together.
inline std::atomic<std::size_t>& vector_pools_kept_bytes() {
  static std::atomic<std::size_t> bytes{0};
  return bytes;
}

// Every pool's release(), for release_kept_vectors().
struct VectorPoolRegistry {
  std::mutex mutex;
  std::vector<void (*)()> release;
  static VectorPoolRegistry& instance() {
    static VectorPoolRegistry* const registry = new VectorPoolRegistry;  // never destroyed, as the pools
    return *registry;
  }
};

// Frees what every pool keeps (a test's fresh start).
inline void release_kept_vectors() {
  VectorPoolRegistry& r = VectorPoolRegistry::instance();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (void (*release)() : r.release) release();
}

template <class T>
class VectorPool {
  static_assert(std::is_trivially_destructible_v<T>, "clearing a kept vector must cost nothing");

 public:
  // About twice what the bunny's eye side (75k triangles) gives back.
  static constexpr std::size_t kMaxKeptBytes = std::size_t{64} << 20;
  static constexpr std::size_t kMaxVectors = 8;

  // Never destroyed: a grid held by a static object may be destroyed after
  // any function-local static.
  static VectorPool& instance() {
    static VectorPool* const pool = [] {
      VectorPoolRegistry& r = VectorPoolRegistry::instance();
      const std::lock_guard<std::mutex> lock(r.mutex);
      r.release.push_back([] { VectorPool<T>::instance().release(); });
      return new VectorPool;
    }();
    return *pool;
  }

  // Frees every vector kept.
  void release() {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const std::vector<T>& v : kept_) vector_pools_kept_bytes() -= v.capacity() * sizeof(T);
    kept_.clear();
  }

  // An empty vector with capacity for at least `n` elements: the smallest
  // kept one that holds n, else a new one.
  std::vector<T> take(std::size_t n) {
    std::vector<T> out;
    if (vector_reuse_enabled().load(std::memory_order_relaxed)) {
      const std::lock_guard<std::mutex> lock(mutex_);
      std::size_t best = kept_.size();
      for (std::size_t k = 0; k < kept_.size(); ++k)
        if (kept_[k].capacity() >= n && (best == kept_.size() || kept_[k].capacity() < kept_[best].capacity()))
          best = k;
      if (best < kept_.size()) {
        out = std::move(kept_[best]);
        kept_.erase(kept_.begin() + static_cast<std::ptrdiff_t>(best));
        vector_pools_kept_bytes() -= out.capacity() * sizeof(T);
      }
    }
    out.clear();
    out.reserve(n);
    return out;
  }

  // Keeps v's storage for a later take() (v is left empty).
  void give(std::vector<T>& v) {
    std::vector<T> kept = std::move(v);
    v = std::vector<T>();
    if (kept.capacity() == 0 || !vector_reuse_enabled().load(std::memory_order_relaxed)) return;
    kept.clear();
    const std::lock_guard<std::mutex> lock(mutex_);
    vector_pools_kept_bytes() += kept.capacity() * sizeof(T);
    kept_.push_back(std::move(kept));
    while (!kept_.empty() && (vector_pools_kept_bytes() > kMaxKeptBytes || kept_.size() > kMaxVectors)) {
      const auto smallest = std::min_element(kept_.begin(), kept_.end(),
                                             [](const auto& a, const auto& b) { return a.capacity() < b.capacity(); });
      vector_pools_kept_bytes() -= smallest->capacity() * sizeof(T);
      kept_.erase(smallest);  // freed here
    }
  }

 private:
  std::mutex mutex_;
  std::vector<std::vector<T>> kept_;
};

// A vector from VectorPool<T>, given back when this goes out of scope: the
// temporaries of a build.
template <class T>
class PooledVector {
 public:
  explicit PooledVector(std::size_t reserve = 0) : v_(VectorPool<T>::instance().take(reserve)) {}
  ~PooledVector() { VectorPool<T>::instance().give(v_); }
  PooledVector(const PooledVector&) = delete;
  PooledVector& operator=(const PooledVector&) = delete;
  std::vector<T>& operator*() { return v_; }
  const std::vector<T>& operator*() const { return v_; }
  std::vector<T>* operator->() { return &v_; }
  const std::vector<T>* operator->() const { return &v_; }

 private:
  std::vector<T> v_;
};

}  // namespace nearcap
