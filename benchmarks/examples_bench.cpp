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
//
// "solve5/<name>/<penalty|lagrange>/<trial_derivatives|separate>/threads:<T>": whole solves of 5
// iterations, where trial points bring the next iteration's derivatives (the one-iteration
// benchmarks above end on their last iteration, which never evaluates its trial point with
// derivatives); "solve5_ab/<name>/<penalty|lagrange>/threads:<T>": the two alternating in one
// loop, with their ratio; "correction_ab/<name>/lagrange/threads:<T>": the same for the
// constraint correction (SolverOptions::constraint_correction) against none.

#include <cstdint>
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

// Loads examples/<name>/<name>.yaml into *config and sets *options to its solver options on
// state.range(0) threads with the penalty or Lagrange route, 5 fixed iterations (the warm-up).
// False (the benchmark skipped with the error) when the example does not load.
bool LoadBenchmarkExample(benchmark::State& state, const std::string& name, bool lagrange,
                          idto::ExampleConfig* config, idto::SolverOptions* options) {
  try {
    const std::string dir = std::string(IDTO_SOURCE_DIR);
    *config = idto::LoadExampleConfig(dir + "/examples/" + name + "/" + name + ".yaml", {dir});
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return false;
  }
  *options = config->solver;
  options->num_threads = static_cast<int>(state.range(0));
  options->constraint_method =
      lagrange ? idto::ConstraintMethod::kLagrangeMultipliers : idto::ConstraintMethod::kPenalty;
  options->max_iterations = 5;
  options->fixed_iterations = true;
  return true;
}

void BM_ExampleIteration(benchmark::State& state, const std::string& name, bool lagrange,
                         idto::DerivativeMethod derivatives, bool double_residual,
                         bool portable_kernels = false) {
  const PortableKernels kernels(portable_kernels);
  idto::ExampleConfig config;
  idto::SolverOptions o;
  if (!LoadBenchmarkExample(state, name, lagrange, &config, &o)) return;
  o.derivative_method = derivatives;
  if (double_residual) o.kkt_extended_threshold = std::numeric_limits<double>::infinity();
  idto::TrajectoryOptimizer opt(config.model, config.problem, o);
  idto::Trajectory sol;
  opt.Solve(idto::MakeInitialGuess(config), &sol);  // warm-up: past the first iterations
  opt.mutable_options().max_iterations = 1;
  idto::bench::TimeSolverIterations(state, &opt, &sol);
  state.counters["nq"] = config.model.nq();
  state.counters["N"] = config.problem.num_steps;
}

// One benchmark iteration is a whole solve of kSolveIterations iterations (Solve from the
// iterate the warm-up reached, so every call does the same work), with the initial guess's
// evaluation: the iteration figure (`iteration_us`) is the solve time divided by the iterations,
// everything included. With trial derivatives (the default) each accepted trial point brings
// its derivatives; "separate" evaluates and differentiates in two passes (the peer). Counters:
// accepted steps and trial points evaluated with derivatives per solve.
constexpr int kSolveIterations = 5;

void BM_ExampleSolve(benchmark::State& state, const std::string& name, bool lagrange,
                     bool trial_derivatives) {
  idto::ExampleConfig config;
  idto::SolverOptions o;
  if (!LoadBenchmarkExample(state, name, lagrange, &config, &o)) return;
  o.trial_derivatives = trial_derivatives;
  idto::TrajectoryOptimizer opt(config.model, config.problem, o);
  idto::Trajectory sol;
  opt.Solve(idto::MakeInitialGuess(config), &sol);  // warm-up: past the first iterations
  const std::vector<Eigen::VectorXd> start = sol.q;
  opt.mutable_options().max_iterations = kSolveIterations;
  double seconds = 0.0, accepted = 0.0, with_derivatives = 0.0, t_deriv = 0.0, t_cost = 0.0;
  double t_hess = 0.0;
  std::int64_t solves = 0;
  for (auto _ : state) {
    const idto::SolverSummary s = opt.Solve(start, &sol);
    if (s.termination == idto::TerminationType::kFailure || s.iterations != kSolveIterations) {
      state.SkipWithError(("solve failed: " + s.message).c_str());
      break;
    }
    seconds += s.solve_time;
    for (const idto::IterationSummary& it : s.log) {
      accepted += it.accepted;
      with_derivatives += it.trial_with_derivatives;
      t_deriv += it.time_derivatives;
      t_cost += it.time_cost;
      t_hess += it.time_hessian;
    }
    ++solves;
  }
  if (solves > 0) {
    const double n = static_cast<double>(solves);
    state.counters["iteration_us"] = 1e6 * seconds / (n * kSolveIterations);
    state.counters["accepted"] = accepted / n;
    state.counters["derivatives_us"] = 1e6 * t_deriv / (n * kSolveIterations);
    state.counters["trial_cost_us"] = 1e6 * t_cost / (n * kSolveIterations);
    state.counters["hessian_us"] = 1e6 * t_hess / (n * kSolveIterations);
    state.counters["trials_with_derivatives"] = with_derivatives / n;
  }
  state.counters["nq"] = config.model.nq();
  state.counters["N"] = config.problem.num_steps;
}

// Two settings of one option alternating solve by solve in one loop (the machine's speed drifts
// by up to 1.5x between runs minutes apart): each benchmark iteration is one solve of each.
// set(options, first) applies the first (the default) or the second setting. Counters: µs per
// solver iteration of each (named first_name, second_name) and their ratio second / first (above
// 1 when the default is faster). trial derivatives vs separate passes; the constraint correction
// vs none (their solves take different steps: the ratio is per iteration, not per solve).
template <typename Set>
void BM_OptionAb(benchmark::State& state, const std::string& name, bool lagrange,
                 const char* first_name, const char* second_name, Set set) {
  idto::ExampleConfig config;
  idto::SolverOptions o;
  if (!LoadBenchmarkExample(state, name, lagrange, &config, &o)) return;
  idto::Trajectory sol;
  idto::TrajectoryOptimizer warm(config.model, config.problem, o);
  warm.Solve(idto::MakeInitialGuess(config), &sol);
  const std::vector<Eigen::VectorXd> start = sol.q;
  o.max_iterations = kSolveIterations;
  set(&o, true);
  idto::TrajectoryOptimizer first(config.model, config.problem, o);
  set(&o, false);
  idto::TrajectoryOptimizer second(config.model, config.problem, o);
  double t_first = 0.0, t_second = 0.0;
  std::int64_t solves = 0;
  for (auto _ : state) {
    const idto::SolverSummary a = first.Solve(start, &sol);
    const idto::SolverSummary b = second.Solve(start, &sol);
    if (a.iterations != kSolveIterations || b.iterations != kSolveIterations) {
      state.SkipWithError("a solve stopped early");
      break;
    }
    t_first += a.solve_time;
    t_second += b.solve_time;
    ++solves;
  }
  if (solves > 0) {
    const double per = 1e6 / (static_cast<double>(solves) * kSolveIterations);
    state.counters[first_name] = t_first * per;
    state.counters[second_name] = t_second * per;
    state.counters["ratio"] = t_second / t_first;
  }
}

void BM_TrialDerivativesAb(benchmark::State& state, const std::string& name, bool lagrange) {
  BM_OptionAb(state, name, lagrange, "trial_derivatives_us", "separate_us",
              [](idto::SolverOptions* o, bool first) { o->trial_derivatives = first; });
}

void BM_ConstraintCorrectionAb(benchmark::State& state, const std::string& name) {
  const double correction = idto::SolverOptions().constraint_correction;
  BM_OptionAb(state, name, true, "correction_us", "no_correction_us",
              [correction](idto::SolverOptions* o, bool first) {
                o->constraint_correction = first ? correction : 0.0;
              });
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
    if (name != "pendulum") {
      benchmark::RegisterBenchmark(
          ("correction_ab/" + name + "/lagrange").c_str(),
          [name](benchmark::State& s) { BM_ConstraintCorrectionAb(s, name); })
          ->ArgName("threads")
          ->Arg(1)
          ->Arg(2)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
    for (const bool lagrange : {false, true}) {
      if (name == "pendulum" && lagrange) continue;
      benchmark::RegisterBenchmark(
          ("solve5_ab/" + name + "/" + (lagrange ? "lagrange" : "penalty")).c_str(),
          [name, lagrange](benchmark::State& s) { BM_TrialDerivativesAb(s, name, lagrange); })
          ->ArgName("threads")
          ->Arg(1)
          ->Arg(2)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      for (const bool fused : {true, false}) {
        const std::string bench = "solve5/" + name + "/" + (lagrange ? "lagrange" : "penalty") +
                                  (fused ? "/trial_derivatives" : "/separate");
        benchmark::RegisterBenchmark(bench.c_str(),
                                     [name, lagrange, fused](benchmark::State& s) {
                                       BM_ExampleSolve(s, name, lagrange, fused);
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
