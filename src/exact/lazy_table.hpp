// A fixed-size table whose entries are computed on first use, from any
// thread (private to src/exact/).
//
// The per-pixel reference keeps per-triangle data (camera-space edge and
// plane vectors, the light's edge vectors) that a frame at a small resolution
// reads for a fraction of the triangles: at 160x120 on the 75k-triangle bunny
// the pixel traces test about 22% of the triangles around the eye and about
// 35% of the lit ones.  Computing an entry when it is first read, instead of
// all of them while setting up, leaves the rest unpaid, and leaves their
// memory untouched (the storage is not initialised, and comes from a pool
// that keeps the blocks of the frames before).
//
// Every entry is a pure function of its index and of inputs that do not
// change while the table lives, so whichever thread computes it, the value is
// the same as an eager build's.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <new>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace nearcap {

// Storage blocks kept after a table is destroyed, for the next frame's table:
// a fresh block of tens of megabytes (the bunny's eye triangles take 17 MB)
// costs a page fault per 4 KB page as the traces first touch it, a reused one
// does not.  At most kMaxBytes are kept; a block is reused for a request of
// at least half its size.
class StoragePool {
 public:
  static constexpr std::size_t kMaxBytes = std::size_t{96} << 20;

  // A block of at least `bytes` bytes, not initialised, handed back when it
  // is destroyed.
  class Block {
   public:
    Block() = default;
    Block(Block&& o) noexcept : data_(std::move(o.data_)), size_(o.size_) { o.size_ = 0; }
    Block& operator=(Block&& o) noexcept {
      if (this != &o) {
        release();
        data_ = std::move(o.data_);
        size_ = o.size_;
        o.size_ = 0;
      }
      return *this;
    }
    Block(const Block&) = delete;
    Block& operator=(const Block&) = delete;
    ~Block() { release(); }
    unsigned char* data() const { return data_.get(); }

   private:
    friend class StoragePool;
    Block(std::unique_ptr<unsigned char[]> data, std::size_t size) : data_(std::move(data)), size_(size) {}
    void release() {
      if (data_) StoragePool::instance().give(std::move(data_), size_);
      size_ = 0;
    }
    std::unique_ptr<unsigned char[]> data_;
    std::size_t size_ = 0;
  };

  // Never destroyed: a table held by a static object may be destroyed after
  // any function-local static.
  static StoragePool& instance() {
    static StoragePool* const pool = new StoragePool;
    return *pool;
  }

  Block take(std::size_t bytes) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      for (std::size_t k = 0; k < kept_.size(); ++k)
        if (kept_[k].second >= bytes && kept_[k].second / 2 <= bytes) {
          auto [data, size] = std::move(kept_[k]);
          kept_.erase(kept_.begin() + static_cast<std::ptrdiff_t>(k));
          kept_bytes_ -= size;
          return Block(std::move(data), size);
        }
    }
    return Block(std::unique_ptr<unsigned char[]>(new unsigned char[bytes]), bytes);
  }

 private:
  void give(std::unique_ptr<unsigned char[]> data, std::size_t size) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (kept_bytes_ + size > kMaxBytes) return;  // freed here
    kept_bytes_ += size;
    kept_.emplace_back(std::move(data), size);
  }
  std::mutex mutex_;
  std::vector<std::pair<std::unique_ptr<unsigned char[]>, std::size_t>> kept_;
  std::size_t kept_bytes_ = 0;
};

template <class T>
class LazyTable {
  static_assert(std::is_trivially_destructible_v<T>, "entries are never destroyed one by one");
  static_assert(alignof(T) <= alignof(std::max_align_t), "new unsigned char[] is aligned for T");

 public:
  LazyTable() = default;
  explicit LazyTable(std::size_t n)
      : size_(n),
        state_(new std::atomic<std::uint8_t>[n]()),
        storage_(StoragePool::instance().take(std::max<std::size_t>(n, 1) * sizeof(Slot))),
        slots_(reinterpret_cast<Slot*>(storage_.data())) {}

  std::size_t size() const { return size_; }

  // Entry i, computed by make() (returning a T) when no thread has yet.  A
  // thread that finds another one computing it waits for it (a few hundred
  // nanoseconds).  When make() throws, the entry stays unset and the
  // exception propagates.
  template <class Make>
  const T& get(std::size_t i, Make&& make) const {
    std::atomic<std::uint8_t>& s = state_[i];
    for (std::uint8_t state = s.load(std::memory_order_acquire); state != kReady;
         state = s.load(std::memory_order_acquire)) {
      if (state == kBuilding) {
        std::this_thread::yield();
        continue;
      }
      std::uint8_t expected = kEmpty;
      if (!s.compare_exchange_strong(expected, kBuilding, std::memory_order_acquire)) continue;
      try {
        ::new (static_cast<void*>(slots_[i].bytes)) T(make());
      } catch (...) {
        s.store(kEmpty, std::memory_order_release);
        throw;
      }
      s.store(kReady, std::memory_order_release);
      break;
    }
    return *std::launder(reinterpret_cast<const T*>(slots_[i].bytes));
  }

  // Whether entry i has been computed (for tests).
  bool computed(std::size_t i) const { return state_[i].load(std::memory_order_acquire) == kReady; }

 private:
  static constexpr std::uint8_t kEmpty = 0, kBuilding = 1, kReady = 2;
  struct alignas(T) Slot {
    unsigned char bytes[sizeof(T)];
  };
  std::size_t size_ = 0;
  std::unique_ptr<std::atomic<std::uint8_t>[]> state_;
  StoragePool::Block storage_;  // not initialised: no entry is read before it is computed
  Slot* slots_ = nullptr;
};

}  // namespace nearcap
