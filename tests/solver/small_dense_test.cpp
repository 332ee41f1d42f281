// The banded KKT factorization's block kernels (src/math/small_dense.hpp) against Eigen's dense
// operations, for every block size from 1 to 20 (both sides of kSmallKernelLimit), with a leading
// dimension larger than the rows and with sparse operands (the zero-skipping paths).

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "math/small_dense.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr int kPad = 3;  // leading dimension = rows + kPad

// A random matrix with about a third of its entries zero.
MatrixXd SparseRandom(int rows, int cols, test::Random* rng) {
  MatrixXd M = rng->Matrix(rows, cols);
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) {
      if ((i + 2 * j) % 3 == 0) M(i, j) = 0.0;
    }
  }
  return M;
}

// Lower triangular with a dominant diagonal, its upper triangle filled with garbage the kernels
// must not read.
MatrixXd RandomLower(int size, test::Random* rng) {
  MatrixXd L = rng->Matrix(size, size);
  L.diagonal().array() = L.diagonal().array().abs() + 2.0;
  L.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);
  return L;
}

// Copies M into a column-major buffer with leading dimension rows + kPad.
MatrixXd Padded(const MatrixXd& M) {
  MatrixXd P = MatrixXd::Constant(M.rows() + kPad, M.cols(), -7.0);
  P.topRows(M.rows()) = M;
  return P;
}

class SmallDense : public ::testing::TestWithParam<int> {};

TEST_P(SmallDense, LowerSolvesMatchEigen) {
  const int m = GetParam();
  test::Random rng(100 + m);
  const MatrixXd L = RandomLower(m, &rng);
  const VectorXd inverse = L.diagonal().cwiseInverse();
  MatrixXd Lp = Padded(L);
  for (int cols : {1, 2, m}) {
    const MatrixXd B = SparseRandom(m, cols, &rng);
    MatrixXd X = Padded(B);
    internal::LowerSolveInPlace(Lp.data(), m + kPad, inverse.data(), m, X.data(), m + kPad, cols);
    const MatrixXd expected = L.triangularView<Eigen::Lower>().solve(B);
    EXPECT_LE((X.topRows(m) - expected).norm(), 1e-13 * (1.0 + expected.norm())) << cols;
    EXPECT_TRUE((X.bottomRows(kPad).array() == -7.0).all()) << "wrote past the rows";
  }
  VectorXd x = SparseRandom(m, 1, &rng);
  const VectorXd expected = L.triangularView<Eigen::Lower>().transpose().solve(x);
  internal::LowerTransposeSolveInPlace(Lp.data(), m + kPad, inverse.data(), m, x.data());
  EXPECT_LE((x - expected).norm(), 1e-13 * (1.0 + expected.norm()));
}

TEST_P(SmallDense, ProductsMatchEigen) {
  const int m = GetParam();
  test::Random rng(200 + m);
  for (int n : {0, m / 2, m}) {
    const MatrixXd T = SparseRandom(m, m, &rng), X = SparseRandom(m, m, &rng);
    const MatrixXd C0 = rng.Matrix(m, m);
    VectorXd sigma = VectorXd::Ones(m);
    sigma.tail(m - n).setConstant(-1.0);
    const MatrixXd expected = C0 - T * sigma.asDiagonal() * X;
    const MatrixXd Tp = Padded(T), Xp = Padded(X);
    for (bool lower : {false, true}) {
      MatrixXd C = Padded(C0);
      internal::SubtractSignedProduct(Tp.data(), m + kPad, Xp.data(), m + kPad, m, m, m, n, lower,
                                      C.data(), m + kPad);
      const MatrixXd got = C.topRows(m);
      if (lower) {
        const MatrixXd d = MatrixXd(got.triangularView<Eigen::Lower>()) -
                           MatrixXd(expected.triangularView<Eigen::Lower>());
        EXPECT_LE(d.norm(), 1e-13 * (1.0 + expected.norm())) << "n = " << n;
      } else {
        EXPECT_LE((got - expected).norm(), 1e-13 * (1.0 + expected.norm())) << "n = " << n;
      }
      EXPECT_TRUE((C.bottomRows(kPad).array() == -7.0).all()) << "wrote past the rows";
    }
  }
  const MatrixXd A = SparseRandom(m, m + 1, &rng);
  const VectorXd x = rng.Vector(m), z = rng.Vector(m + 1);
  VectorXd y = rng.Vector(m + 1);
  VectorXd expected = y - A.transpose() * x;
  internal::SubtractTransposeTimes(A.data(), m, m, m + 1, x.data(), y.data());
  EXPECT_LE((y - expected).norm(), 1e-13 * (1.0 + expected.norm()));
  VectorXd w = rng.Vector(m);
  expected = w + A * z;
  internal::AddTimes(A.data(), m, m, m + 1, z.data(), w.data());
  EXPECT_LE((w - expected).norm(), 1e-13 * (1.0 + expected.norm()));
}

TEST_P(SmallDense, CholeskyColumnsFactorAndLeaveTheSchurComplement) {
  const int m = GetParam();
  test::Random rng(300 + m);
  const MatrixXd R = rng.Matrix(m, m);
  const MatrixXd S = R * R.transpose() + MatrixXd::Identity(m, m);
  const int n = m / 2;
  MatrixXd F = S;
  VectorXd diagonal = S.diagonal(), inverse(m);
  double relative = 0.0;
  ASSERT_EQ(internal::CholeskyColumnsInPlace(0.0, diagonal.data(), m, 0, n, F.data(), m,
                                             inverse.data(), &relative),
            -1);
  // The first n columns: P = Lp Lpᵀ, Y = Q Lp⁻ᵀ; the trailing block: R − Y Yᵀ.
  const Eigen::LLT<MatrixXd> llt(S.topLeftCorner(n, n));
  const MatrixXd Lp = llt.matrixL();
  const MatrixXd Y =
      Lp.triangularView<Eigen::Lower>().solve(S.bottomLeftCorner(m - n, n).transpose()).transpose();
  const MatrixXd schur = S.bottomRightCorner(m - n, m - n) - Y * Y.transpose();
  const MatrixXd got_lp = F.topLeftCorner(n, n).triangularView<Eigen::Lower>();
  EXPECT_LE((got_lp - Lp).norm(), 1e-12 * Lp.norm());
  EXPECT_LE((F.bottomLeftCorner(m - n, n) - Y).norm(), 1e-12 * (1.0 + Y.norm()));
  const MatrixXd got_schur = F.bottomRightCorner(m - n, m - n).triangularView<Eigen::Lower>();
  const MatrixXd want_schur = schur.triangularView<Eigen::Lower>();
  EXPECT_LE((got_schur - want_schur).norm(), 1e-12 * (1.0 + schur.norm()));
  for (int k = 0; k < n; ++k) EXPECT_DOUBLE_EQ(inverse[k], 1.0 / F(k, k));
  // A singular trailing block fails at its dependent row with the relative pivot.
  if (m >= 2) {
    MatrixXd G = MatrixXd::Zero(m, m);
    G.col(0).setOnes();
    G(0, 0) = 4.0;
    diagonal = G.diagonal();
    diagonal(m - 1) = 1.0;
    const int row = internal::CholeskyColumnsInPlace(1e-14, diagonal.data(), m, 0, m, G.data(), m,
                                                     inverse.data(), &relative);
    EXPECT_EQ(row, 1);
  }
}

INSTANTIATE_TEST_SUITE_P(Sizes, SmallDense, ::testing::Range(1, 21));

}  // namespace
}  // namespace idto
