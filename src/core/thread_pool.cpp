// The process-wide thread pool behind ParallelFor (core/parallel.hpp).
//
// Protocol of one phase (a call of RunOnThreadPool that found the pool free):
//  1. The caller writes the phase descriptor (`phase_`), resets the completion counter, then
//     publishes the chunks as one home range per participant: participant p's chunks
//     [p C / P, (p + 1) C / P) in the atomic word `ranges_[p]` = [generation | next | end].
//  2. It posts the generation to the mailboxes of workers 1 .. participants-1 (waking those that
//     sleep), then claims and runs chunks itself with thread identity 0.
//  3. A participant takes chunks from the front of its own range; when that is empty it steals
//     from the back of the others'. A claim is a compare-exchange that succeeds only while the
//     range's generation is the participant's phase's and chunks remain in it; a worker that
//     wakes after its phase ended finds another generation or no chunk left and claims nothing
//     (the ranges of an ended phase are all empty). A successful claim means the caller is still
//     waiting for that chunk, so the descriptor it then reads is its phase's.
//     Home ranges keep a time step on the same thread from one phase to the next when nothing
//     is stolen and the phases have the same item and participant counts (the derivatives, the
//     gradient and the Hessian rows of step k), so its data stays in that thread's cache unless
//     the OS migrates the thread. On the 40-step spinner, claiming from one shared counter moved
//     the steps between the threads at random and made 2 threads slower than one
//     (docs/benchmarks.md, session 21).
//  Generations are compared modulo 2^24 in the range words: a worker that stalls between
//  reading its mailbox and claiming for exactly a multiple of 2^24 phases (minutes of other
//  threads' work) could take a chunk of a later phase. This was so before the home ranges too.
//  4. After running a chunk, the participant counts it in `done_`; the caller returns when every
//     chunk is counted. It never waits for a worker that has not claimed a chunk.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include <pthread.h>
#include <sched.h>

#include "core/parallel.hpp"

namespace idto::internal {
namespace {

// Waiting: spin this many checks (with a CPU pause), then yield until the yield time has passed
// since the wait began (kYieldTime; for idle workers SetThreadPoolIdleYield's), then sleep on a
// condition variable.
constexpr int kSpinChecks = 256;
constexpr std::chrono::microseconds kYieldTime{250};
// The idle workers' yield time in microseconds (SetThreadPoolIdleYield).
std::atomic<std::int64_t> idle_yield_us{kYieldTime.count()};
// The scheduling the workers follow (SetThreadPoolScheduling): request count (32 bits) | policy
// (16) | priority (16). Each worker applies a new request when it next wakes for a phase.
std::atomic<std::uint64_t> scheduling_request{0};
// errno of the latest worker that could not apply a request (0: none since the last take).
std::atomic<int> scheduling_error{0};
// Ranges longer than kChunksPerThread * participants are cut into chunks of several indices.
constexpr int kChunksPerThread = 4;  // see parallel.hpp

// A range word: generation (24 bits) | next chunk (20 bits) | end chunk (20 bits).
constexpr int kCountBits = 20;
constexpr std::uint64_t kCountMask = (std::uint64_t{1} << kCountBits) - 1;
constexpr int kMaxChunks = static_cast<int>(kCountMask);
constexpr std::uint64_t kGenerationMask = (std::uint64_t{1} << 24) - 1;
constexpr std::uint64_t kStopGeneration = ~std::uint64_t{0};

std::uint64_t PackRange(std::uint64_t generation, std::uint64_t next, std::uint64_t end) {
  return ((generation & kGenerationMask) << (2 * kCountBits)) | (next << kCountBits) | end;
}
std::uint64_t RangeGeneration(std::uint64_t word) { return word >> (2 * kCountBits); }
int RangeNext(std::uint64_t word) { return static_cast<int>((word >> kCountBits) & kCountMask); }
int RangeEnd(std::uint64_t word) { return static_cast<int>(word & kCountMask); }

// One participant's home range of chunks (cache-line aligned: its owner claims from it).
struct alignas(64) Range {
  std::atomic<std::uint64_t> word{0};  // generation 0, empty
};

// Takes the first (front) or the last (!front) chunk of `range` if it belongs to `generation`.
bool TakeChunk(std::atomic<std::uint64_t>* range, std::uint64_t generation, bool front,
               int* chunk) {
  std::uint64_t word = range->load(std::memory_order_acquire);
  for (;;) {
    if (RangeGeneration(word) != (generation & kGenerationMask)) return false;
    const int next = RangeNext(word), end = RangeEnd(word);
    if (next >= end) return false;
    const std::uint64_t taken = front ? word + (std::uint64_t{1} << kCountBits) : word - 1;
    if (range->compare_exchange_weak(word, taken, std::memory_order_acq_rel,
                                     std::memory_order_acquire)) {
      *chunk = front ? next : end - 1;
      return true;
    }
  }
}

inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

// A place to sleep: a thread that found `ready()` false after spinning and yielding sleeps on
// `cv`; whoever makes it true calls Notify() after its (sequentially consistent) store.
struct SleepSlot {
  std::atomic<bool> sleeping{false};
  std::mutex mutex;
  std::condition_variable cv;

  template <typename Ready>
  void WaitUntil(const Ready& ready, std::chrono::microseconds yield_time = kYieldTime) {
    for (int i = 0; i < kSpinChecks; ++i) {
      if (ready()) return;
      CpuRelax();
    }
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - start < yield_time) {
      if (ready()) return;
      std::this_thread::yield();
    }
    std::unique_lock<std::mutex> lock(mutex);
    // Dekker pair with Notify(): either ready() below sees the new state, or the notifier sees
    // `sleeping` and takes the mutex, which it can only do once this thread waits.
    sleeping.store(true, std::memory_order_seq_cst);
    while (!ready()) cv.wait(lock);
    sleeping.store(false, std::memory_order_relaxed);
  }

  void Notify() {
    if (sleeping.load(std::memory_order_seq_cst)) {
      std::lock_guard<std::mutex> lock(mutex);
      cv.notify_all();
    }
  }
};

// One worker thread, its mailbox (the generation of the latest phase posted to it) and its
// place to sleep. Cache-line aligned: the mailbox is polled while spinning.
struct alignas(64) Worker {
  std::atomic<std::uint64_t> mailbox{0};
  SleepSlot slot;
  std::thread thread;
};

// What the participants of a phase run. Written by the caller before the phase is published;
// read by a participant only while it holds a claimed chunk (the phase is then still running).
struct Phase {
  ItemFunction fn{nullptr};
  const void* context{nullptr};
  int begin{0};
  int end{0};
  int chunk_size{1};
  int num_chunks{0};
};

class ThreadPool {
 public:
  static ThreadPool& Instance() {
    static ThreadPool pool;
    return pool;
  }

  ThreadPool() = default;
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;
  ~ThreadPool();

  // Runs a phase; false (nothing run) when another phase holds the pool.
  bool TryRun(int begin, int end, int num_threads, ItemFunction fn, const void* context);

  void set_wake_delay_ms(int ms) { wake_delay_ms_.store(ms, std::memory_order_relaxed); }
  int num_workers() const { return num_workers_.load(std::memory_order_relaxed); }

 private:
  void StartWorkers(int count);
  void WorkerLoop(Worker* worker, int thread);
  void DelayForTesting(Worker* worker);
  void Participate(std::uint64_t generation, int thread);
  bool Claim(std::uint64_t generation, int thread, int* chunk);
  void RunChunk(int chunk, int thread);
  void RecordFailure(int i, std::exception_ptr error);

  std::atomic<bool> busy_{false};
  // Home ranges: [0, participants) of the latest phase; the others hold older, empty words.
  Range ranges_[kMaxParallelThreads];
  std::atomic<int> participants_{0};  // of the latest phase (a hint: see Claim)
  alignas(64) std::atomic<int> done_{0};
  std::atomic<int> first_failure_{INT_MAX};  // smallest index that threw in this phase
  std::mutex error_mutex_;
  std::exception_ptr error_;  // its exception (guarded by error_mutex_)
  Phase phase_;
  std::uint64_t generation_{0};                   // of the latest phase (caller side, under busy_)
  SleepSlot caller_;                              // where the caller waits for the last chunks
  std::vector<std::unique_ptr<Worker>> workers_;  // worker k has thread identity k + 1
  std::atomic<int> num_workers_{0};
  std::atomic<int> wake_delay_ms_{0};
};

ThreadPool::~ThreadPool() {
  for (const std::unique_ptr<Worker>& worker : workers_) {
    worker->mailbox.store(kStopGeneration, std::memory_order_seq_cst);
    std::lock_guard<std::mutex> lock(worker->slot.mutex);
    worker->slot.cv.notify_all();
  }
  for (const std::unique_ptr<Worker>& worker : workers_) worker->thread.join();
}

void ThreadPool::StartWorkers(int count) {
  while (static_cast<int>(workers_.size()) < count) {
    // The slot first: a bad_alloc here leaves no running thread behind (destroying a joinable
    // std::thread would terminate the process).
    workers_.push_back(std::make_unique<Worker>());
    Worker* raw = workers_.back().get();
    const int thread = static_cast<int>(workers_.size());
    try {
      raw->thread = std::thread([this, raw, thread] { WorkerLoop(raw, thread); });
    } catch (const std::system_error&) {
      workers_.pop_back();
      return;  // out of threads: the phases run with the workers there are
    }
    num_workers_.store(static_cast<int>(workers_.size()), std::memory_order_relaxed);
  }
}

// Applies a scheduling request to the calling worker thread; a refusal is kept for
// TakeThreadPoolSchedulingError.
void ApplySchedulingRequest(std::uint64_t request) {
  sched_param param{};
  param.sched_priority = static_cast<int>(request & 0xFFFF);
  const int policy = static_cast<int>((request >> 16) & 0xFFFF);
  const int error = pthread_setschedparam(pthread_self(), policy, &param);
  if (error != 0) scheduling_error.store(error, std::memory_order_relaxed);
}

void ThreadPool::WorkerLoop(Worker* worker, int thread) {
  std::uint64_t seen = 0, applied = 0;
  for (;;) {
    worker->slot.WaitUntil(
        [&] { return worker->mailbox.load(std::memory_order_seq_cst) != seen; },
        std::chrono::microseconds(idle_yield_us.load(std::memory_order_relaxed)));
    seen = worker->mailbox.load(std::memory_order_seq_cst);
    if (seen == kStopGeneration) return;
    const std::uint64_t request = scheduling_request.load(std::memory_order_acquire);
    if (request != applied) {
      ApplySchedulingRequest(request);
      applied = request;
    }
    if (wake_delay_ms_.load(std::memory_order_relaxed) > 0) DelayForTesting(worker);
    Participate(seen, thread);
  }
}

void ThreadPool::DelayForTesting(Worker* worker) {
  const std::chrono::milliseconds delay(wake_delay_ms_.load(std::memory_order_relaxed));
  std::unique_lock<std::mutex> lock(worker->slot.mutex);
  worker->slot.cv.wait_for(lock, delay, [&] {
    return worker->mailbox.load(std::memory_order_seq_cst) == kStopGeneration;
  });
}

bool ThreadPool::Claim(std::uint64_t generation, int thread, int* chunk) {
  if (TakeChunk(&ranges_[thread].word, generation, true, chunk)) return true;
  // The count only bounds the search: a range of another phase never yields a chunk (those of
  // an ended phase are empty, those of a later one carry its generation, modulo 2^24).
  const int participants =
      std::min(participants_.load(std::memory_order_acquire), kMaxParallelThreads);
  for (int s = 1; s < participants; ++s) {
    const int victim = (thread + s) % participants;
    if (TakeChunk(&ranges_[victim].word, generation, false, chunk)) return true;
  }
  return false;
}

void ThreadPool::Participate(std::uint64_t generation, int thread) {
  int chunk = 0;
  while (Claim(generation, thread, &chunk)) {
    const int num_chunks = phase_.num_chunks;  // read while the phase is surely running
    RunChunk(chunk, thread);
    // After this increment the phase may end: nothing of it is touched any more.
    if (done_.fetch_add(1, std::memory_order_seq_cst) + 1 == num_chunks) caller_.Notify();
  }
}

void ThreadPool::RunChunk(int chunk, int thread) {
  const Phase& phase = phase_;
  const int first = phase.begin + chunk * phase.chunk_size;
  const int last = first + std::min(phase.chunk_size, phase.end - first);
  for (int i = first; i < last; ++i) {
    if (i > first_failure_.load(std::memory_order_relaxed)) return;  // a smaller index threw
    try {
      phase.fn(phase.context, i, thread);
    } catch (...) {
      RecordFailure(i, std::current_exception());
      return;
    }
  }
}

void ThreadPool::RecordFailure(int i, std::exception_ptr error) {
  std::lock_guard<std::mutex> lock(error_mutex_);
  if (i < first_failure_.load(std::memory_order_relaxed)) {
    first_failure_.store(i, std::memory_order_relaxed);
    error_ = std::move(error);
  }
}

bool ThreadPool::TryRun(int begin, int end, int num_threads, ItemFunction fn, const void* context) {
  if (busy_.exchange(true, std::memory_order_acquire)) return false;
  struct Release {
    std::atomic<bool>* busy;
    ~Release() { busy->store(false, std::memory_order_release); }
  } release{&busy_};
  StartWorkers(num_threads - 1);
  const int participants = std::min(num_threads, static_cast<int>(workers_.size()) + 1);
  const int n = end - begin;
  int chunk_size = std::max(1, n / (kChunksPerThread * participants));
  chunk_size = std::max(chunk_size, n / kMaxChunks + 1);
  phase_ = Phase{fn, context, begin, end, chunk_size, (n + chunk_size - 1) / chunk_size};
  done_.store(0, std::memory_order_relaxed);
  first_failure_.store(INT_MAX, std::memory_order_relaxed);
  error_ = nullptr;
  const std::uint64_t generation = ++generation_;
  const std::uint64_t chunks = static_cast<std::uint64_t>(phase_.num_chunks);
  const std::uint64_t parts = static_cast<std::uint64_t>(participants);
  participants_.store(participants, std::memory_order_release);
  for (std::uint64_t p = 0; p < parts; ++p) {
    ranges_[p].word.store(PackRange(generation, p * chunks / parts, (p + 1) * chunks / parts),
                          std::memory_order_seq_cst);
  }
  for (int k = 0; k + 1 < participants; ++k) {
    Worker& worker = *workers_[static_cast<size_t>(k)];
    worker.mailbox.store(generation, std::memory_order_seq_cst);
    worker.slot.Notify();
  }
  Participate(generation, 0);
  const int num_chunks = phase_.num_chunks;
  caller_.WaitUntil([&] { return done_.load(std::memory_order_seq_cst) == num_chunks; });
  std::exception_ptr error;
  {
    std::lock_guard<std::mutex> lock(error_mutex_);
    error = std::move(error_);
    error_ = nullptr;
  }
  if (error) std::rethrow_exception(error);
  return true;
}

}  // namespace

void RunOnThreadPool(int begin, int end, int num_threads, ItemFunction fn, const void* context) {
  if (!ThreadPool::Instance().TryRun(begin, end, num_threads, fn, context)) {
    // The pool runs another phase (nested call, or another thread's): run serially here.
    for (int i = begin; i < end; ++i) fn(context, i, 0);
  }
}

void SetWorkerWakeDelayForTesting(int milliseconds) {
  ThreadPool::Instance().set_wake_delay_ms(milliseconds);
}

int NumThreadPoolWorkers() { return ThreadPool::Instance().num_workers(); }

std::chrono::microseconds SetThreadPoolIdleYield(std::chrono::microseconds yield_time) {
  if (yield_time.count() < 0) {
    ThrowInvalidArgument("SetThreadPoolIdleYield", "yield_time",
                         std::to_string(yield_time.count()) + " us", ">= 0");
  }
  return std::chrono::microseconds(idle_yield_us.exchange(yield_time.count()));
}

void SetThreadPoolScheduling(int policy, int priority) {
  if (policy < 0 || policy > 0xFFFF) {
    ThrowInvalidArgument("SetThreadPoolScheduling", "policy", std::to_string(policy),
                         "SCHED_OTHER, SCHED_FIFO or SCHED_RR");
  }
  if (priority < 0 || priority > 0xFFFF) {
    ThrowInvalidArgument("SetThreadPoolScheduling", "priority", std::to_string(priority),
                         "a priority of `policy` (sched_get_priority_min/max)");
  }
  static std::atomic<std::uint64_t> count{0};
  const std::uint64_t n = (count.fetch_add(1, std::memory_order_relaxed) + 1) & 0xFFFFFFFFu;
  scheduling_request.store(
      (n << 32) | (static_cast<std::uint64_t>(policy) << 16) | static_cast<std::uint64_t>(priority),
      std::memory_order_release);
}

int TakeThreadPoolSchedulingError() { return scheduling_error.exchange(0); }

std::chrono::microseconds ThreadPoolIdleYield() {
  return std::chrono::microseconds(idle_yield_us.load(std::memory_order_relaxed));
}

}  // namespace idto::internal
