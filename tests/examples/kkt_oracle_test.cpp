// The Lagrange step of every example with unactuated DoFs, from the banded O(N) KKT solve the
// minimizer uses, against the dense formula lambda = (A H^-1 A^T)^-1 (h - A H^-1 g),
// p = -H^-1 (g + A^T lambda), at the initial guess and after 10 iterations. The reference is the
// dense formula in long double (64-bit mantissa). The banded solve must be within 1e-9 relative
// of it, or, where the problem's conditioning makes that impossible in double precision, at
// least as accurate as the dense formula evaluated in double (today's former route) up to a
// factor 10; and its backward error (the KKT residual, in long double) must be at round-off.
// Measured: forward 1e-12..7e-10 on acrobot, spinner, hopper and Allegro; up to 1.3e-8 on the
// quadruped and bimanual move (dense in double: up to 3e-8); 4e-6 on bimanual_balance (dense in
// double 6e-7 to 2e-5); backward error below 1e-17 everywhere.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "idto/idto.hpp"
#include "solver/trust_region.hpp"

namespace idto {
namespace {

const std::vector<std::string> kShareDirs = {IDTO_SOURCE_DIR};

struct Step {
  Eigen::VectorXd p, lambda;
};

// H (shifted as the minimizer shifts it), A and the two solutions at iterate q.
void CompareAt(const ExampleConfig& config, const std::vector<Eigen::VectorXd>& q) {
  Transcription t(config.model, config.problem);
  TrajectoryState state = t.MakeState();
  state.q = q;
  t.Evaluate(&state);
  TrajectoryDerivatives d = t.MakeDerivatives();
  t.CalcDerivatives(state, &d);
  const int N = t.num_steps(), n = t.nq(), nu = t.num_unactuated();
  Eigen::VectorXd g(N * n), h(N * nu), diagonal(N * n);
  t.CalcGradient(state, d, &g);
  t.CalcConstraints(state, &h);
  PentaDiagonalMatrix H(N, n);
  t.CalcHessian(state, d, &H);
  PentaDiagonalCholesky chol(N, n);
  double mu = 0.0;
  ASSERT_TRUE(internal::FactorizeWithShift(&H, &chol, &diagonal, &mu));

  BlockConstraintJacobian A(N, n, nu);
  for (int j = 0; j < N; ++j) {
    for (int s = std::max(j - 1, 1); s <= std::min(j + 1, N); ++s) {
      t.ConstraintBlock(d, j, s, A.Block(j, s));
    }
  }
  BandedKktSolver kkt(N, n, nu);
  const KktStatus status = kkt.Factor(H, A);
  ASSERT_TRUE(status.ok()) << status.Message();
  Step banded;
  kkt.Solve(g, h, &banded.p, &banded.lambda);

  using MatrixXld = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  using VectorXld = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
  Eigen::MatrixXd At(N * n, N * nu);
  t.CalcDenseConstraintJacobianTranspose(d, &At);
  const MatrixXld Hl = H.MakeDense().cast<long double>(), Atl = At.cast<long double>();
  const VectorXld gl = g.cast<long double>(), hl = h.cast<long double>();
  const Eigen::LLT<MatrixXld> Hllt(Hl);
  const MatrixXld S = Atl.transpose() * Hllt.solve(Atl);
  const VectorXld lambda = S.llt().solve(hl - Atl.transpose() * Hllt.solve(gl));
  Step dense;
  dense.lambda = lambda.cast<double>();
  dense.p = (-Hllt.solve(gl + Atl * lambda)).cast<double>();
  // The same formula in double.
  const Eigen::MatrixXd Hd = H.MakeDense();
  const Eigen::LLT<Eigen::MatrixXd> Hllt_d(Hd);
  const Eigen::MatrixXd S_d = At.transpose() * Hllt_d.solve(At);
  Step dense_double;
  dense_double.lambda = S_d.llt().solve(h - At.transpose() * Hllt_d.solve(g));
  dense_double.p = -Hllt_d.solve(g + At * dense_double.lambda);
  auto error = [](const Eigen::VectorXd& x, const Eigen::VectorXd& reference) {
    return (x - reference).norm() / reference.norm();
  };
  const double e_lambda = error(banded.lambda, dense.lambda);
  const double e_p = error(banded.p, dense.p);
  const double e_lambda_double = error(dense_double.lambda, dense.lambda);
  const double e_p_double = error(dense_double.p, dense.p);
  // Backward error of a candidate (p, lambda), evaluated in long double: the relative residual
  // of the KKT system. A backward-stable solver keeps it near round-off whatever the
  // conditioning; the forward error above is then bounded by the conditioning.
  auto backward = [&](const Step& x) {
    const VectorXld p = x.p.cast<long double>(), l = x.lambda.cast<long double>();
    const VectorXld r1 = Hl * p + Atl * l + gl, r2 = Atl.transpose() * p + hl;
    const long double scale =
        Hl.norm() * p.norm() + Atl.norm() * (l.norm() + p.norm()) + gl.norm() + hl.norm();
    return static_cast<double>(std::sqrt(r1.squaredNorm() + r2.squaredNorm()) / scale);
  };
  const double b = backward(banded), b_double = backward(dense_double);
  EXPECT_LE(b, 1e-14) << "dense in double: " << b_double;
  // Forward error: 1e-9, or within 10x of the dense route in double where conditioning makes
  // 1e-9 impossible for any double-precision solve (bimanual_balance: both ~1e-6).
  EXPECT_LE(e_lambda, std::max(1e-9, 10.0 * e_lambda_double))
      << "dense in double: " << e_lambda_double;
  EXPECT_LE(e_p, std::max(1e-9, 10.0 * e_p_double)) << "dense in double: " << e_p_double;
  std::printf(
      "[ kkt ] lambda %.2e (dense in double %.2e), p %.2e (%.2e); backward error %.2e (%.2e)\n",
      e_lambda, e_lambda_double, e_p, e_p_double, b, b_double);
}

class KktOracle : public ::testing::TestWithParam<std::string> {};

TEST_P(KktOracle, BandedStepEqualsTheDenseFormula) {
  ExampleConfig config = LoadExampleConfig(FindExampleConfig(GetParam(), kShareDirs), kShareDirs);
  ASSERT_GT(config.problem.UnactuatedDofs(config.model).size(), 0u);
  const std::vector<Eigen::VectorXd> guess = MakeInitialGuess(config);
  {
    SCOPED_TRACE("initial guess");
    CompareAt(config, guess);
  }
  config.solver.max_iterations = 10;
  config.solver.constraint_method = ConstraintMethod::kLagrangeMultipliers;
  TrajectoryOptimizer optimizer(config.model, config.problem, config.solver);
  Trajectory solution;
  optimizer.Solve(guess, &solution);
  SCOPED_TRACE("after 10 iterations");
  CompareAt(config, solution.q);
}

INSTANTIATE_TEST_SUITE_P(Examples, KktOracle,
                         ::testing::Values("acrobot", "spinner", "hopper", "quadruped",
                                           "quadruped_hills", "allegro", "bimanual",
                                           "bimanual_lift", "bimanual_balance"));

}  // namespace
}  // namespace idto
