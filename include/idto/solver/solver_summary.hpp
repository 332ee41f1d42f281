#pragma once

/// @file
/// What a solve reports (design.md §5): per-iteration statistics and the outcome.

#include <string>
#include <vector>

namespace idto {

enum class TerminationType {
  kConverged,        ///< a convergence criterion was met
  kMaxIterations,    ///< ran out of iterations (the normal outcome with fixed_iterations)
  kFailure,          ///< numerical trouble (non-finite cost, failed factorization); last good
                     ///< iterate kept
  kUserTermination,  ///< a callback asked to stop, successfully (kTerminateSuccessfully)
  kUserAbort         ///< a callback aborted the solve (kAbort); last good iterate kept
};

/// "converged", "max_iterations", "failure", "user" or "user_abort".
std::string TerminationTypeName(TerminationType type);

/// Dogleg step kinds.
enum class DoglegStep { kNewton, kCauchy, kDogleg, kNone };

/// Statistics of one iteration.
struct IterationSummary {
  int iteration{0};
  double cost{0.0};              ///< L at the start of the iteration
  double merit{0.0};             ///< L + h^T lambda (= cost without multipliers)
  double gradient_norm{0.0};     ///< |g| (of the merit with multipliers)
  double step_norm{0.0};         ///< |p|
  double scaled_step_norm{0.0};  ///< |D^-1 p| of the dogleg step (before any correction)
  /// |D^-1 c| of the constraint correction added to the dogleg step (Lagrange method,
  /// SolverOptions::constraint_correction); 0 when none was added. step_norm includes it.
  double correction_norm{0.0};
  double trust_radius{0.0};  ///< radius used for this step
  double ratio{0.0};         ///< rho = actual / predicted reduction
  bool accepted{false};
  /// Lagrange method: the trial point passed the ratio test but its cost and constraint
  /// violation were both more than 10 times the iterate's, so it was rejected as a failed step
  /// (the radius shrinks; docs/solver.md, "Growth guard"). Always false with the penalty method.
  bool growth_guard{false};
  DoglegStep step_type{DoglegStep::kNone};
  double constraint_violation{0.0};  ///< sum of squared unactuated generalized forces
  double trial_cost{0.0};
  /// The trial point was evaluated together with its derivatives
  /// (SolverOptions::trial_derivatives): an accepted step starts the next iteration with them,
  /// a rejected one discards them.
  bool trial_with_derivatives{false};
  /// Levenberg-Marquardt shift mu of H + mu diag(H) needed to factor H (0: none).
  double regularization{0.0};
  // Seconds spent in each phase (wall time).
  /// The derivatives at the iterate (0 when the previous trial point brought them; iteration 0
  /// with trial_derivatives: the initial guess's evaluation with its derivatives).
  double time_derivatives{0.0};
  double time_cost{0.0};  ///< the trial point's trajectory and cost (with its derivatives, if so)
  double time_hessian{0.0};        ///< gradient and Gauss-Newton Hessian assembly
  double time_factorization{0.0};  ///< block Cholesky of H (with any regularization retries)
  double time_multipliers{0.0};    ///< Lagrange multipliers (0 with the penalty method)
  double time_total{0.0};          ///< the whole iteration
  /// Seconds spent in contact evaluation (ContactEngine::Evaluate and EvaluateChanged) during
  /// this iteration's derivative and cost phases: a share of time_derivatives + time_cost.
  /// Each thread's time inside those calls, summed over the solver's threads (like CPU time),
  /// so with num_threads > 1 it can exceed the wall time of those phases. 0 when the problem
  /// has no contact pairs. Measuring it never changes results.
  double time_contact{0.0};
};

/// The outcome of a solve.
struct SolverSummary {
  TerminationType termination{TerminationType::kMaxIterations};
  std::string message;
  int iterations{0};
  double initial_cost{0.0};
  double final_cost{0.0};
  double constraint_violation{0.0};  ///< at the returned trajectory
  double solve_time{0.0};            ///< s
  std::vector<IterationSummary> log;

  double mean_iteration_time() const;
  /// One line: termination, iterations, costs, violation, time.
  std::string BriefReport() const;
  /// The iteration table and the timing breakdown.
  std::string FullReport() const;
  /// The iteration log as CSV with a header line.
  std::string ToCsv() const;
};

}  // namespace idto
