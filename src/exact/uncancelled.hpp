// exact/uncancelled.hpp — work that fills a cache, run where a cancellation
// of the caller's tasks cannot cut it short (private to src/exact/).
//
// When a TBB task throws, TBB cancels the task group it belongs to and every
// group nested in it: a parallel loop running there stops taking iterations
// and returns as if it were done.  A structure built for a cache that later
// frames read (a light setup, an eye setup) must not be left half built that
// way by an exception elsewhere in the frame (tests/light_setup_test.cpp and
// tests/eye_setup_test.cpp build one in a cancelled group).  Light setups
// and a grid's faces are built through tbb::collaborative_call_once, whose
// function runs in a context of its own (task_arena::execute), which a
// cancellation of the caller's group does not reach.
#pragma once

#include <tbb/task_group.h>

#include <utility>

namespace nearcap {

// Runs `f`, and the parallel loops it starts, in a task group context of its
// own (isolated from the caller's), waiting for it; an exception `f` throws
// propagates to the caller.
template <class F>
void run_uncancelled(F&& f) {
  tbb::task_group_context context(tbb::task_group_context::isolated);
  tbb::task_group group(context);
  group.run_and_wait(std::forward<F>(f));
}

}  // namespace nearcap
