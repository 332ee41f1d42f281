#pragma once

/// @file
/// Counts heap allocations (malloc, calloc, realloc; operator new and Eigen go through malloc)
/// while a ScopedAllocationCounter is alive. Define IDTO_DEFINE_ALLOCATION_COUNTER before
/// including this header in exactly one translation unit of a test binary: it interposes glibc's
/// malloc. Under AddressSanitizer (which owns malloc) counting is unavailable:
/// AllocationCountingAvailable() is false and tests should skip.

#include <atomic>
#include <cstddef>

namespace idto::test {

inline std::atomic<long>& AllocationCount() {
  static std::atomic<long> count{0};
  return count;
}
inline std::atomic<bool>& AllocationCounting() {
  static std::atomic<bool> on{false};
  return on;
}

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool AllocationCountingAvailable() { return false; }
#else
constexpr bool AllocationCountingAvailable() { return true; }
#endif

/// Counts allocations between construction and count().
class ScopedAllocationCounter {
 public:
  ScopedAllocationCounter() {
    AllocationCount() = 0;
    AllocationCounting() = true;
  }
  ~ScopedAllocationCounter() { AllocationCounting() = false; }
  long count() const { return AllocationCount().load(); }
};

}  // namespace idto::test

#if defined(IDTO_DEFINE_ALLOCATION_COUNTER) && \
    !(defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__))
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t n, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void __libc_free(void* p);

void* malloc(std::size_t size) {
  if (idto::test::AllocationCounting()) ++idto::test::AllocationCount();
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
  if (idto::test::AllocationCounting()) ++idto::test::AllocationCount();
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) {
  if (idto::test::AllocationCounting()) ++idto::test::AllocationCount();
  return __libc_realloc(p, size);
}
void free(void* p) { __libc_free(p); }
}
#endif
