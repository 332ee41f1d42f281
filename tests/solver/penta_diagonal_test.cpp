// The block-pentadiagonal factorization against dense Eigen, up to condition numbers of 1e12.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "idto/core/errors.hpp"
#include "idto/math/penta_diagonal_matrix.hpp"
#include "math/split_penta_diagonal_cholesky.hpp"
#include "solver/banded_test_support.hpp"
#include "support/eigen_matchers.hpp"
#include "support/kernel_paths.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

// A random SPD pentadiagonal matrix: L D Lᵀ with L block-banded and D spanning [1, condition]
// on a log scale (test::RandomBandedSpd), stored by blocks.
PentaDiagonalMatrix RandomSpd(int N, int n, double condition, test::Random* rng) {
  const Eigen::MatrixXd Hd = test::RandomBandedSpd(N, n, condition, rng);
  PentaDiagonalMatrix H(N, n);
  for (int k = 0; k < N; ++k) {
    H.C(k) = Hd.block(k * n, k * n, n, n);
    H.C(k) = 0.5 * (H.C(k) + H.C(k).transpose()).eval();
    if (k >= 1) H.B(k) = Hd.block(k * n, (k - 1) * n, n, n);
    if (k >= 2) H.A(k) = Hd.block(k * n, (k - 2) * n, n, n);
  }
  return H;
}

// The factorizations run on both paths of the block kernels (support/kernel_paths.hpp).
class PentaDiagonalCholeskyTest : public test::KernelPathTest {};
IDTO_INSTANTIATE_KERNEL_PATHS(PentaDiagonalCholeskyTest);
class SplitPentaDiagonalTest : public test::KernelPathTest {};
IDTO_INSTANTIATE_KERNEL_PATHS(SplitPentaDiagonalTest);

// Blocks of 1-6 rows take fixed-size products, larger ones Eigen's: every size against the dense
// product.
TEST(PentaDiagonal, MultiplyAndDenseAgree) {
  test::Random rng(1);
  for (int n : {1, 2, 3, 4, 5, 6, 7, 9}) {
    SCOPED_TRACE(::testing::Message() << "n=" << n);
    const PentaDiagonalMatrix H = RandomSpd(7, n, 1e3, &rng);
    const Eigen::MatrixXd D = H.MakeDense();
    const Eigen::VectorXd x = rng.Vector(7 * n);
    Eigen::VectorXd y;
    H.Multiply(x, &y);
    EXPECT_EIGEN_NEAR_REL(y, Eigen::VectorXd(D * x), 1e-13);
    // Block rows computed separately (as on two threads) give bitwise the same product.
    Eigen::VectorXd y_rows = Eigen::VectorXd::Zero(7 * n);
    H.MultiplyRows(x, 4, 7, &y_rows);
    H.MultiplyRows(x, 0, 4, &y_rows);
    EXPECT_EQ(y_rows, y);
    // Zero outside the band.
    EXPECT_EQ(D.block(3 * n, 0, n, n).norm(), 0.0);
  }
}

TEST_P(PentaDiagonalCholeskyTest, CholeskySolvesLikeDenseUpToConditionNumber1e12) {
  test::Random rng(2);
  for (double condition : {1.0, 1e3, 1e6, 1e9, 1e12}) {
    for (auto [N, n] :
         {std::pair{1, 4}, std::pair{2, 3}, std::pair{10, 6}, std::pair{40, 2}, std::pair{5, 19},
          std::pair{9, 1}, std::pair{12, 5}, std::pair{6, 7}, std::pair{3, 1}}) {
      SCOPED_TRACE(::testing::Message() << "cond=" << condition << " N=" << N << " n=" << n);
      const PentaDiagonalMatrix H = RandomSpd(N, n, condition, &rng);
      const Eigen::MatrixXd D = H.MakeDense();
      const Eigen::VectorXd b = rng.Vector(N * n);
      PentaDiagonalCholesky chol(N, n);
      chol.compute(H);
      ASSERT_EQ(chol.info(), PentaDiagonalCholesky::Info::kSuccess);
      Eigen::VectorXd x = b;
      chol.SolveInPlace(&x);
      // Backward stable: the residual is small relative to |H| |x|.
      const double residual = (D * x - b).norm() / (D.norm() * x.norm() + b.norm());
      EXPECT_LT(residual, 1e-14);
      const Eigen::VectorXd x_dense = D.llt().solve(b);
      const double cond = 1.0 / D.llt().rcond();
      EXPECT_LT((x - x_dense).norm() / x_dense.norm(), 1e-15 * cond + 1e-12);
      // Several right-hand sides at once.
      Eigen::MatrixXd X = rng.Matrix(N * n, 3);
      const Eigen::MatrixXd Bm = X;
      chol.SolveInPlace(&X);
      EXPECT_LT((D * X - Bm).norm() / (D.norm() * X.norm() + Bm.norm()), 1e-14);
    }
  }
}

TEST_P(PentaDiagonalCholeskyTest, ForwardSolveGivesTheEnergyNormAndSkipsLeadingZeroBlocks) {
  test::Random rng(5);
  const int N = 12, n = 3;
  const PentaDiagonalMatrix H = RandomSpd(N, n, 1e4, &rng);
  PentaDiagonalCholesky chol(N, n);
  chol.compute(H);
  ASSERT_EQ(chol.info(), PentaDiagonalCholesky::Info::kSuccess);
  const Eigen::MatrixXd D = H.MakeDense();
  // |L^-1 b|^2 = b^T H^-1 b, whatever the factor.
  Eigen::VectorXd b = rng.Vector(N * n);
  Eigen::VectorXd y = b;
  chol.SolveLowerInPlace(&y);
  EXPECT_NEAR(y.squaredNorm(), b.dot(D.llt().solve(b)), 1e-10 * y.squaredNorm());
  // Columns that are zero above block 5: starting there gives the full forward solve.
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(N * n, 4);
  B.bottomRows((N - 5) * n) = rng.Matrix((N - 5) * n, 4);
  Eigen::MatrixXd full = B, skipped = B;
  chol.SolveLowerInPlace(full, 0);
  chol.SolveLowerInPlace(skipped.middleCols(0, 4), 5);
  EXPECT_EIGEN_NEAR(skipped, full, 1e-13);
  // Y^T Y = B^T H^-1 B (the multiplier step's Schur complement).
  EXPECT_EIGEN_NEAR(Eigen::MatrixXd(full.transpose() * full),
                    Eigen::MatrixXd(B.transpose() * D.llt().solve(B)), 1e-9);
}

TEST_P(PentaDiagonalCholeskyTest, IndefiniteMatricesReportTheFailedBlock) {
  test::Random rng(3);
  PentaDiagonalMatrix H = RandomSpd(5, 2, 10.0, &rng);
  H.C(3)(1, 1) = -1e3;
  PentaDiagonalCholesky chol(5, 2);
  chol.compute(H);
  EXPECT_EQ(chol.info(), PentaDiagonalCholesky::Info::kNumericalIssue);
  EXPECT_EQ(chol.failed_block(), 3);
  H.C(1)(0, 0) = std::nan("");
  chol.compute(H);
  EXPECT_EQ(chol.info(), PentaDiagonalCholesky::Info::kNumericalIssue);
  EXPECT_EQ(chol.failed_block(), 1);
}

TEST(PentaDiagonal, ScaleSymmetricIsDHD) {
  test::Random rng(4);
  PentaDiagonalMatrix H = RandomSpd(6, 3, 1e2, &rng);
  const Eigen::MatrixXd before = H.MakeDense();
  const Eigen::VectorXd d = rng.Vector(18, 0.5, 2.0);
  H.ScaleSymmetric(d);
  EXPECT_EIGEN_NEAR_REL(H.MakeDense(), Eigen::MatrixXd(d.asDiagonal() * before * d.asDiagonal()),
                        1e-14);
  Eigen::VectorXd diag;
  H.Diagonal(&diag);
  EXPECT_EIGEN_NEAR(diag, Eigen::VectorXd(H.MakeDense().diagonal()), 0.0);
}

using internal::SplitPentaDiagonalCholesky;

// The two-half factorization (the penalty route's Newton step) against dense Eigen, on sizes
// below and above the split thresholds and every horizon from 1 to 21 (both parities of the
// halves, the smallest split horizon 8 with halves of 3).
TEST_P(SplitPentaDiagonalTest, SolvesLikeDenseOnEverySplit) {
  test::Random rng(6);
  for (int n : {2, SplitPentaDiagonalCholesky::kMinBlockSize, 11, 19}) {
    for (int N = 1; N <= 21; ++N) {
      for (double condition : {1.0, 1e6, 1e12}) {
        SCOPED_TRACE(::testing::Message() << "cond=" << condition << " N=" << N << " n=" << n);
        const PentaDiagonalMatrix H = RandomSpd(N, n, condition, &rng);
        const Eigen::MatrixXd D = H.MakeDense();
        const Eigen::VectorXd b = rng.Vector(N * n);
        SplitPentaDiagonalCholesky chol(N, n, 2);
        EXPECT_EQ(chol.two_halves(), N >= SplitPentaDiagonalCholesky::kMinBlocks &&
                                         n >= SplitPentaDiagonalCholesky::kMinBlockSize);
        ASSERT_TRUE(chol.compute(H));
        EXPECT_EQ(chol.failed_block(), -1);
        Eigen::VectorXd x = b;
        chol.SolveInPlace(&x);
        EXPECT_LT((D * x - b).norm() / (D.norm() * x.norm() + b.norm()), 1e-14);
        const Eigen::VectorXd x_dense = D.llt().solve(b);
        const double cond = 1.0 / D.llt().rcond();
        EXPECT_LT((x - x_dense).norm() / x_dense.norm(), 1e-15 * cond + 1e-12);
      }
    }
  }
}

TEST_P(SplitPentaDiagonalTest, OneAndTwoThreadsAreBitwiseEqual) {
  test::Random rng(7);
  const int N = 20, n = 12;
  const PentaDiagonalMatrix H = RandomSpd(N, n, 1e8, &rng);
  const Eigen::VectorXd b = rng.Vector(N * n);
  SplitPentaDiagonalCholesky one(N, n, 1), two(N, n, 2);
  ASSERT_TRUE(one.two_halves());
  ASSERT_TRUE(one.compute(H));
  Eigen::VectorXd x1 = b;
  one.SolveInPlace(&x1);
  for (int repeat = 0; repeat < 20; ++repeat) {
    ASSERT_TRUE(two.compute(H));
    Eigen::VectorXd x2 = b;
    two.SolveInPlace(&x2);
    ASSERT_EQ(x1, x2) << "repeat " << repeat;
  }
  // set_num_threads switches between them; the result stays the same.
  one.set_num_threads(2);
  ASSERT_TRUE(one.compute(H));
  Eigen::VectorXd x3 = b;
  one.SolveInPlace(&x3);
  EXPECT_EQ(x1, x3);
  EXPECT_THROW(one.set_num_threads(0), InvalidArgument);
}

// A pivot that is not positive definite in the top half, the bottom half or either separator
// block is reported with its block row, on one and two threads; an SPD matrix factors again
// afterwards.
TEST_P(SplitPentaDiagonalTest, ReportsTheFailedBlockInEitherHalfAndTheSeparator) {
  test::Random rng(8);
  const int N = 12, n = 8;  // s = 5: top 0..4, separator 5 and 6, bottom 11..7
  const PentaDiagonalMatrix good = RandomSpd(N, n, 10.0, &rng);
  for (int threads : {1, 2}) {
    for (int block : {0, 3, 5, 6, 8, 11}) {
      SCOPED_TRACE(::testing::Message() << "threads=" << threads << " block=" << block);
      PentaDiagonalMatrix H = good;
      H.C(block)(2, 2) = -1e4;
      SplitPentaDiagonalCholesky chol(N, n, threads);
      EXPECT_FALSE(chol.compute(H));
      EXPECT_EQ(chol.failed_block(), block);
      H.C(block)(2, 2) = std::nan("");
      EXPECT_FALSE(chol.compute(H));
      EXPECT_EQ(chol.failed_block(), block);
      ASSERT_TRUE(chol.compute(good));
      EXPECT_EQ(chol.failed_block(), -1);
    }
    // Both halves fail: the top's block is the one reported.
    PentaDiagonalMatrix H = good;
    H.C(2)(0, 0) = -1e4;
    H.C(9)(0, 0) = -1e4;
    SplitPentaDiagonalCholesky chol(N, n, threads);
    EXPECT_FALSE(chol.compute(H));
    EXPECT_EQ(chol.failed_block(), 2);
  }
}

TEST(SplitPentaDiagonal, RejectsBadSizes) {
  SplitPentaDiagonalCholesky chol(10, 8, 1);
  EXPECT_THROW(chol.compute(PentaDiagonalMatrix(10, 7)), InvalidArgument);
  EXPECT_THROW(SplitPentaDiagonalCholesky(-1, 8, 1), InvalidArgument);
  EXPECT_THROW(SplitPentaDiagonalCholesky(10, 8, 0), InvalidArgument);
}

}  // namespace
}  // namespace idto
