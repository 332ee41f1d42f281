// BandedKktSolver::SolveUnrefined (the solver's constraint correction): one forward and one
// backward sweep, against the dense long-double oracle and the refined Solve; the status and
// size rules of Solve; no allocation; bitwise equal on 1 and 2 threads.

#include <cstring>
#include <tuple>

#include <gtest/gtest.h>

#include "idto/core/errors.hpp"
#include "solver/banded_test_support.hpp"
#include "support/allocation_counter.hpp"

namespace idto {
namespace {

double RelativeError(const Eigen::VectorXd& x, const Eigen::VectorXd& reference) {
  return (x - reference).norm() / std::max(reference.norm(), 1e-300);
}

// Well-conditioned systems (κ(H) = 100): one sweep is within ~κ ε of the exact solution, as the
// refined solve is; with g = 0 (the correction's right-hand side) too.
TEST(KktUnrefined, MatchesTheDenseOracleAndTheRefinedSolve) {
  test::Random rng(31);
  for (auto [N, n, nu, threads] : {std::tuple{12, 3, 1, 1}, std::tuple{20, 4, 2, 2},
                                   std::tuple{10, 23, 6, 1}, std::tuple{10, 23, 6, 2}}) {
    SCOPED_TRACE(::testing::Message()
                 << "N=" << N << " n=" << n << " nu=" << nu << " threads=" << threads);
    test::KktProblem P = test::RandomProblem(N, n, nu, 100.0, 1.0, &rng);
    for (const bool zero_gradient : {false, true}) {
      if (zero_gradient) P.g.setZero();
      BandedKktSolver kkt(N, n, nu);
      kkt.set_num_threads(threads);
      ASSERT_TRUE(kkt.Factor(P.H, P.A).ok());
      Eigen::VectorXd p, lambda, p_refined, lambda_refined, p_oracle, lambda_oracle;
      kkt.SolveUnrefined(P.g, P.h, &p, &lambda);
      kkt.Solve(P.g, P.h, &p_refined, &lambda_refined);
      test::DenseOracle(P, &p_oracle, &lambda_oracle);
      EXPECT_LT(RelativeError(p, p_oracle), 1e-11);
      EXPECT_LT(RelativeError(lambda, lambda_oracle), 1e-11);
      EXPECT_LT(RelativeError(p, p_refined), 1e-11);
      // The constraint rows hold: A p = −h.
      Eigen::VectorXd Ap;
      P.A.Multiply(p, &Ap);
      EXPECT_LT((Ap + P.h).norm(), 1e-11 * std::max(1.0, P.h.norm()));
    }
  }
}

TEST(KktUnrefined, StatusAndSizesFollowSolve) {
  test::Random rng(32);
  const int N = 6, n = 3, nu = 1;
  test::KktProblem P = test::RandomProblem(N, n, nu, 10.0, 1.0, &rng);
  BandedKktSolver kkt(N, n, nu);
  ASSERT_TRUE(kkt.Factor(P.H, P.A).ok());
  Eigen::VectorXd p, lambda;
  EXPECT_THROW(kkt.SolveUnrefined(Eigen::VectorXd::Zero(N * n + 1), P.h, &p, &lambda),
               InvalidArgument);
  EXPECT_THROW(kkt.SolveUnrefined(P.g, Eigen::VectorXd::Zero(N * nu - 1), &p, &lambda),
               InvalidArgument);
  // A failed factorization (an indefinite H): zeros, never NaN.
  P.H.C(2) = -P.H.C(2);
  ASSERT_FALSE(kkt.Factor(P.H, P.A).ok());
  p = Eigen::VectorXd::Constant(N * n, 7.0);
  kkt.SolveUnrefined(P.g, P.h, &p, &lambda);
  EXPECT_TRUE(p.isZero(0.0));
  EXPECT_TRUE(lambda.isZero(0.0));
  EXPECT_EQ(lambda.size(), N * nu);
}

TEST(KktUnrefined, NoAllocationAndBitwiseEqualOnOneAndTwoThreads) {
  test::Random rng(33);
  const int N = 10, n = 23, nu = 6;  // two halves (block size 29)
  const test::KktProblem P = test::RandomProblem(N, n, nu, 100.0, 1.0, &rng);
  Eigen::VectorXd p[2], lambda[2];
  for (int threads = 1; threads <= 2; ++threads) {
    BandedKktSolver kkt(N, n, nu);
    kkt.set_num_threads(threads);
    ASSERT_TRUE(kkt.Factor(P.H, P.A).ok());
    Eigen::VectorXd& pt = p[threads - 1];
    Eigen::VectorXd& lt = lambda[threads - 1];
    pt.resize(N * n);
    lt.resize(N * nu);
    kkt.SolveUnrefined(P.g, P.h, &pt, &lt);  // the process's thread pool starts on first use
    if (test::AllocationCountingAvailable()) {
      test::ScopedAllocationCounter counter;
      kkt.SolveUnrefined(P.g, P.h, &pt, &lt);
      EXPECT_EQ(counter.count(), 0);
    }
  }
  EXPECT_EQ(std::memcmp(p[0].data(), p[1].data(), sizeof(double) * p[0].size()), 0);
  EXPECT_EQ(std::memcmp(lambda[0].data(), lambda[1].data(), sizeof(double) * lambda[0].size()), 0);
}

}  // namespace
}  // namespace idto
