// The heap's settings for the program (see heap_settings.hpp).
#include "heap_settings.hpp"

#include <cstdlib>  // defines __GLIBC__ under glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace nearcap::cli {

void keep_freed_memory() {
#if defined(__GLIBC__)
  // glibc's largest mmap threshold on 64-bit systems (DEFAULT_MMAP_THRESHOLD_MAX:
  // mallopt refuses more); a fixed threshold also turns off its dynamic raising.
  constexpr int kMmapThreshold = 32 * 1024 * 1024;
  mallopt(M_MMAP_THRESHOLD, kMmapThreshold);
  // Free memory at the heap's top is never given back (the largest int).
  mallopt(M_TRIM_THRESHOLD, 0x7fffffff);
#endif
}

}  // namespace nearcap::cli
