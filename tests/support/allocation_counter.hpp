#pragma once

/// @file
/// Counts heap allocations (malloc, calloc, realloc; operator new and Eigen go through malloc)
/// while a ScopedAllocationCounter is alive. Define IDTO_DEFINE_ALLOCATION_COUNTER before
/// including this header in exactly one translation unit of a test binary: it interposes glibc's
/// malloc or, under AddressSanitizer (which owns malloc), installs an allocation hook in the
/// sanitizer's allocator, which every allocation of the program runs. Under ThreadSanitizer
/// counting is unavailable: AllocationCountingAvailable() is false and tests should skip.

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

#if defined(__SANITIZE_THREAD__)
inline bool AllocationCountingAvailable() { return false; }
#elif defined(__SANITIZE_ADDRESS__)
/// Set when the defining translation unit installed its hook (at static initialization).
inline std::atomic<bool>& AllocationHookInstalled() {
  static std::atomic<bool> installed{false};
  return installed;
}
inline bool AllocationCountingAvailable() { return AllocationHookInstalled().load(); }
#else
inline bool AllocationCountingAvailable() { return true; }
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

#if defined(IDTO_DEFINE_ALLOCATION_COUNTER) && defined(__SANITIZE_ADDRESS__)
// The sanitizer runtime's hook interface (sanitizer/allocator_interface.h, which GCC does not
// install): the malloc hook runs for every allocation, whatever function made it.
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*,
                                                                             std::size_t),
                                                         void (*free_hook)(const volatile void*));

namespace idto::test {
namespace {
void CountAllocation(const volatile void* /*p*/, std::size_t /*size*/) {
  if (AllocationCounting()) ++AllocationCount();
}
void IgnoreFree(const volatile void* /*p*/) {}
// Before main, on the main thread, as the runtime requires. It returns 0 on failure (and when
// either hook is null).
const bool kAllocationHookInstalled = [] {
  const bool ok = __sanitizer_install_malloc_and_free_hooks(&CountAllocation, &IgnoreFree) != 0;
  AllocationHookInstalled() = ok;
  return ok;
}();
}  // namespace
}  // namespace idto::test
#endif
