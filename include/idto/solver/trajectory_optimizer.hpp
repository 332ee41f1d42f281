#pragma once

/// @file
/// The IDTO solver (paper §5): Gauss-Newton trust region with dogleg steps on the
/// block-pentadiagonal Hessian, penalty or Lagrange multipliers for the unactuated DoFs.

#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "idto/multibody/model.hpp"
#include "idto/problem/problem_definition.hpp"
#include "idto/solver/solver_options.hpp"
#include "idto/solver/solver_summary.hpp"

namespace idto {

/// A trajectory: q_k (nq) and the derived v_k (nv), tau_k (nv), k = 0..N (tau_N is zero).
struct Trajectory {
  std::vector<Eigen::VectorXd> q;
  std::vector<Eigen::VectorXd> v;
  std::vector<Eigen::VectorXd> tau;
};

/// What a callback returns after each iteration (Ceres' SOLVER_CONTINUE /
/// SOLVER_TERMINATE_SUCCESSFULLY / SOLVER_ABORT).
enum class CallbackReturn {
  kContinue,               ///< go on
  kTerminateSuccessfully,  ///< stop: the iterate is good (TerminationType::kUserTermination)
  kAbort,                  ///< stop: something is wrong (TerminationType::kUserAbort)
  kTerminate = kTerminateSuccessfully  ///< the earlier spelling of kTerminateSuccessfully
};
using IterationCallback = std::function<CallbackReturn(const IterationSummary&)>;

/// Solves a ProblemDefinition: the Gauss-Newton trust-region minimizer (solver/) over the
/// problem's Transcription (problem/transcription.hpp). Holds all per-iteration buffers, so
/// repeated solves (MPC) do not allocate after the first iteration. Not thread-safe itself: it
/// uses options.num_threads internally.
class TrajectoryOptimizer {
 public:
  /// Validates the problem and options (throws InvalidArgument naming the field).
  TrajectoryOptimizer(const Model& model, const ProblemDefinition& problem,
                      const SolverOptions& options = {});
  ~TrajectoryOptimizer();
  TrajectoryOptimizer(TrajectoryOptimizer&&) noexcept;
  TrajectoryOptimizer& operator=(TrajectoryOptimizer&&) noexcept;

  /// Solves from the initial guess q_0..q_N (N + 1 configurations; q_0 is replaced by q_init).
  /// Always returns a summary; on failure *solution holds the last good iterate.
  SolverSummary Solve(const std::vector<Eigen::VectorXd>& q_guess, Trajectory* solution);

  /// Warm start (MPC): continues from the last solution and trust radius (and, with Lagrange
  /// multipliers, whether the last KKT step needed the double-double residual:
  /// BandedKktSolver::set_extended_first).
  SolverSummary SolveWarmStart(Trajectory* solution);
  /// Replace the initial condition (keeps the current iterate and trust radius).
  void ResetInitialConditions(const Eigen::VectorXd& q_init, const Eigen::VectorXd& v_init);
  /// Replace the nominal trajectory (N + 1 entries each).
  void UpdateNominalTrajectory(const std::vector<Eigen::VectorXd>& q_nom,
                               const std::vector<Eigen::VectorXd>& v_nom);
  /// Replace the current iterate (N + 1 configurations) without solving.
  void SetIterate(const std::vector<Eigen::VectorXd>& q);

  void AddCallback(IterationCallback callback);

  const ProblemDefinition& problem() const;
  const SolverOptions& options() const;
  SolverOptions& mutable_options();
  const Model& model() const;

  // ---- Evaluation, exposed for tests, tools and benchmarks. q: N + 1 configurations. ----
  /// L(q) (with the penalty term when the method is kPenalty).
  double EvalCost(const std::vector<Eigen::VectorXd>& q);
  /// tau_k for k = 0..N-1 and v_k for k = 0..N.
  void EvalTrajectory(const std::vector<Eigen::VectorXd>& q, Trajectory* trajectory);
  /// Gradient of L with respect to q_1..q_N (N nq).
  void EvalGradient(const std::vector<Eigen::VectorXd>& q, Eigen::VectorXd* g);
  /// Gauss-Newton Hessian as a dense matrix (N nq square; for tests).
  Eigen::MatrixXd EvalDenseHessian(const std::vector<Eigen::VectorXd>& q);
  /// h(q): the unactuated rows of tau_0..tau_{N-1} (N n_u).
  void EvalConstraints(const std::vector<Eigen::VectorXd>& q, Eigen::VectorXd* h);
  /// The last iterate's trust radius.
  double trust_radius() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace idto
