#include <vector>

#include <benchmark/benchmark.h>

#include "core/parallel.hpp"

namespace {

// Overhead of one ParallelFor dispatch over 40 cheap items (a horizon's worth of time steps).
void BM_ParallelForOverhead(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  std::vector<double> out(40, 0.0);
  for (auto _ : state) {
    idto::ParallelFor(0, 40, threads, [&](int i, int) { out[i] += 1.0; });
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ParallelForOverhead)->Name("core/ParallelFor/40")->Arg(1)->Arg(2);

}  // namespace
