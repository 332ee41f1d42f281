#pragma once

// The trust-region strategy of the minimizer (paper §5.1, Nocedal & Wright ch. 4): diagonal
// scaling, the Levenberg-Marquardt shift that makes H factorable, the Cauchy point, the dogleg
// step, the radius update and the named convergence tests. Private to src/: small functions
// over preallocated vectors, no state of their own.

#include <cmath>
#include <string>

#include <Eigen/Core>

#include "idto/math/penta_diagonal_matrix.hpp"
#include "idto/solver/solver_options.hpp"
#include "idto/solver/solver_summary.hpp"
#include "math/split_penta_diagonal_cholesky.hpp"

namespace idto::internal {

// Smallest trust radius (scaled coordinates); reaching it means no progress is possible.
constexpr double kMinTrustRadius = 1e-12;

// The Lagrange route's growth guard (docs/solver.md, "Growth guard"): a trial point whose cost
// and constraint violation are both more than this many times the iterate's is rejected even
// when the merit L + h^T lambda says it is better. The merit's multipliers come from one KKT
// solve; where they are wrong by orders of magnitude (finite-difference derivatives at
// k = 2e8 N/m) the merit is dominated by h^T lambda and can prefer a point 1e5 times worse in
// both. Legitimate steps raise both by up to 1.3 on the examples' open-loop solves (the merit
// trades L against h^T lambda), where this never trips; in the Allegro hand's closed loop it
// trips on plan flicks that grow the cost 10-500 times (docs/solver.md).
constexpr double kGrowthGuardFactor = 10.0;

// Whether a trial point with cost trial_cost and violation trial_violation (sum of squared
// unactuated generalized forces) from an iterate with cost and violation grows both beyond
// kGrowthGuardFactor. Non-finite values never trip it (the ratio test handles them).
inline bool GrowthGuardTrips(double cost, double violation, double trial_cost,
                             double trial_violation) {
  return trial_cost > kGrowthGuardFactor * cost &&
         trial_violation > kGrowthGuardFactor * violation && std::isfinite(trial_cost) &&
         std::isfinite(trial_violation);
}

// D (N nq) from the Hessian's diagonal: diag(H)^(-1/2) or ^(-1/4), 1 where the diagonal is not
// positive and finite or scaling is off.
void CalcScaling(const PentaDiagonalMatrix& H, ScalingMethod method, Eigen::VectorXd* D);

// Factors *H with `factor()` (true on success: the penta-diagonal Cholesky of the penalty
// route, or the KKT factorization of the Lagrange route, which reads *H). A Gauss-Newton
// Hessian is positive semi-definite in exact arithmetic, but with stiff contact its entries span
// ~18 orders of magnitude and round-off can make it numerically indefinite (or a block
// singular). Then retries with H + mu diag(H) (scale invariant, a Levenberg-Marquardt shift),
// mu = 1e-12, 1e-10, ..., 1e-2; the shift stays in *H, so the step and the predicted reduction
// use the same model. *mu: the shift used. `diagonal` is scratch (N nq). False when even the
// largest shift fails.
template <typename Factor>
bool FactorWithShift(PentaDiagonalMatrix* H, Eigen::VectorXd* diagonal, double* mu,
                     const Factor& factor) {
  *mu = 0.0;
  if (factor()) return true;
  H->Diagonal(diagonal);
  const int N = H->num_blocks(), n = H->block_size();
  double applied = 0.0;
  for (double next = 1e-12; next <= 1e-2 * (1 + 1e-9); next *= 100.0) {
    for (int r = 0; r < N; ++r) {
      for (int i = 0; i < n; ++i) {
        const double d = (*diagonal)(r * n + i);
        // Rows without curvature get an absolute shift.
        H->C(r)(i, i) += (next - applied) * (d > 0.0 ? d : 1.0);
      }
    }
    applied = next;
    if (factor()) {
      *mu = applied;
      return true;
    }
  }
  return false;
}

// FactorWithShift with the penta-diagonal Cholesky (in two halves from the sizes of
// SplitPentaDiagonalCholesky).
bool FactorizeWithShift(PentaDiagonalMatrix* H, SplitPentaDiagonalCholesky* chol,
                        Eigen::VectorXd* diagonal, double* mu);

// The Cauchy point of the scaled model: p_C = -(|D g|^2 / (D^2 g)^T H (D^2 g)) D^2 g (or -D^2 g
// without positive curvature). Scratch d2g and Hd2g (N nq); H x by MultiplyInHalves.
void CalcCauchyPoint(const PentaDiagonalMatrix& H, const Eigen::VectorXd& g,
                     const Eigen::VectorXd& D, int num_threads, Eigen::VectorXd* d2g,
                     Eigen::VectorXd* Hd2g, Eigen::VectorXd* p_cauchy);

// y = H x with the block rows in two halves on up to two threads (from blocks of 8): the same
// result as H.Multiply on any thread count.
void MultiplyInHalves(const PentaDiagonalMatrix& H, const Eigen::VectorXd& x, int num_threads,
                      Eigen::VectorXd* y);

// The dogleg step in scaled coordinates (p = D p~) between the Cauchy and Newton points for
// trust radius `radius`; *p receives it and *scaled_norm |D^-1 p|. Scratch w, u (N nq).
DoglegStep CalcDoglegStep(const Eigen::VectorXd& p_newton, const Eigen::VectorXd& p_cauchy,
                          const Eigen::VectorXd& D, double radius, Eigen::VectorXd* w,
                          Eigen::VectorXd* u, Eigen::VectorXd* p, double* scaled_norm);

// The ratio of actual to predicted reduction; -inf when the trial merit is not finite or no
// reduction was predicted.
double ReductionRatio(double merit, double trial_merit, double predicted);

// Radius update (Nocedal & Wright, Algorithm 4.1): shrink to a quarter of the step when
// rho < 1/4; double (up to max_radius) when rho > 3/4 and the step reached the boundary.
double UpdateTrustRadius(double ratio, double scaled_step_norm, double radius, double max_radius);

// Convergence tests after an accepted step; on success *message says which one held.
bool CostChangeConverged(double previous, double cost, const SolverOptions& options,
                         std::string* message);
bool GradientConverged(double g_dot_p, double cost, const SolverOptions& options,
                       std::string* message);
bool StepConverged(double step_norm, double q_norm, const SolverOptions& options,
                   std::string* message);
// Near a stationary point the predicted reduction sinks to round-off and steps are rejected
// for noise: that is convergence, not failure.
bool PredictedReductionNegligible(double predicted, double merit);

}  // namespace idto::internal
