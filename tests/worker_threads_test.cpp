// tests/worker_threads_test.cpp — release_worker_threads
// (include/nearcap/worker_threads.hpp): after it, no oneTBB worker thread
// is left in the process, and a parallel loop still runs afterwards.
#include "nearcap/worker_threads.hpp"

#include <gtest/gtest.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <set>
#include <thread>

namespace nearcap {
namespace {

// The threads of this process now (Linux: /proc/self/task).
std::size_t thread_count() {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) ++n;
  return n;
}

// A parallel loop long enough that every worker joins it: it waits until
// as many threads as the machine's concurrency have run a part, or a
// second has passed.  Returns how many threads ran parts.
std::size_t run_on_every_worker() {
  const int want = tbb::info::default_concurrency();
  std::atomic<int> seen{0};
  std::mutex m;
  std::set<std::thread::id> ids;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  tbb::parallel_for(0, 64 * want, [&](int) {
    {
      std::lock_guard<std::mutex> lock(m);
      if (ids.insert(std::this_thread::get_id()).second) ++seen;
    }
    while (seen.load() < want && std::chrono::steady_clock::now() < until) std::this_thread::yield();
  });
  return ids.size();
}

TEST(WorkerThreads, NoWorkerIsLeftOnceReleased) {
  if (tbb::info::default_concurrency() < 2) GTEST_SKIP() << "one core: oneTBB starts no worker";
  ASSERT_TRUE(release_worker_threads());
  const std::size_t before = thread_count();
  EXPECT_GE(run_on_every_worker(), 2u);
  EXPECT_GT(thread_count(), before) << "the loop ran on workers, which are threads of the process";
  ASSERT_TRUE(release_worker_threads());
  EXPECT_EQ(thread_count(), before) << "every worker has exited";
  // The next loop starts them again.
  EXPECT_GE(run_on_every_worker(), 2u);
  ASSERT_TRUE(release_worker_threads());
  EXPECT_EQ(thread_count(), before);
}

TEST(WorkerThreads, AreNotReleasedFromInsideAParallelLoop) {
  if (tbb::info::default_concurrency() < 2) GTEST_SKIP() << "one core: oneTBB starts no worker";
  ASSERT_TRUE(release_worker_threads());
  const std::size_t before = thread_count();
  std::atomic<int> released{0}, tried{0};
  tbb::parallel_for(0, 4, [&](int) {
    ++tried;
    released += release_worker_threads() ? 1 : 0;
  });
  EXPECT_EQ(tried.load(), 4);
  EXPECT_EQ(released.load(), 0);
  EXPECT_TRUE(release_worker_threads());
  EXPECT_EQ(thread_count(), before);
}

}  // namespace
}  // namespace nearcap
