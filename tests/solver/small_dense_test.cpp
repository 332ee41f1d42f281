// The banded KKT factorization's block kernels (src/math/small_dense.hpp) against Eigen's dense
// operations, for every block size from 1 to 20 (both sides of kSmallKernelLimit) and the
// examples' larger ones (23, 25, 29), on both paths of the block kernels from the limit up, with
// leading dimensions larger than the rows and with sparse operands (the zero-skipping paths); the
// double-double residual update against exactly known results.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "math/small_dense.hpp"
#include "support/kernel_paths.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr int kPad = 3;  // leading dimension = rows + kPad

// A random matrix with about half of its entries zero: a scattered third, and every row
// i ≡ 1 (mod 4) entirely (so that neighbouring columns share zero rows).
MatrixXd SparseRandom(int rows, int cols, test::Random* rng) {
  MatrixXd M = rng->Matrix(rows, cols);
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) {
      if ((i + 2 * j) % 3 == 0 || i % 4 == 1) M(i, j) = 0.0;
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

// The bodies of the three size-parameterized tests, run once per kernel path.
void LowerSolvesMatchEigenImpl(int m);
void ProductsMatchEigenImpl(int m);
void CholeskyColumnsFactorAndLeaveTheSchurComplementImpl(int m);

TEST_P(SmallDense, LowerSolvesMatchEigen) {
  for (test::KernelPath path : test::AvailableKernelPaths()) {
    const test::ScopedKernelPath scoped(path);
    SCOPED_TRACE(test::KernelPathName(path));
    LowerSolvesMatchEigenImpl(GetParam());
  }
}

void LowerSolvesMatchEigenImpl(int m) {
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
  VectorXd v = rng.Vector(m);
  const VectorXd expected_v = L.triangularView<Eigen::Lower>().solve(v);
  internal::LowerSolveInPlace(Lp.data(), m + kPad, inverse.data(), m, v.data(), m + kPad, 1);
  EXPECT_LE((v - expected_v).norm(), 1e-13 * (1.0 + expected_v.norm()));
  // The transposed solve reads Lᵀ from the strictly upper triangle below the kernel limit (the
  // lower one from it up).
  VectorXd x = SparseRandom(m, 1, &rng);
  const VectorXd expected = L.triangularView<Eigen::Lower>().transpose().solve(x);
  MatrixXd Lm = Lp;
  Lm.topRows(m).triangularView<Eigen::StrictlyUpper>() =
      MatrixXd(L.triangularView<Eigen::StrictlyLower>().transpose());
  if (m >= internal::kSmallKernelLimit)
    Lm.topRows(m).triangularView<Eigen::StrictlyUpper>().setConstant(1e300);
  internal::LowerTransposeSolveInPlace(Lm.data(), m + kPad, inverse.data(), m, x.data());
  EXPECT_LE((x - expected).norm(), 1e-13 * (1.0 + expected.norm()));
}

TEST_P(SmallDense, ProductsMatchEigen) {
  for (test::KernelPath path : test::AvailableKernelPaths()) {
    const test::ScopedKernelPath scoped(path);
    SCOPED_TRACE(test::KernelPathName(path));
    ProductsMatchEigenImpl(GetParam());
  }
}

void ProductsMatchEigenImpl(int m) {
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
  const MatrixXd A = SparseRandom(m, m + 1, &rng), Ap = Padded(A);
  const VectorXd x = rng.Vector(m), z = rng.Vector(m + 1);
  VectorXd y = rng.Vector(m + 1);
  VectorXd expected = y - A.transpose() * x;
  internal::SubtractTransposeTimes(Ap.data(), m + kPad, m, m + 1, x.data(), y.data());
  EXPECT_LE((y - expected).norm(), 1e-13 * (1.0 + expected.norm()));
  // Square: the fixed-size kernels below the limit.
  VectorXd ys = y.head(m);
  expected = ys - A.leftCols(m).transpose() * x;
  internal::SubtractTransposeTimes(Ap.data(), m + kPad, m, m, x.data(), ys.data());
  EXPECT_LE((ys - expected).norm(), 1e-13 * (1.0 + expected.norm()));
  VectorXd w = rng.Vector(m);
  expected = w + A * z;
  internal::AddTimes(Ap.data(), m + kPad, m, m + 1, z.data(), w.data());
  EXPECT_LE((w - expected).norm(), 1e-13 * (1.0 + expected.norm()));
  VectorXd ws = rng.Vector(m);
  expected = ws + A.leftCols(m) * z.head(m);
  internal::AddTimes(Ap.data(), m + kPad, m, m, z.data(), ws.data());
  EXPECT_LE((ws - expected).norm(), 1e-13 * (1.0 + expected.norm()));
}

TEST_P(SmallDense, CholeskyColumnsFactorAndLeaveTheSchurComplement) {
  for (test::KernelPath path : test::AvailableKernelPaths()) {
    const test::ScopedKernelPath scoped(path);
    SCOPED_TRACE(test::KernelPathName(path));
    CholeskyColumnsFactorAndLeaveTheSchurComplementImpl(GetParam());
  }
}

void CholeskyColumnsFactorAndLeaveTheSchurComplementImpl(int m) {
  test::Random rng(300 + m);
  const MatrixXd R = SparseRandom(m, m, &rng);
  const MatrixXd S = R * R.transpose() + MatrixXd::Identity(m, m);
  const MatrixXd L = S.llt().matrixL();
  // In two calls, columns [0, n) and then [n, m), as BandedKktSolver::FactorPivot does: the first
  // leaves the Schur complement in the trailing block, so the two together give S's Cholesky.
  for (int n : {0, m / 2, m}) {
    MatrixXd F = Padded(S);
    const VectorXd diagonal = S.diagonal();
    VectorXd inverse = VectorXd::Constant(m, -1.0);
    double relative = 0.0;
    ASSERT_EQ(internal::CholeskyColumnsInPlace(0.0, diagonal.data(), m, 0, n, F.data(), m + kPad,
                                               inverse.data(), &relative),
              -1);
    if (n > 0 && n < m) {
      // After the first call: the trailing block holds S22 − Y Yᵀ (lower triangle).
      const MatrixXd Y = L.bottomLeftCorner(m - n, n);
      const MatrixXd schur = S.bottomRightCorner(m - n, m - n) - Y * Y.transpose();
      const MatrixXd got = F.block(n, n, m - n, m - n).triangularView<Eigen::Lower>();
      const MatrixXd want = schur.triangularView<Eigen::Lower>();
      EXPECT_LE((got - want).norm(), 1e-12 * (1.0 + want.norm())) << "n = " << n;
    }
    ASSERT_EQ(internal::CholeskyColumnsInPlace(0.0, diagonal.data(), m, n, m, F.data(), m + kPad,
                                               inverse.data(), &relative),
              -1);
    const MatrixXd got = F.topRows(m).triangularView<Eigen::Lower>();
    EXPECT_LE((got - L).norm(), 1e-12 * L.norm()) << "n = " << n;
    for (int k = 0; k < m; ++k) EXPECT_DOUBLE_EQ(inverse[k], 1.0 / F(k, k)) << k;
    EXPECT_TRUE((F.bottomRows(kPad).array() == -7.0).all()) << "wrote past the rows";
  }
  // A dependent last row (S = B Bᵀ with B's last row equal to its first): the last pivot is
  // round-off relative to its scale, so tolerance 1e-14 fails there and reports it.
  if (m >= 2) {
    MatrixXd B = rng.Matrix(m, m);
    B.row(m - 1) = B.row(0);
    MatrixXd G = B * B.transpose();
    const VectorXd diagonal = G.diagonal();
    VectorXd inverse(m);
    double relative = 1.0;
    const int row = internal::CholeskyColumnsInPlace(1e-14, diagonal.data(), m, 0, m, G.data(), m,
                                                     inverse.data(), &relative);
    EXPECT_EQ(row, m - 1);
    EXPECT_LE(std::abs(relative), 1e-14);
  }
}

// The double-double update is exact where double arithmetic is not: (1 + 2⁻³⁰)² = 1 + 2⁻²⁹ +
// 2⁻⁶⁰, whose last term a double product drops; and 1 − 2⁻⁶⁰, which a double sum rounds to 1.
TEST(SmallDenseExact, ProductAndSumErrorsAreKept) {
  const double a = 1.0 + std::ldexp(1.0, -30);
  double hi = 1.0, lo = 0.0;
  internal::SubtractProductExactly(a, a, &hi, &lo);
  EXPECT_EQ(hi, -std::ldexp(1.0, -29));
  EXPECT_EQ(lo, -std::ldexp(1.0, -60));
  hi = 1.0;
  lo = 0.0;
  internal::SubtractProductExactly(std::ldexp(1.0, -30), std::ldexp(1.0, -30), &hi, &lo);
  EXPECT_EQ(hi, 1.0);
  EXPECT_EQ(lo, -std::ldexp(1.0, -60));
}

// TwoProductError (Dekker's product in the default build, one fma with -mfma) and both
// TwoProductErrorWith variants are exact: a b = product + error, checked against std::fma (exact by
// definition, emulated in software when there is no fma instruction) on products over 600 binades,
// signs and zeros.
TEST(SmallDenseExact, TwoProductErrorIsExact) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  int nonzero = 0;
  for (int i = 0; i < 20000; ++i) {
    const double a = std::ldexp(mantissa(rng), exponent(rng) / 2);
    const double b = i % 1000 == 0 ? 0.0 : std::ldexp(mantissa(rng), exponent(rng) / 2);
    const double product = a * b;
    const double error = internal::TwoProductError(a, b, product);
    ASSERT_EQ(error, std::fma(a, b, -product)) << a << " * " << b;
    ASSERT_EQ(internal::TwoProductErrorWith<false>(a, b, product), error) << a << " * " << b;
    ASSERT_EQ(internal::TwoProductErrorWith<true>(a, b, product), error) << a << " * " << b;
    nonzero += error != 0.0;
  }
  EXPECT_GT(nonzero, 19000);  // the products are almost never exact in double
}

TEST(SmallDenseExact, TransposeWithLeadingDimensions) {
  test::Random rng(5);
  const MatrixXd X = rng.Matrix(4, 7), Xp = Padded(X);
  MatrixXd T = MatrixXd::Constant(7 + kPad, 4, -7.0);
  internal::Transpose(Xp.data(), 4 + kPad, 4, 7, T.data(), 7 + kPad);
  EXPECT_EQ(T.topRows(7), X.transpose());
  EXPECT_TRUE((T.bottomRows(kPad).array() == -7.0).all());
}

INSTANTIATE_TEST_SUITE_P(Sizes, SmallDense,
                         ::testing::Values(1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16,
                                           17, 18, 19, 20, 23, 25, 29));

}  // namespace
}  // namespace idto
