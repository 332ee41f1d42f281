// The Lagrange step of every example with unactuated DoFs, from the banded O(N) KKT solve the
// minimizer uses, against the dense formula lambda = (A H^-1 A^T)^-1 (h - A H^-1 g),
// p = -H^-1 (g + A^T lambda), at the initial guess and after 10 iterations. The reference is the
// dense formula in long double (64-bit mantissa), refined against the KKT residual evaluated in
// __float128 (113-bit mantissa) until it no longer moves: on the bimanual lift and balance the
// condition number (~1e10) leaves the long-double formula itself ~1e-9 off, which would hide the
// banded solve's accuracy. Checked: the minimizer's default (refinement residual in double, plus
// one step with the residual in double-double when the first correction exceeds 1e-11) against
// 1e-10 relative; the residual in double alone against 1e-9, or 10x the dense formula in double
// where the conditioning forbids 1e-9;
// BandedKktSolver::set_extended_residual(true) (double-double residual, two refinement steps)
// against 1e-12 on every example; and their backward error (the KKT residual, in long double)
// at round-off. The dense formula in double (the former route) is printed beside them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "examples/example_test_support.hpp"
#include "idto/idto.hpp"
#include "solver/trust_region.hpp"

namespace idto {
namespace {

using test::kShareDirs;

struct Step {
  Eigen::VectorXd p, lambda;
};

__extension__ typedef __float128 Quad;  // GCC's quadruple precision (software)
using MatrixXld = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
using VectorXld = Eigen::Matrix<long double, Eigen::Dynamic, 1>;

// The solution of [H A^T; A 0][p; lambda] = -[g; h] from a long-double start (p0, lambda0),
// refined with residuals in __float128 and corrections from the long-double factors (the
// Cholesky of H and of S = A H^-1 A^T): each step divides the error by ~1/(cond * 1e-19) until
// it reaches quadruple round-off times the condition number.
Step RefinedReference(const Eigen::MatrixXd& H, const Eigen::MatrixXd& At, const Eigen::VectorXd& g,
                      const Eigen::VectorXd& h, const Eigen::LLT<MatrixXld>& Hllt,
                      const Eigen::LLT<MatrixXld>& Sllt, const VectorXld& lambda0,
                      const VectorXld& p0) {
  const int np = static_cast<int>(H.rows()), nl = static_cast<int>(At.cols());
  std::vector<Quad> p(np), l(nl);
  for (int i = 0; i < np; ++i) p[i] = p0(i);
  for (int i = 0; i < nl; ++i) l[i] = lambda0(i);
  const MatrixXld Atl = At.cast<long double>();
  for (int step = 0; step < 4; ++step) {
    VectorXld r1(np), r2(nl);  // -g - H p - A^T lambda, -h - A p
    for (int i = 0; i < np; ++i) {
      Quad sum = -static_cast<Quad>(g(i));
      for (int j = 0; j < np; ++j) sum -= static_cast<Quad>(H(i, j)) * p[j];
      for (int j = 0; j < nl; ++j) sum -= static_cast<Quad>(At(i, j)) * l[j];
      r1(i) = static_cast<long double>(sum);
    }
    for (int j = 0; j < nl; ++j) {
      Quad sum = -static_cast<Quad>(h(j));
      for (int i = 0; i < np; ++i) sum -= static_cast<Quad>(At(i, j)) * p[i];
      r2(j) = static_cast<long double>(sum);
    }
    // [H A^T; A 0][dp; dl] = [r1; r2]: dl = S^-1 (A H^-1 r1 - r2), dp = H^-1 (r1 - A^T dl).
    const VectorXld dl = Sllt.solve(Atl.transpose() * Hllt.solve(r1) - r2);
    const VectorXld dp = Hllt.solve(r1 - Atl * dl);
    for (int i = 0; i < np; ++i) p[i] += dp(i);
    for (int i = 0; i < nl; ++i) l[i] += dl(i);
  }
  Step out;
  out.p.resize(np);
  out.lambda.resize(nl);
  for (int i = 0; i < np; ++i) out.p(i) = static_cast<double>(p[i]);
  for (int i = 0; i < nl; ++i) out.lambda(i) = static_cast<double>(l[i]);
  return out;
}

// The banded solver's solutions of one KKT system, in its four modes.
struct BandedSteps {
  Step banded;                    // the default: adaptive double-double refinement step
  Step first;                     // the double-double step first (the minimizer's hint)
  Step plain;                     // the refinement residual in double only
  Step extended;                  // the residual in double-double always
  bool adaptive_extended{false};  // the default took the double-double step
};

// Compares the banded solutions x of [H A^T; A 0][p; lambda] = -[g; h] (At = A^T, dense) with the
// dense formula refined in long double.
void CheckAgainstDense(const PentaDiagonalMatrix& H, const Eigen::MatrixXd& At,
                       const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                       const BandedSteps& steps);

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
  internal::SplitPentaDiagonalCholesky chol(N, n, 1);
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
  // Blocks of 8 and more over 8 and more steps: the two-half order, with no fallback.
  EXPECT_EQ(kkt.factored_in_two_halves(), n + nu >= BandedKktSolver::kTwoHalfMinBlock && N >= 8);
  BandedSteps x;
  kkt.Solve(g, h, &x.banded.p, &x.banded.lambda);
  x.adaptive_extended = kkt.last_solve_extended();
  // The minimizer's hint after an iteration that needed the double-double step.
  kkt.set_extended_first(true);
  kkt.Solve(g, h, &x.first.p, &x.first.lambda);
  EXPECT_TRUE(kkt.last_solve_extended());
  kkt.set_extended_first(false);
  // Without the adaptive double-double step: the refinement residual in double only.
  kkt.set_extended_threshold(std::numeric_limits<double>::infinity());
  kkt.Solve(g, h, &x.plain.p, &x.plain.lambda);
  EXPECT_FALSE(kkt.last_solve_extended());
  kkt.set_extended_residual(true);
  kkt.Solve(g, h, &x.extended.p, &x.extended.lambda);
  Eigen::MatrixXd At(N * n, N * nu);
  t.CalcDenseConstraintJacobianTranspose(d, &At);
  CheckAgainstDense(H, At, g, h, x);
}

void CheckAgainstDense(const PentaDiagonalMatrix& H, const Eigen::MatrixXd& At,
                       const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                       const BandedSteps& steps) {
  const Step& banded = steps.banded;
  const Step& extended = steps.extended;
  const Step& plain = steps.plain;
  const Step& first = steps.first;
  const bool adaptive_extended = steps.adaptive_extended;
  const MatrixXld Hl = H.MakeDense().cast<long double>(), Atl = At.cast<long double>();
  const VectorXld gl = g.cast<long double>(), hl = h.cast<long double>();
  const Eigen::LLT<MatrixXld> Hllt(Hl);
  const MatrixXld S = Atl.transpose() * Hllt.solve(Atl);
  const VectorXld lambda = S.llt().solve(hl - Atl.transpose() * Hllt.solve(gl));
  const VectorXld p_long = -Hllt.solve(gl + Atl * lambda);
  Step dense = RefinedReference(H.MakeDense(), At, g, h, Hllt, S.llt(), lambda, p_long);
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
  const double e_lambda_extended = error(extended.lambda, dense.lambda);
  const double e_p_extended = error(extended.p, dense.p);
  const double e_lambda_double = error(dense_double.lambda, dense.lambda);
  const double e_p_double = error(dense_double.p, dense.p);
  const double e_lambda_long = error(lambda.cast<double>(), dense.lambda);
  const double e_p_long = error(p_long.cast<double>(), dense.p);
  // Backward error of a candidate (p, lambda), evaluated in long double: the relative residual
  // of the KKT system. A backward-stable solver keeps it near round-off whatever the
  // conditioning; the forward error is then bounded by the conditioning.
  auto backward = [&](const Step& x) {
    const VectorXld p = x.p.cast<long double>(), l = x.lambda.cast<long double>();
    const VectorXld r1 = Hl * p + Atl * l + gl, r2 = Atl.transpose() * p + hl;
    const long double scale =
        Hl.norm() * p.norm() + Atl.norm() * (l.norm() + p.norm()) + gl.norm() + hl.norm();
    return static_cast<double>(std::sqrt(r1.squaredNorm() + r2.squaredNorm()) / scale);
  };
  const double b = backward(banded), b_double = backward(dense_double);
  EXPECT_LE(b, 1e-14) << "dense in double: " << b_double;
  EXPECT_LE(backward(extended), 1e-14);
  // The default: 1e-10 on every example. The refinement residual in double alone is up to
  // ~1e-6 off where the conditioning is ~1e10 (bimanual lift and balance) and ~1e-8 on the
  // quadruped, as the dense formula in double is; a first correction above 1e-11 adds one step
  // with the residual in double-double.
  const double e_lambda_plain = error(plain.lambda, dense.lambda);
  const double e_p_plain = error(plain.p, dense.p);
  EXPECT_LE(e_lambda, 1e-10) << "residual in double only: " << e_lambda_plain;
  EXPECT_LE(e_p, 1e-10) << "residual in double only: " << e_p_plain;
  const double e_lambda_first = error(first.lambda, dense.lambda);
  const double e_p_first = error(first.p, dense.p);
  EXPECT_LE(e_lambda_first, 1e-10);
  EXPECT_LE(e_p_first, 1e-10);
  EXPECT_LE(e_lambda_plain, std::max(1e-9, 10.0 * e_lambda_double))
      << "double: " << e_lambda_double;
  EXPECT_LE(e_p_plain, std::max(1e-9, 10.0 * e_p_double)) << "double: " << e_p_double;
  // With the residual in double-double: 1e-12 everywhere, also where the conditioning (~1e10 on
  // the bimanual lift and balance) puts the dense formula in long double ~1e-9 off (measured:
  // below 1e-15; with a long-double residual it was 1.5e-9 to 6e-9 there).
  EXPECT_LE(e_lambda_extended, 1e-12) << "long double: " << e_lambda_long;
  EXPECT_LE(e_p_extended, 1e-12) << "long double: " << e_p_long;
  std::printf(
      "[ kkt ] lambda %.2e%s, extended first %.2e, residual in double only %.2e, extended %.2e "
      "(dense formula in double %.2e, in long double %.2e); p %.2e, %.2e, %.2e, extended %.2e "
      "(%.2e, %.2e); backward error %.2e (%.2e)\n",
      e_lambda, adaptive_extended ? " (adaptive double-double step)" : "", e_lambda_first,
      e_lambda_plain, e_lambda_extended, e_lambda_double, e_lambda_long, e_p, e_p_first, e_p_plain,
      e_p_extended, e_p_double, e_p_long, b, b_double);
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
