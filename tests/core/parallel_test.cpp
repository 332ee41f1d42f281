// ParallelFor on the library's thread pool (src/core/parallel.hpp): coverage, thread identities,
// exceptions, concurrent and nested callers, and a phase that must not wait for late workers.

#include "core/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace idto {
namespace {

using ::testing::HasSubstr;
using Clock = std::chrono::steady_clock;

// Busy work of about `us` microseconds (keeps an item running while others start).
void SpinFor(int us) {
  const auto until = Clock::now() + std::chrono::microseconds(us);
  while (Clock::now() < until) {
  }
}

// Runs ParallelFor(begin, end, threads) and checks that every index ran exactly once, with a
// thread identity in [0, threads) that no other running item held at the same time.
void ExpectEachIndexOnce(int begin, int end, int threads, int item_us = 0) {
  const int n = std::max(0, end - begin);
  std::unique_ptr<std::atomic<int>[]> hits(new std::atomic<int>[static_cast<size_t>(n)]);
  std::unique_ptr<std::atomic<int>[]> in_use(new std::atomic<int>[static_cast<size_t>(threads)]);
  for (int i = 0; i < n; ++i) hits[i] = 0;
  for (int t = 0; t < threads; ++t) in_use[t] = 0;
  std::atomic<int> bad_thread{0}, shared_thread{0};
  ParallelFor(begin, end, threads, [&](int i, int thread) {
    if (thread < 0 || thread >= threads) {
      ++bad_thread;
      return;
    }
    if (in_use[thread].exchange(1) != 0) ++shared_thread;
    hits[i - begin].fetch_add(1);
    if (item_us > 0) SpinFor(item_us);
    in_use[thread].store(0);
  });
  const std::string where = "[" + std::to_string(begin) + ", " + std::to_string(end) +
                            "), threads " + std::to_string(threads);
  EXPECT_EQ(bad_thread.load(), 0) << where;
  EXPECT_EQ(shared_thread.load(), 0) << where;
  int wrong = 0;
  for (int i = 0; i < n; ++i) wrong += hits[i].load() != 1;
  EXPECT_EQ(wrong, 0) << where;
}

TEST(ParallelFor, VisitsEveryIndexOnceForManyRangesAndThreadCounts) {
  for (int threads : {1, 2, 3, 4, 8}) {
    for (int begin : {-3, 0, 5}) {
      for (int n : {-2, 0, 1, 2, 3, 7, 40, 129, 1000, 20000}) {
        ExpectEachIndexOnce(begin, begin + n, threads);
      }
    }
  }
}

TEST(ParallelFor, ThreadIdsAreUniqueAmongConcurrentItems) {
  // Items long enough (20 µs) that the participants overlap.
  for (int threads : {2, 3, 4}) ExpectEachIndexOnce(0, 300, threads, 20);
}

TEST(ParallelFor, RejectsThreadCountsOutsideTheDocumentedRange) {
  for (int threads : {0, -1, kMaxParallelThreads + 1, 100000}) {
    EXPECT_THAT([&] { ParallelFor(0, 10, threads, [](int, int) {}); },
                ::testing::ThrowsMessage<InvalidArgument>(
                    HasSubstr("num_threads is " + std::to_string(threads))));
  }
  EXPECT_NO_THROW(ParallelFor(0, 10, kMaxParallelThreads, [](int, int) {}));
}

// Items 17 and 33 throw; the exception of the smallest index reaches the caller, every index
// below it ran, and the pool keeps working.
TEST(ParallelFor, RethrowsTheExceptionOfTheSmallestIndexOnTheCaller) {
  for (int threads : {1, 2, 4}) {
    for (int repeat = 0; repeat < 20; ++repeat) {
      std::vector<std::atomic<int>> ran(100);
      std::string message;
      try {
        ParallelFor(0, 100, threads, [&](int i, int) {
          ran[static_cast<size_t>(i)] = 1;
          if (i == 17 || i == 33) throw std::runtime_error("item " + std::to_string(i));
          SpinFor(2);
        });
      } catch (const std::runtime_error& e) {
        message = e.what();
      }
      EXPECT_EQ(message, "item 17") << "threads " << threads;
      for (int i = 0; i <= 17; ++i) EXPECT_EQ(ran[static_cast<size_t>(i)].load(), 1) << i;
    }
  }
  // Any type, from the caller's or a worker's item.
  EXPECT_THROW(ParallelFor(0, 50, 2,
                           [](int i, int) {
                             if (i == 49) throw 42;
                           }),
               int);
  ExpectEachIndexOnce(0, 1000, 2);
}

TEST(ParallelFor, NestedCallsRunSeriallyWithoutDeadlock) {
  std::vector<std::atomic<int>> hits(40 * 30);
  ParallelFor(0, 40, 2, [&](int i, int) {
    ParallelFor(0, 30, 2, [&](int j, int inner_thread) {
      EXPECT_EQ(inner_thread, 0);  // the pool is busy with the outer phase
      hits[static_cast<size_t>(i * 30 + j)] += 1;
    });
  });
  for (const std::atomic<int>& h : hits) EXPECT_EQ(h.load(), 1);
}

// Two threads (two optimizers, say) call ParallelFor at the same time: one gets the pool, the
// other runs serially; neither deadlocks, both see every index once.
TEST(ParallelFor, ConcurrentCallersFromTwoThreads) {
  auto caller = [](int threads) {
    for (int r = 0; r < 300; ++r) ExpectEachIndexOnce(0, 1 + (r * 7) % 97, threads, r % 3);
  };
  std::thread a(caller, 2), b(caller, 3);
  a.join();
  b.join();
}

// Simulates descheduled workers: each worker is woken 1 s late. A fork-join loop would wait for
// them at its barrier; here the caller runs every item itself and returns at once.
TEST(ParallelFor, CallerFinishesThePhaseWhenWorkersAreLate) {
  ExpectEachIndexOnce(0, 100, 4);  // the workers exist
  internal::SetWorkerWakeDelayForTesting(1000);
  std::vector<int> thread_of(200, -1);
  const auto start = Clock::now();
  ParallelFor(0, 200, 4, [&](int i, int thread) { thread_of[static_cast<size_t>(i)] = thread; });
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_LT(seconds, 0.5);
  EXPECT_EQ(std::count(thread_of.begin(), thread_of.end(), 0), 200);
  // Later phases with different ranges and thread counts while the late workers wake up (they
  // must not take items of a phase they were not woken for).
  internal::SetWorkerWakeDelayForTesting(2);
  for (int r = 0; r < 200; ++r) ExpectEachIndexOnce(r % 5, 3 + (r * 13) % 150, 2 + r % 3);
  internal::SetWorkerWakeDelayForTesting(0);
}

// The pool does run items on its workers (it is not a serial loop): with 2 ms items, a worker
// takes some within a few phases.
TEST(ParallelFor, WorkersTakeItems) {
  bool worker_ran = false;
  const auto deadline = Clock::now() + std::chrono::seconds(20);
  while (!worker_ran && Clock::now() < deadline) {
    std::atomic<int> on_workers{0};
    ParallelFor(0, 8, 2, [&](int, int thread) {
      if (thread != 0) ++on_workers;
      SpinFor(2000);
    });
    worker_ran = on_workers.load() > 0;
  }
  EXPECT_TRUE(worker_ran);
  EXPECT_GE(internal::NumThreadPoolWorkers(), 1);
}

// Home ranges: with P participants and one item per chunk (4 per participant), participant p
// owns items [4p, 4p + 4). Its owner takes them from the front and others steal them from the
// back, so in every phase, whatever the timing, each home range is a prefix run by its owner and
// a suffix run by others. (One shared counter, as before session 21, breaks this: the caller
// takes item 0, a worker item 1, the caller item 2.) And the items do get spread: in some phase
// (30 at least, more up to 20 s if the workers are never scheduled) a worker runs the first item
// of its own range.
TEST(ParallelFor, OwnersTakeTheirRangeFromTheFrontAndOthersStealFromTheBack) {
  for (int threads : {2, 3}) {
    const int n = 4 * threads;
    bool worker_started_its_range = false;
    const auto deadline = Clock::now() + std::chrono::seconds(20);
    for (int phase = 0; phase < 30 || (!worker_started_its_range && Clock::now() < deadline);
         ++phase) {
      std::vector<int> thread_of(static_cast<size_t>(n), -1);
      ParallelFor(0, n, threads, [&](int i, int thread) {
        thread_of[static_cast<size_t>(i)] = thread;
        SpinFor(200);
      });
      for (int p = 0; p < threads; ++p) {
        // Owner's items first, then only others' items.
        bool in_suffix = false;
        for (int i = 4 * p; i < 4 * p + 4; ++i) {
          const int t = thread_of[static_cast<size_t>(i)];
          ASSERT_GE(t, 0) << "item " << i << " did not run";
          if (t != p) in_suffix = true;
          EXPECT_FALSE(in_suffix && t == p)
              << "threads " << threads << ", item " << i << ": its owner " << p
              << " ran it after another thread stole an earlier one";
        }
        if (p > 0 && thread_of[static_cast<size_t>(4 * p)] == p) worker_started_its_range = true;
      }
    }
    EXPECT_TRUE(worker_started_its_range) << "threads " << threads;
  }
}

// The idle workers' yield time: set, read back, restored; negative times are refused; phases
// run as before with workers that stay awake between them.
TEST(ParallelFor, IdleYieldTimeIsSetReadAndRestored) {
  using std::chrono::microseconds;
  const microseconds original = internal::ThreadPoolIdleYield();
  EXPECT_EQ(original, microseconds(250));
  EXPECT_EQ(internal::SetThreadPoolIdleYield(microseconds(30000)), original);
  EXPECT_EQ(internal::ThreadPoolIdleYield(), microseconds(30000));
  EXPECT_THAT([] { internal::SetThreadPoolIdleYield(microseconds(-1)); },
              ::testing::ThrowsMessage<InvalidArgument>(::testing::HasSubstr("yield_time")));
  EXPECT_EQ(internal::ThreadPoolIdleYield(), microseconds(30000));
  for (int phase = 0; phase < 3; ++phase) {
    std::vector<int> visits(64, 0);
    ParallelFor(0, 64, 2, [&](int i, int) { ++visits[i]; });
    EXPECT_EQ(std::count(visits.begin(), visits.end(), 1), 64);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // idle, awake
  }
  EXPECT_EQ(internal::SetThreadPoolIdleYield(original), microseconds(30000));
  EXPECT_EQ(internal::ThreadPoolIdleYield(), original);
}

}  // namespace
}  // namespace idto
