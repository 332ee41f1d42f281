#pragma once

/// @file
/// A deterministic parallel-for over independent indices, run on a persistent thread pool.
///
/// Private to the library (not installed): callers in src/ include it as "core/parallel.hpp".
///
/// **Scheduling.** `ParallelFor(begin, end, num_threads, body)` splits [begin, end) into chunks
/// (about four per participant) and publishes them to the process-wide pool
/// (src/core/thread_pool.cpp) as one home range of consecutive chunks per participant. The
/// calling thread and up to `num_threads - 1` worker threads each take chunks from the front of
/// their own range, then steal from the back of the others' until none is left; then the caller
/// waits only for chunks other threads have already claimed. A worker that wakes up late, or is
/// descheduled by the operating system, therefore holds the phase up by at most the chunk it is
/// running: the caller does all unclaimed work itself. Without stealing, index i runs on the
/// same thread in every phase over the same range with the same `num_threads`, so its data
/// stays in that thread's cache (unless the OS migrates the thread).
/// Idle threads spin for a few microseconds, yield for up to 250 µs (the serial parts of a
/// solver iteration between two phases), then sleep on a condition variable.
///
/// **Thread identities.** `body(i, thread)` receives `thread` in [0, num_threads): 0 for the
/// calling thread, k for the pool's k-th worker. Each identity is used by at most one thread at a
/// time, so it can index per-thread scratch without locks.
///
/// **Determinism.** Which thread runs which index depends on timing. Each index must write only
/// its own outputs (per-thread scratch may hold anything between indices); reductions are done
/// afterwards in index order by the caller, so results are bitwise identical for any thread count
/// and any interleaving.
///
/// **Exceptions.** An exception thrown by `body` does not terminate the process: it is captured
/// and rethrown on the calling thread once every running index has returned. When several
/// indices throw, the one rethrown is that of the *smallest index* (deterministic when the
/// indices that throw are); indices above an index known to have thrown may be skipped, every
/// index below it runs.
///
/// **One pool per process.** All callers share one pool, created on first use and joined at exit;
/// its workers are started lazily, as many as the largest `num_threads` requested minus one.
/// One phase runs on it at a time: a `ParallelFor` that finds the pool busy (called from a work
/// item, i.e. nested, or from another thread while a phase runs, e.g. two optimizers on two
/// threads) runs its indices serially on its own thread with `thread` = 0. That never deadlocks
/// and keeps results identical; it only loses the parallelism of the second caller.

#include <chrono>
#include <string>

#include "idto/core/errors.hpp"

namespace idto {

/// Largest accepted `num_threads` (SolverOptions::kMaxNumThreads is the same number).
inline constexpr int kMaxParallelThreads = 256;

namespace internal {

/// Calls item `i` of a phase with thread identity `thread`.
using ItemFunction = void (*)(const void* context, int i, int thread);

/// Runs `fn(context, i, thread)` for i in [begin, end) on the pool with up to `num_threads`
/// participants (see the file comment). Requires end - begin >= 2 and
/// 2 <= num_threads <= kMaxParallelThreads. Rethrows the exception of the smallest index that
/// threw.
void RunOnThreadPool(int begin, int end, int num_threads, ItemFunction fn, const void* context);

/// Testing hook: every worker waits this long after being woken for a phase before it takes
/// work (0: no delay), as a descheduled thread would. The wait ends early when the pool shuts
/// down.
void SetWorkerWakeDelayForTesting(int milliseconds);

/// Testing hook: the number of worker threads the pool has started.
int NumThreadPoolWorkers();
/// How long an idle worker keeps yielding (awake, ready for the next phase) before it sleeps on
/// a condition variable: 250 µs by default, enough for the serial gaps inside a solver
/// iteration. A paced control loop sets it above its period to keep the workers awake between
/// re-plans (mpc::ClosedLoopOptions::keep_workers_awake). Returns the previous value; throws
/// InvalidArgument for a negative time. Takes effect from each worker's next wait.
std::chrono::microseconds SetThreadPoolIdleYield(std::chrono::microseconds yield_time);
/// The idle workers' current yield time (SetThreadPoolIdleYield).
std::chrono::microseconds ThreadPoolIdleYield();
/// Asks every pool worker, present and future, to run under the scheduling `policy`
/// (SCHED_OTHER, SCHED_FIFO or SCHED_RR) at `priority` (0 for SCHED_OTHER): each applies it with
/// pthread_setschedparam when it next wakes for a phase, so the first phase after the call may
/// still run at the previous setting. Process-wide, last call wins (mpc::RealtimeScheduling
/// keeps the calling thread and the workers alike). A worker that the OS refuses keeps its
/// scheduling and records the error for TakeThreadPoolSchedulingError. Throws InvalidArgument
/// for a negative policy or priority.
void SetThreadPoolScheduling(int policy, int priority);
/// The errno of the latest worker that could not apply a SetThreadPoolScheduling request since
/// the last call (0: none), and resets it.
int TakeThreadPoolSchedulingError();

}  // namespace internal

/// Calls `body(i, thread)` for every i in [begin, end) exactly once, on up to `num_threads`
/// threads of the process-wide pool (the calling thread included). `thread` in
/// [0, num_threads) is unique among concurrently running calls. Throws InvalidArgument when
/// `num_threads` is not in [1, kMaxParallelThreads]; rethrows the exception of the smallest
/// index whose call threw, on the calling thread, after every running call has returned.
template <typename Body>
void ParallelFor(int begin, int end, int num_threads, const Body& body) {
  if (num_threads < 1 || num_threads > kMaxParallelThreads) {
    ThrowInvalidArgument("ParallelFor", "num_threads", std::to_string(num_threads),
                         "in [1, " + std::to_string(kMaxParallelThreads) + "]");
  }
  if (num_threads == 1 || end - begin <= 1) {
    for (int i = begin; i < end; ++i) body(i, 0);
    return;
  }
  internal::RunOnThreadPool(
      begin, end, num_threads,
      [](const void* context, int i, int thread) {
        (*static_cast<const Body*>(context))(i, thread);
      },
      &body);
}

}  // namespace idto
