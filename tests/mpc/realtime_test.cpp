// RealtimeScheduling: SCHED_FIFO for the loop's thread and the solver's pool workers, restored
// afterwards; refusals reported, bad priorities rejected; the closed loop's option. (The YAML
// key mpc.realtime_priority: tests/config/mpc_config_test.cpp.)
//
// Where the OS grants SCHED_FIFO (root, CAP_SYS_NICE, RLIMIT_RTPRIO: CI runs as root) the tests
// check the policy each thread actually runs under; where it refuses, they check that the
// refusal is reported and nothing changed. Both branches assert.

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include "core/parallel.hpp"
#include "idto/config/mpc_config.hpp"
#include "idto/idto.hpp"
#include "idto/mpc/closed_loop.hpp"
#include "idto/mpc/realtime.hpp"

namespace idto {
namespace {

using ::testing::HasSubstr;

struct Scheduling {
  int policy{-1};
  int priority{-1};
};

Scheduling ThisThread() {
  Scheduling s;
  sched_param param{};
  if (pthread_getschedparam(pthread_self(), &s.policy, &param) == 0) {
    s.priority = param.sched_priority;
  }
  return s;
}

// Runs phases on 2 threads until the pool's worker (thread identity 1) has run an item, and
// returns the scheduling it ran under in the last such phase. Each item sleeps briefly so that
// the caller cannot finish a phase alone before the worker wakes.
Scheduling WorkerScheduling() {
  for (int attempt = 0; attempt < 50; ++attempt) {
    std::atomic<int> policy{-1}, priority{-1};
    ParallelFor(0, 8, 2, [&](int, int thread) {
      std::this_thread::sleep_for(std::chrono::microseconds(300));
      if (thread == 1) {
        const Scheduling s = ThisThread();
        policy.store(s.policy);
        priority.store(s.priority);
      }
    });
    if (policy.load() >= 0) return Scheduling{policy.load(), priority.load()};
  }
  return Scheduling{};
}

TEST(RealtimeScheduling, RejectsPrioritiesOutsideTheFifoRange) {
  EXPECT_THROW(mpc::RealtimeScheduling(-1), InvalidArgument);
  EXPECT_EQ(mpc::kMaxRealtimePriority, sched_get_priority_max(SCHED_FIFO));
  EXPECT_THROW(mpc::RealtimeScheduling(mpc::kMaxRealtimePriority + 1), InvalidArgument);
  try {
    mpc::RealtimeScheduling scope(1000);
    FAIL() << "no exception";
  } catch (const InvalidArgument& e) {
    EXPECT_THAT(e.what(), HasSubstr("priority"));
    EXPECT_THAT(e.what(), HasSubstr("1000"));
  }
}

TEST(RealtimeScheduling, PriorityZeroChangesNothing) {
  const Scheduling before = ThisThread();
  mpc::RealtimeScheduling scope(0);
  EXPECT_FALSE(scope.active());
  EXPECT_EQ(scope.error(), "");
  EXPECT_EQ(ThisThread().policy, before.policy);
}

TEST(RealtimeScheduling, LoopThreadAndWorkersRunFifoAndReturnAfterwards) {
  const Scheduling before = ThisThread();
  ASSERT_NE(before.policy, SCHED_FIFO) << "the test runner already runs under SCHED_FIFO";
  WorkerScheduling();  // the worker exists and has applied any earlier request
  {
    mpc::RealtimeScheduling scope(7);
    if (!scope.active()) {
      // Refused by the OS: reported, and nothing changed.
      EXPECT_THAT(scope.error(), HasSubstr("SCHED_FIFO priority 7"));
      EXPECT_THAT(scope.error(), HasSubstr("pthread_setschedparam"));
      EXPECT_EQ(ThisThread().policy, before.policy);
      EXPECT_NE(WorkerScheduling().policy, SCHED_FIFO);
      return;
    }
    EXPECT_EQ(scope.error(), "");
    EXPECT_EQ(ThisThread().policy, SCHED_FIFO);
    EXPECT_EQ(ThisThread().priority, 7);
    WorkerScheduling();  // the first phase may still run at the old setting
    const Scheduling worker = WorkerScheduling();
    EXPECT_EQ(worker.policy, SCHED_FIFO);
    EXPECT_EQ(worker.priority, 7);
    EXPECT_EQ(scope.CheckWorkers(), "");
    {
      // Nested: the inner scope's end returns both to the outer one's priority.
      mpc::RealtimeScheduling inner(9);
      ASSERT_TRUE(inner.active());
      WorkerScheduling();
      EXPECT_EQ(WorkerScheduling().priority, 9);
    }
    EXPECT_EQ(ThisThread().priority, 7);
    WorkerScheduling();
    EXPECT_EQ(WorkerScheduling().priority, 7);
  }
  EXPECT_EQ(ThisThread().policy, before.policy);
  EXPECT_EQ(ThisThread().priority, before.priority);
  WorkerScheduling();
  const Scheduling worker = WorkerScheduling();
  EXPECT_EQ(worker.policy, before.policy);
  EXPECT_EQ(worker.priority, before.priority);
}

TEST(RealtimeScheduling, ClosedLoopRejectsABadPriorityAndReportsTheOutcome) {
  const ExampleConfig config = LoadExampleConfig(
      std::string(IDTO_SOURCE_DIR) + "/examples/spinner/spinner.yaml", {IDTO_SOURCE_DIR});
  MpcConfig mpc = ParseMpcConfig(config);
  mpc.closed_loop.duration = 0.05;
  mpc.closed_loop.latency = mpc::LatencyModel::kControlPeriod;
  std::unique_ptr<sim::Plant> plant = sim::MakeBuiltinPlant(config.model, mpc.builtin);
  plant->Reset(config.problem.q_init, config.problem.v_init);
  SolverOptions options = config.solver;
  options.num_threads = 2;
  mpc::Controller controller(config.model, config.problem, options, mpc.controller);
  controller.Initialize(MakeInitialGuess(config), 5);

  mpc.closed_loop.realtime_priority = 100;
  try {
    mpc::RunClosedLoop(config.model, mpc.closed_loop, &controller, plant.get());
    FAIL() << "no exception";
  } catch (const InvalidArgument& e) {
    EXPECT_THAT(e.what(), HasSubstr("options.realtime_priority"));
    EXPECT_THAT(e.what(), HasSubstr("100"));
  }

  const Scheduling before = ThisThread();
  mpc.closed_loop.realtime_priority = 3;
  const mpc::ClosedLoopLog log =
      mpc::RunClosedLoop(config.model, mpc.closed_loop, &controller, plant.get());
  EXPECT_FALSE(log.solve_time.empty());
  EXPECT_EQ(ThisThread().policy, before.policy);  // restored when the run ended
  const mpc::RealtimeScheduling probe(3);         // granted here exactly when it was to the loop
  if (probe.active()) {
    EXPECT_EQ(log.realtime_error, "");
  } else {
    EXPECT_THAT(log.realtime_error, HasSubstr("SCHED_FIFO priority 3"));
  }
}

}  // namespace
}  // namespace idto
