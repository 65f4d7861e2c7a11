// nearcap/worker_threads.cpp — see include/nearcap/worker_threads.hpp.
#include "nearcap/worker_threads.hpp"

#include <tbb/global_control.h>

#include <new>

namespace nearcap {

bool release_worker_threads() {
  tbb::task_scheduler_handle handle{tbb::attach{}};
  return tbb::finalize(handle, std::nothrow);
}

}  // namespace nearcap
