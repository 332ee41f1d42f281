#pragma once

/// @file
/// Options of the IDTO solver (design.md §5). Contact physics is part of the problem.

#include <string>

#include "idto/problem/derivative_method.hpp"

namespace idto {

/// How the unactuated-torque constraint h(q) = 0 is handled (paper §5.2).
enum class ConstraintMethod {
  kNone,                ///< ignore h (R's unactuated entries still weigh it)
  kPenalty,             ///< quadratic penalty through R's unactuated entries
  kLagrangeMultipliers  ///< constrained dogleg on the merit L + h^T lambda
};

/// The YAML spelling of a constraint method: "none", "penalty" or "lagrange".
std::string ConstraintMethodName(ConstraintMethod method);

/// Diagonal scaling D of the trust region.
enum class ScalingMethod {
  kNone,       ///< D = I
  kSqrt,       ///< D = diag(H)^(-1/2)
  kDoubleSqrt  ///< D = diag(H)^(-1/4): the paper's choice
};

/// Solver options with documented defaults. Check with IsValid().
struct SolverOptions {
  int max_iterations{100};  ///< iterations (each: derivatives, factorization, trial)
  /// Largest accepted num_threads (a higher count is an error, not a silent cap).
  static constexpr int kMaxNumThreads = 256;
  /// Threads for per-step work, in [1, kMaxNumThreads] (results do not depend on it). More
  /// threads pay off reliably from about 10 degrees of freedom. On a 2-core virtual machine,
  /// 2 threads took 0.76× the 1-thread iteration on the quadruped (nv = 18). On the spinner,
  /// hopper, acrobot and pendulum (nv ≤ 5) they took 1.06–1.5× on one day and 0.61–0.73× on
  /// another, depending on how costly it was to move a step's data between the cores
  /// (docs/benchmarks.md, sessions 17 and 21). Measure on the target machine.
  int num_threads{1};
  ConstraintMethod constraint_method{ConstraintMethod::kPenalty};
  /// kPenalty: when > 0, the weight w of w/2 |h|^2, placed on R's unactuated entries (paper
  /// §5.2.1); 0 keeps R's unactuated entries as given (the paper's tables set them in R).
  double penalty_weight{0.0};
  /// kLagrangeMultipliers: accumulate the KKT refinement's residual in double-double arithmetic
  /// (two refinement steps), so the Newton step and λ are exact to double precision instead of
  /// carrying ~κ·1e-16 relative error (κ the KKT system's condition number; ~1e-6 → below 1e-15
  /// on the bimanual examples) for about 1.8× the KKT time
  /// (BandedKktSolver::set_extended_residual).
  bool kkt_extended_residual{false};
  /// kLagrangeMultipliers, without kkt_extended_residual: when the refinement's first correction
  /// of the KKT step is above this (relative), one more refinement step with the residual in
  /// double-double follows (BandedKktSolver::set_extended_threshold). The default 1e-11 leaves
  /// well-conditioned steps as they are and brings ill-conditioned ones (the quadruped, hopper
  /// and bi-manual examples) within ~1e-11 of the exact step. >= 0; infinity (or 1e300 in YAML):
  /// never.
  double kkt_extended_threshold{1e-11};
  /// d tau / d q: exact (kAnalytic, the default) or by forward / central differences.
  DerivativeMethod derivative_method{DerivativeMethod::kAnalytic};
  /// Relative step of finite differences; 0: sqrt(eps) (forward; central with contact) or
  /// cbrt(eps) (central without contact).
  double finite_difference_step{0.0};
  ScalingMethod scaling{ScalingMethod::kDoubleSqrt};

  double initial_trust_radius{1e-1};  ///< in scaled coordinates
  double max_trust_radius{1e3};
  double acceptance_ratio{0.05};  ///< eta: accept the step when rho > eta
  /// kLagrangeMultipliers: a dogleg step shorter than the Newton step does not satisfy the
  /// linearized constraints h + A p = 0 (its Cauchy part follows the merit's gradient, which
  /// does not see the violation). The step is then corrected onto them: p + c, with c the
  /// correction of least H-norm (A c = −(h + A p), one more solve with the KKT factorization),
  /// scaled down to |D⁻¹ c| <= constraint_correction × the trust radius. A correction that makes
  /// the predicted reduction non-positive is dropped. 0: no correction (the reference
  /// implementation's step). In [0, 10] (docs/solver.md, "Constraint correction").
  double constraint_correction{0.5};

  /// Convergence (all on by default; set a tolerance to 0 to disable it):
  double cost_tolerance{1e-10};      ///< |L_new - L| / max(|L|, 1) after an accepted step
  double gradient_tolerance{1e-12};  ///< |g^T p| / max(|L|, 1)
  double step_tolerance{1e-12};      ///< |p| / max(|q|, 1)
  /// Runs exactly max_iterations (MPC); convergence tests are skipped.
  bool fixed_iterations{false};
  /// With the analytic derivatives: evaluate the initial guess and each trial point together
  /// with its derivatives, in one pass per step (Transcription::EvaluateWithDerivatives): the
  /// next iteration after an accepted step needs no separate derivative phase, and the
  /// evaluation's own kinematics and inverse dynamics are saved. A rejected step discards its
  /// derivatives, so trial points are evaluated so only where acceptance is likely: not on the
  /// last iteration, after a rejected step or a step that grew the trust radius, or for a full
  /// Newton step. The same method; tau and the contact round differently (docs/solver.md,
  /// "Trial derivatives"). No effect with finite differences.
  bool trial_derivatives{true};

  int verbosity{0};  ///< 0 silent, 1 a line per iteration (to stdout)

  /// True when every field is valid; otherwise false with the reason in *why.
  bool IsValid(std::string* why) const;
};

}  // namespace idto
