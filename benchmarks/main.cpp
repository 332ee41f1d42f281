// idto-bench: the benchmark suite. Benchmarks register themselves in the other files of this
// folder; names start with their module ("core/", "dynamics/", "contact/", "solver/", ...).
#include <benchmark/benchmark.h>

#include "idto/version.hpp"

int main(int argc, char** argv) {
  benchmark::AddCustomContext("idto_version", IDTO_VERSION_STRING);
#if defined(__clang__)
  benchmark::AddCustomContext("compiler", "clang " __clang_version__);
#elif defined(__GNUC__)
  benchmark::AddCustomContext("compiler", "gcc " __VERSION__);
#endif
#ifdef IDTO_HAVE_MUJOCO
  benchmark::AddCustomContext("mujoco", "yes");
#else
  benchmark::AddCustomContext("mujoco", "no");
#endif
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
