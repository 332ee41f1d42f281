// The Lagrange step of every example with unactuated DoFs, from the banded O(N) KKT solve the
// minimizer uses, against the dense formula lambda = (A H^-1 A^T)^-1 (h - A H^-1 g),
// p = -H^-1 (g + A^T lambda): 1e-9 relative, at the initial guess and after 10 iterations. The
// dense formula is evaluated in long double (64-bit mantissa): in double its own error reaches
// 1e-8 on the stiff examples (cond(A H^-1 A^T) ~ 1e8), more than the banded solve's.

#include <gtest/gtest.h>

#include <algorithm>
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
  EXPECT_LE((banded.lambda - dense.lambda).norm(), 1e-9 * dense.lambda.norm())
      << (banded.lambda - dense.lambda).norm() / dense.lambda.norm();
  EXPECT_LE((banded.p - dense.p).norm(), 1e-9 * dense.p.norm())
      << (banded.p - dense.p).norm() / dense.p.norm();
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
                         ::testing::Values("acrobot", "spinner", "hopper", "quadruped", "quadruped_hills", "allegro",
                                           "bimanual", "bimanual_lift", "bimanual_balance"));

}  // namespace
}  // namespace idto
