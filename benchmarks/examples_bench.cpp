// Time per solver iteration of every example (examples/<name>/<name>.yaml) as configured in its
// file, with analytic derivatives (the default) and forward differences, 1 and 2 threads,
// penalty and Lagrange multipliers.
//
// Each benchmark iteration is one solver iteration (SolveWarmStart, max_iterations = 1,
// fixed_iterations) from the example's initial guess after 5 warm-up iterations; the cost
// re-evaluation at the start of each call is included. Counters: the per-phase breakdown in µs.
// Names: "examples/<name>/<penalty|lagrange>/<analytic|forward>/threads:<T>", and
// "examples/<name>/lagrange_double_residual/analytic/threads:<T>": the KKT refinement's residual
// in double only (solver.kkt_extended_threshold infinite), the peer of the default's adaptive
// double-double step; "examples/<name>/<penalty|lagrange>_portable_kernels/analytic/threads:<T>":
// the dense block kernels' portable path (src/math/block_kernels.hpp), the peer of the AVX2/FMA
// path that the default runs on CPUs that have it.

#include <limits>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "idto/idto.hpp"
#include "iteration_timing.hpp"
#include "math/block_kernels.hpp"

namespace {

// Switches the AVX2/FMA block kernels off for one benchmark (benchmarks run one at a time).
class PortableKernels {
 public:
  explicit PortableKernels(bool on) : on_(on), before_(idto::internal::UseAvx2Kernels()) {
    if (on_) idto::internal::SetAvx2KernelsEnabledForTesting(false);
  }
  ~PortableKernels() {
    if (on_) idto::internal::SetAvx2KernelsEnabledForTesting(before_);
  }

 private:
  bool on_, before_;
};

void BM_ExampleIteration(benchmark::State& state, const std::string& name, bool lagrange,
                         idto::DerivativeMethod derivatives, bool double_residual,
                         bool portable_kernels = false) {
  const PortableKernels kernels(portable_kernels);
  const int threads = static_cast<int>(state.range(0));
  idto::ExampleConfig config;
  try {
    const std::string dir = std::string(IDTO_SOURCE_DIR);
    config = idto::LoadExampleConfig(dir + "/examples/" + name + "/" + name + ".yaml", {dir});
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  idto::SolverOptions o = config.solver;
  o.num_threads = threads;
  o.constraint_method =
      lagrange ? idto::ConstraintMethod::kLagrangeMultipliers : idto::ConstraintMethod::kPenalty;
  o.derivative_method = derivatives;
  if (double_residual) o.kkt_extended_threshold = std::numeric_limits<double>::infinity();
  o.max_iterations = 5;
  o.fixed_iterations = true;
  idto::TrajectoryOptimizer opt(config.model, config.problem, o);
  idto::Trajectory sol;
  opt.Solve(idto::MakeInitialGuess(config), &sol);  // warm-up: past the first iterations
  opt.mutable_options().max_iterations = 1;
  idto::bench::TimeSolverIterations(state, &opt, &sol);
  state.counters["nq"] = config.model.nq();
  state.counters["N"] = config.problem.num_steps;
}

void Register() {
  for (const std::string name :
       {"pendulum", "acrobot", "spinner", "hopper", "quadruped", "quadruped_hills", "allegro",
        "bimanual", "bimanual_lift", "bimanual_balance", "quadruped_limits", "allegro_limits"}) {
    // 0: penalty, 1: Lagrange, 2: Lagrange with the residual in double only.
    for (int variant : {0, 1, 2}) {
      const bool lagrange = variant > 0, double_residual = variant == 2;
      if (name == "pendulum" && lagrange) continue;
      for (const auto method :
           {idto::DerivativeMethod::kAnalytic, idto::DerivativeMethod::kForwardDifferences}) {
        if (double_residual && method != idto::DerivativeMethod::kAnalytic) continue;
        const std::string bench =
            "examples/" + name + "/" +
            (variant == 0 ? "penalty" : (variant == 1 ? "lagrange" : "lagrange_double_residual")) +
            (method == idto::DerivativeMethod::kAnalytic ? "/analytic" : "/forward");
        benchmark::RegisterBenchmark(
            bench.c_str(),
            [name, lagrange, method, double_residual](benchmark::State& s) {
              BM_ExampleIteration(s, name, lagrange, method, double_residual);
            })
            ->ArgName("threads")
            ->Arg(1)
            ->Arg(2)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
    for (const bool lagrange : {false, true}) {
      if (name == "pendulum" && lagrange) continue;
      const std::string bench = "examples/" + name + "/" + (lagrange ? "lagrange" : "penalty") +
                                "_portable_kernels/analytic";
      benchmark::RegisterBenchmark(
          bench.c_str(),
          [name, lagrange](benchmark::State& s) {
            BM_ExampleIteration(s, name, lagrange, idto::DerivativeMethod::kAnalytic, false, true);
          })
          ->ArgName("threads")
          ->Arg(1)
          ->Arg(2)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
}

const bool kRegistered = (Register(), true);

}  // namespace
