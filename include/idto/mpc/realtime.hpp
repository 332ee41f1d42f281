#pragma once

/// @file
/// Real-time scheduling for a control loop: the loop's thread and the solver's worker threads
/// under SCHED_FIFO, so that another process computing on the same cores cannot delay a re-plan.
///
/// A robot's computer runs other processes (drivers, estimation, perception). Under the normal
/// time-sharing policy a process that never sleeps gets its share of the cores whenever it wants
/// it, and a 2-thread re-plan beside it runs at about 1-thread speed (docs/benchmarks.md,
/// "Issue 19"). SCHED_FIFO threads run ahead of every normal thread. Linux grants it to root, to
/// a process with CAP_SYS_NICE, or up to the process's RLIMIT_RTPRIO (`ulimit -r`); elsewhere
/// the request is refused and reported (error()), and the loop runs at its normal priority.
/// Construct it before the controller's first solve (Controller::Initialize): the solver's
/// worker threads are started by that solve and then start under SCHED_FIFO. Workers switched
/// later, when they next wake, were measured less steady: beside a busy process, 3 of 8
/// free-running quadruped loops had a re-plan p95 above 1.5x the quiet one, against 1 of 16
/// with the scope in place from the start (docs/benchmarks.md, session 22).
/// A SCHED_FIFO thread that computes without a pause holds its core until the kernel's
/// real-time throttling (by default 5 % of each second left to normal threads): give it to a
/// loop that waits for its control ticks (ClosedLoopOptions::real_time, or the caller's own
/// timer).

#include <string>

namespace idto::mpc {

/// The largest SCHED_FIFO priority on Linux (sched_get_priority_max(SCHED_FIFO)): the upper
/// bound of every real-time priority option (ClosedLoopOptions, YAML, idto-run).
inline constexpr int kMaxRealtimePriority = 99;

/// For its lifetime, the constructing thread and the solver's worker threads run under
/// SCHED_FIFO at `priority`; the destructor returns the constructing thread to its previous
/// scheduling and asks the workers to take that same scheduling. Workers apply a change when
/// they next wake for a parallel phase. The workers' setting is process-wide: with several
/// scopes alive on different threads, the one constructed or destroyed last decides it.
/// Not copyable or movable; destroy it on the thread that constructed it.
class RealtimeScheduling {
 public:
  /// priority: 0 (nothing is changed: the scope is inactive) or a SCHED_FIFO priority in
  /// [1, kMaxRealtimePriority]. Throws InvalidArgument outside that range. A refusal by the OS does
  /// not throw: active() is false and error() says why.
  explicit RealtimeScheduling(int priority);
  ~RealtimeScheduling();
  RealtimeScheduling(const RealtimeScheduling&) = delete;
  RealtimeScheduling& operator=(const RealtimeScheduling&) = delete;

  /// True when the constructing thread runs under SCHED_FIFO through this scope.
  bool active() const { return active_; }
  /// Why the requested scheduling was not (fully) applied, "" when it was or when priority is 0.
  /// Refusals by workers are collected by CheckWorkers().
  const std::string& error() const { return error_; }
  /// Adds to error() any refusal a worker met since the scope began (call it after the solver
  /// has run at least one parallel phase); returns error().
  const std::string& CheckWorkers();

 private:
  int priority_{0};
  bool active_{false};
  int old_policy_{0};
  int old_priority_{0};
  std::string error_;
};

}  // namespace idto::mpc
