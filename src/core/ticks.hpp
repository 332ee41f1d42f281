#pragma once

// A cheap monotonic tick counter for attributing time to short phases (the contact share of an
// iteration): the time-stamp counter on x86 (about 10 ns a read on this project's machine,
// against 25 ns for steady_clock::now()), nanoseconds of steady_clock elsewhere. Ticks are
// converted to seconds with the tick rate measured over a phase that contains them. Private to
// the library (src/ only).

#include <chrono>
#include <cstdint>

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace idto::internal {

inline std::uint64_t Ticks() {
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#else
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::steady_clock::now().time_since_epoch())
                                        .count());
#endif
}

// Ticks since t0 (0 if the counter went back, e.g. a thread moved to a core whose counter lags).
inline std::uint64_t TicksSince(std::uint64_t t0) {
  const std::uint64_t t1 = Ticks();
  return t1 > t0 ? t1 - t0 : 0;
}

// `ticks` counted inside a phase that lasted `phase_ticks` and `phase_seconds`, in seconds.
inline double TicksToSeconds(std::uint64_t ticks, std::uint64_t phase_ticks, double phase_seconds) {
  if (ticks == 0 || phase_ticks == 0) return 0.0;
  return phase_seconds * static_cast<double>(ticks) / static_cast<double>(phase_ticks);
}

}  // namespace idto::internal
