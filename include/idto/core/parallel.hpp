#pragma once

/// @file
/// A deterministic parallel-for over independent indices.
///
/// Each index must write only its own outputs; reductions are done afterwards in index order by
/// the caller, so results are bitwise identical for any thread count.

#ifdef _OPENMP
#include <omp.h>
#endif

namespace idto {

/// Number of threads OpenMP would use by default (1 without OpenMP).
inline int MaxThreads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

/// Calls `body(i, thread)` for i in [begin, end) on up to `num_threads` threads (static
/// schedule). `thread` in [0, num_threads) identifies the calling thread for per-thread scratch.
template <typename Body>
void ParallelFor(int begin, int end, int num_threads, const Body& body) {
#ifdef _OPENMP
  if (num_threads > 1 && end - begin > 1) {
#pragma omp parallel for schedule(static) num_threads(num_threads)
    for (int i = begin; i < end; ++i) body(i, omp_get_thread_num());
    return;
  }
#endif
  (void)num_threads;
  for (int i = begin; i < end; ++i) body(i, 0);
}

}  // namespace idto
