#pragma once

// The timed loop shared by the solver benchmarks: each benchmark iteration is one solver
// iteration (SolveWarmStart on an optimizer set to max_iterations = 1), and the per-phase
// breakdown of the solver's own timers is reported as counters in µs per iteration
// (derivatives, hessian, factorization, multipliers, trial cost, and contact: the contact
// evaluations within derivatives and trial cost, CPU time summed over threads), and iteration:
// the solver's own time of the iteration (IterationSummary::time_total), without the per-call
// work around it (the start's cost evaluation, the solution's copy).

#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "idto/idto.hpp"

namespace idto::bench {

/// Runs the benchmark loop on `opt` from `*solution` and sets the breakdown counters. Stops
/// with an error when an iteration fails or logs nothing. With `restart` (N + 1 configurations)
/// and restart_every > 0, every restart_every-th iteration (the first included) is a cold Solve
/// from it: the loop cycles through the first restart_every iterations of one solve, so the
/// work does not depend on how far a run gets (without it, a faster build runs further into
/// the solve, whose later iterations may cost more). A run whose iteration count is not a
/// multiple of restart_every weights the early iterations of its last cycle more; a run of one
/// iteration times the cold first one.
inline void TimeSolverIterations(benchmark::State& state, TrajectoryOptimizer* opt,
                                 Trajectory* solution,
                                 const std::vector<Eigen::VectorXd>* restart = nullptr,
                                 int restart_every = 0) {
  if (restart != nullptr && restart_every <= 0) {
    state.SkipWithError("TimeSolverIterations: restart_every must be positive with a restart");
    return;
  }
  double t_deriv = 0, t_hess = 0, t_fact = 0, t_mult = 0, t_cost = 0, t_contact = 0, t_iter = 0;
  std::int64_t n = 0;
  for (auto _ : state) {
    const SolverSummary s = restart != nullptr && n % restart_every == 0
                                ? opt->Solve(*restart, solution)
                                : opt->SolveWarmStart(solution);
    if (s.termination == TerminationType::kFailure || s.log.empty()) {
      state.SkipWithError(("no iteration: " + s.message).c_str());
      break;
    }
    const IterationSummary& it = s.log.back();
    t_deriv += it.time_derivatives;
    t_hess += it.time_hessian;
    t_fact += it.time_factorization;
    t_mult += it.time_multipliers;
    t_cost += it.time_cost;
    t_contact += it.time_contact;
    t_iter += it.time_total;
    ++n;
  }
  if (n > 0) {
    const double us = 1e6 / static_cast<double>(n);
    state.counters["derivatives_us"] = t_deriv * us;
    state.counters["hessian_us"] = t_hess * us;
    state.counters["factorization_us"] = t_fact * us;
    state.counters["multipliers_us"] = t_mult * us;
    state.counters["trial_cost_us"] = t_cost * us;
    state.counters["contact_us"] = t_contact * us;
    state.counters["iteration_us"] = t_iter * us;
  }
}

}  // namespace idto::bench
