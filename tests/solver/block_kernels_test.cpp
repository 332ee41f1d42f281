// The AVX2/FMA block kernels (src/math/block_kernels.hpp) against Eigen's dense products,
// triangular solves and Cholesky factorization, on every tile shape: sizes 1 to 33 (row tails
// of 1 to 7 and column tails of 1 to 3), leading dimensions larger than the rows, and checks
// that nothing outside the written part of C changes.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "math/block_kernels.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

namespace avx2 = internal::avx2;

class Avx2BlockKernels : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!internal::Avx2KernelsAvailable()) {
      GTEST_SKIP() << "this CPU has no AVX2 and FMA: the kernels under test cannot run here";
    }
  }
};

// Columns of a matrix with a leading dimension `ld` >= rows: the rows below are padding.
Eigen::MatrixXd Padded(const Eigen::MatrixXd& X, int ld, test::Random* rng) {
  Eigen::MatrixXd P = rng->Matrix(ld, X.cols());
  P.topRows(X.rows()) = X;
  return P;
}

TEST_F(Avx2BlockKernels, ProductNTMatchesEigenOnEveryTileShape) {
  test::Random rng(11);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int m : {1, 3, 4, 5, 8, 9, 12, 19, 23, 33}) {
    for (int n : {1, 2, 3, 4, 5, 7, 19}) {
      for (int k : {0, 1, 6, 19, 54}) {
        SCOPED_TRACE(::testing::Message() << "m=" << m << " n=" << n << " k=" << k);
        const Eigen::MatrixXd A = rng.Matrix(m, k), B = rng.Matrix(n, k);
        const Eigen::MatrixXd C0 = rng.Matrix(m, n);
        const double alpha = -0.75;
        const Eigen::MatrixXd expected = C0 + alpha * A * B.transpose();
        const int lda = m + 3, ldb = n + 1, ldc = m + 2;
        const Eigen::MatrixXd Ap = Padded(A, lda, &rng), Bp = Padded(B, ldb, &rng);
        Eigen::MatrixXd Cp = Padded(C0, ldc, &rng);
        Cp.bottomRows(ldc - m).setConstant(nan);  // padding must be neither read nor written
        avx2::AddProductNT(m, n, k, alpha, Ap.data(), lda, Bp.data(), ldb, false, Cp.data(), ldc);
        const double scale = 1.0 + std::sqrt(static_cast<double>(k));
        EXPECT_LE((Cp.topRows(m) - expected).cwiseAbs().maxCoeff(), 1e-14 * scale);
        EXPECT_TRUE(Cp.bottomRows(ldc - m).array().isNaN().all());
      }
    }
  }
}

TEST_F(Avx2BlockKernels, LowerProductWritesOnlyTheLowerTriangle) {
  test::Random rng(12);
  for (int n : {1, 2, 3, 4, 5, 7, 8, 9, 13, 19, 24, 29}) {
    for (int k : {1, 5, 57}) {
      SCOPED_TRACE(::testing::Message() << "n=" << n << " k=" << k);
      const Eigen::MatrixXd A = rng.Matrix(n, k), B = rng.Matrix(n, k);
      const Eigen::MatrixXd C0 = rng.Matrix(n, n);
      Eigen::MatrixXd C = C0;
      avx2::AddProductNT(n, n, k, 2.0, A.data(), n, B.data(), n, true, C.data(), n);
      const Eigen::MatrixXd full = C0 + 2.0 * A * B.transpose();
      for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
          if (i >= j) {
            EXPECT_NEAR(C(i, j), full(i, j), 1e-13 * (1.0 + k)) << i << ", " << j;
          } else {
            EXPECT_EQ(C(i, j), C0(i, j)) << i << ", " << j;  // untouched
          }
        }
      }
    }
  }
}

TEST_F(Avx2BlockKernels, RightTransposedSolveInvertsTheProduct) {
  test::Random rng(13);
  for (int m : {1, 3, 8, 19, 23}) {
    for (int n : {1, 2, 4, 5, 9, 19, 29}) {
      SCOPED_TRACE(::testing::Message() << "m=" << m << " n=" << n);
      Eigen::MatrixXd L = rng.Matrix(n, n, -0.3, 0.3);
      L.diagonal().array() += 2.0;
      L.triangularView<Eigen::StrictlyUpper>().setConstant(
          std::numeric_limits<double>::quiet_NaN());  // never read
      const Eigen::MatrixXd X0 = rng.Matrix(m, n);
      const Eigen::MatrixXd Ll = L.triangularView<Eigen::Lower>();
      const Eigen::MatrixXd expected =
          Ll.transpose().triangularView<Eigen::Upper>().solve<Eigen::OnTheRight>(X0);
      const int ldx = m + 1;
      Eigen::MatrixXd Xp = Padded(X0, ldx, &rng);
      avx2::SolveRightLowerTransposed(m, n, L.data(), n, Xp.data(), ldx);
      EXPECT_LE((Xp.topRows(m) - expected).cwiseAbs().maxCoeff(), 1e-14);
      // The defining identity: X L^T = X0.
      EXPECT_LE((Xp.topRows(m) * Ll.transpose() - X0).cwiseAbs().maxCoeff(), 1e-14);
    }
  }
}

// Both of LowerSolve's routes: through the transpose (size x cols up to 1024 entries) and the
// blocked loop beyond; and the plain product A B.
TEST_F(Avx2BlockKernels, LeftSolveAndProductNNMatchEigen) {
  test::Random rng(15);
  for (int size : {1, 3, 4, 7, 16, 29, 70}) {
    for (int cols : {1, 5, 29, 70}) {
      SCOPED_TRACE(::testing::Message() << "size=" << size << " cols=" << cols);
      Eigen::MatrixXd L = rng.Matrix(size, size, -0.3, 0.3);
      L.diagonal().array() += 2.0;
      L.triangularView<Eigen::StrictlyUpper>().setConstant(
          std::numeric_limits<double>::quiet_NaN());
      const Eigen::VectorXd inverse = L.diagonal().cwiseInverse();
      const Eigen::MatrixXd Ll = L.triangularView<Eigen::Lower>();
      const Eigen::MatrixXd X0 = rng.Matrix(size, cols);
      const int ldx = size + 2;
      Eigen::MatrixXd Xp = Padded(X0, ldx, &rng);
      avx2::LowerSolve(size, L.data(), size, inverse.data(), Xp.data(), ldx, cols);
      EXPECT_LE((Ll * Xp.topRows(size) - X0).cwiseAbs().maxCoeff(), 1e-13);
    }
  }
  for (bool lower : {false, true}) {
    const int m = 23, k = 29;
    const Eigen::MatrixXd A = rng.Matrix(m, k), B = rng.Matrix(k, m), C0 = rng.Matrix(m, m);
    Eigen::MatrixXd C = C0;
    avx2::AddProductNN(m, m, k, -1.5, A.data(), m, B.data(), k, lower, C.data(), m);
    const Eigen::MatrixXd expected = C0 - 1.5 * A * B;
    for (int j = 0; j < m; ++j) {
      for (int i = 0; i < m; ++i) {
        if (!lower || i >= j) {
          EXPECT_NEAR(C(i, j), expected(i, j), 1e-13 * k);
        } else {
          EXPECT_EQ(C(i, j), C0(i, j));
        }
      }
    }
  }
}

TEST_F(Avx2BlockKernels, CholeskyMatchesEigenAndRejectsIndefiniteOrNonFinitePivots) {
  test::Random rng(14);
  for (int n : {1, 2, 3, 4, 5, 8, 11, 19, 23, 29, 33}) {
    SCOPED_TRACE(::testing::Message() << "n=" << n);
    const Eigen::MatrixXd J = rng.Matrix(n, n);
    Eigen::MatrixXd S = J * J.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd expected = Eigen::MatrixXd(S.llt().matrixL());
    Eigen::MatrixXd F = S;
    F.triangularView<Eigen::StrictlyUpper>().setConstant(7.0);  // only the lower part is read
    ASSERT_TRUE(avx2::CholeskyInPlace(n, F.data(), n));
    EXPECT_LE((F - expected).norm(), 1e-12 * expected.norm());
    EXPECT_EQ(F.triangularView<Eigen::StrictlyUpper>().toDenseMatrix().norm(), 0.0);
    EXPECT_LE((F * F.transpose() - S).norm(), 1e-14 * S.norm());
    // An indefinite or non-finite pivot anywhere, including the last column of a panel.
    for (int bad : {0, n / 2, n - 1}) {
      Eigen::MatrixXd G = S;
      G(bad, bad) = -1e3;
      EXPECT_FALSE(avx2::CholeskyInPlace(n, G.data(), n)) << "negative pivot " << bad;
      G = S;
      G(bad, bad) = std::numeric_limits<double>::infinity();
      EXPECT_FALSE(avx2::CholeskyInPlace(n, G.data(), n)) << "infinite pivot " << bad;
      G = S;
      G(n - 1, bad) = std::numeric_limits<double>::quiet_NaN();
      EXPECT_FALSE(avx2::CholeskyInPlace(n, G.data(), n)) << "NaN in row " << n - 1;
    }
  }
}

// The switch: off gives the portable path whatever the CPU, on restores the CPU's.
TEST(BlockKernels, SwitchFollowsTheCpu) {
  const bool before = internal::UseAvx2Kernels();
  internal::SetAvx2KernelsEnabledForTesting(false);
  EXPECT_FALSE(internal::UseAvx2Kernels());
  internal::SetAvx2KernelsEnabledForTesting(true);
  EXPECT_EQ(internal::UseAvx2Kernels(), internal::Avx2KernelsAvailable());
  internal::SetAvx2KernelsEnabledForTesting(before);
}

}  // namespace
}  // namespace idto
