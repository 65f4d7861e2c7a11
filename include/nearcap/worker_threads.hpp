// nearcap/worker_threads.hpp — the process's worker threads (oneTBB's),
// sent away before the real GL is timed.
//
// The emulation's rasterizer and the exact reference run their loops on
// oneTBB's worker threads.  A worker that runs out of work keeps spinning
// for a while before it sleeps, and on a machine with few cores it may spin
// on a core that the GL's own threads (llvmpipe's rasterizer threads) need:
// a frame timed right after such a loop may run beside a spinning worker.
// With the workers released, the same frames' times strayed less from one
// configuration to the next (docs/findings/policy-oracle.md, "Timing after
// the worker threads are released").
//
// A renderer does not run those loops between its frames, so the commands
// that time the real GL (calibrate, evaluate, render --bench) release the
// workers after their CPU work and before their first timed draw; the next
// parallel loop starts them again, outside every timing.
#pragma once

namespace nearcap {

// Joins oneTBB's worker threads (tbb::finalize): every worker has finished
// and exited when it returns true.  Returns false where oneTBB refuses, as
// from inside a parallel loop.  Not to be called while another thread runs
// parallel work.
bool release_worker_threads();

}  // namespace nearcap
