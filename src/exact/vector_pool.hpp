// Vectors whose storage is kept, with its capacity, from one grid build to
// the next (private to src/exact/).
//
// A grid around the eye (central_grid.hpp) is rebuilt whenever the camera
// moves, and a grid around the light whenever the light moves.  Each build
// fills vectors of megabytes (the bunny's 75k triangles: 6.6 MB of triangle
// copies, as much of per-face placements, a few MB of cell entries).  Freshly
// allocated, such a vector comes from mmap and costs the kernel a page fault
// per 4 KB page as the build first writes it, and freeing it returns the pages:
// on two threads that kernel work, serial, was most of an eye side's setup
// (docs/findings/exact-speed.md).  A vector taken from a VectorPool instead
// has the capacity of one an earlier build gave back, its pages already
// mapped.
//
// A vector taken is always empty (size 0), so what a build writes into it is
// what it would write into a fresh one: reuse changes no value, only where
// the values live.  Pools are per element type; each keeps at most kMaxBytes
// and kMaxVectors, dropping its smallest vectors first.
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

template <class T>
class VectorPool {
  static_assert(std::is_trivially_destructible_v<T>, "clearing a kept vector must cost nothing");

 public:
  static constexpr std::size_t kMaxBytes = std::size_t{128} << 20;
  static constexpr std::size_t kMaxVectors = 16;

  // Never destroyed: a grid held by a static object may be destroyed after
  // any function-local static.
  static VectorPool& instance() {
    static VectorPool* const pool = new VectorPool;
    return *pool;
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
        kept_bytes_ -= out.capacity() * sizeof(T);
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
    kept_bytes_ += kept.capacity() * sizeof(T);
    kept_.push_back(std::move(kept));
    while (!kept_.empty() && (kept_bytes_ > kMaxBytes || kept_.size() > kMaxVectors)) {
      const auto smallest = std::min_element(kept_.begin(), kept_.end(),
                                             [](const auto& a, const auto& b) { return a.capacity() < b.capacity(); });
      kept_bytes_ -= smallest->capacity() * sizeof(T);
      kept_.erase(smallest);  // freed here
    }
  }

 private:
  std::mutex mutex_;
  std::vector<std::vector<T>> kept_;
  std::size_t kept_bytes_ = 0;
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
