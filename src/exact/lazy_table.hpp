// A fixed-size table whose entries are computed on first use, from any
// thread (private to src/exact/).
//
// The per-pixel reference keeps per-triangle data (camera-space edge and
// plane vectors, the light's edge vectors) that a frame at a small resolution
// reads for a fraction of the triangles: at 160x120 on the 75k-triangle bunny
// the pixel traces test about 22% of the triangles around the eye and about
// 35% of the lit ones.  Computing an entry when it is first read, instead of
// all of them while setting up, leaves the rest unpaid, and leaves their
// memory untouched (the storage is not initialised).
//
// Every entry is a pure function of its index and of inputs that do not
// change while the table lives, so whichever thread computes it, the value is
// the same as an eager build's.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <thread>
#include <type_traits>

namespace nearcap {

template <class T>
class LazyTable {
  static_assert(std::is_trivially_destructible_v<T>, "entries are never destroyed one by one");

 public:
  LazyTable() = default;
  explicit LazyTable(std::size_t n) : size_(n), state_(new std::atomic<std::uint8_t>[n]()), slots_(new Slot[n]) {}

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
  std::unique_ptr<Slot[]> slots_;  // default-initialised: no entry is written before it is computed
};

}  // namespace nearcap
