#pragma once

// Dense kernels for the banded KKT factorization's blocks (m = n + nu, a few to a few dozen),
// private to src/. Below kSmallKernelLimit: column-oriented loops over contiguous columns that
// skip zero coefficients (the examples' blocks are sparse: bodies that do not touch do not
// couple) and multiply by stored reciprocals of the pivots; there Eigen's dynamic-size products
// and triangular solves spend most of their time packing and blocking. From the limit up, the
// register-tiled AVX2/FMA kernels of math/block_kernels.hpp where the CPU has them, else Eigen's
// blocked kernels (docs/benchmarks.md, "KKT kernels" and session 17).
// All matrices are column-major with a leading dimension (ld) and are read and written in place.

#include <cmath>
#include <type_traits>

#include <Eigen/Core>

#include "math/block_kernels.hpp"

namespace idto::internal {

/// Block sizes below this take the loops; from it up, Eigen's kernels (measured: the loops are
/// 1.2–1.5× faster on the hopper (m = 8) and ball + finger (m = 11) KKT systems, 1.2× slower
/// on the quadruped (m = 24) and Allegro (m = 29) ones).
constexpr int kSmallKernelLimit = 16;

using ConstMatrixMap = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
using MatrixMap = Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>;

namespace small_dense_detail {

// The triangular solves of one dense vector (the KKT sweeps) for R rows known at compile time:
// unrolled, without the zero tests that pay off only for the factorization's sparse right-hand
// sides.
template <int R>
void LowerSolveVectorFixed(const double* L, int ldl, const double* inverse_diagonal, double* x) {
  for (int k = 0; k < R; ++k) {
    const double* __restrict l = L + static_cast<long>(k) * ldl;
    const double a = x[k] * inverse_diagonal[k];
    x[k] = a;
    for (int i = k + 1; i < R; ++i) x[i] -= a * l[i];
  }
}

template <int R>
void LowerTransposeSolveFixed(const double* L, int ldl, const double* inverse_diagonal, double* x) {
  for (int k = R - 1; k >= 0; --k) {
    const double* __restrict u = L + static_cast<long>(k) * ldl;
    const double a = x[k] * inverse_diagonal[k];
    x[k] = a;
    for (int i = 0; i < k; ++i) x[i] -= a * u[i];
  }
}

// Two columns of X at a time with R rows known at compile time: row i of the pair is one 2-lane
// vector held in a register for the whole solve (each column of L is loaded once per pair, no
// store until the end; measured 2.2× faster than the loops over a dynamic row count at R = 15).
// A pair whose multipliers are both zero skips its update (the factorization's right-hand sides
// are often sparse). Per entry, the same operations in the same order as a column at a time.
template <int R>
void LowerSolvePairsFixed(const double* L, int ldl, const double* inverse_diagonal, double* X,
                          int ldx, int cols) {
  typedef double Pair __attribute__((vector_size(16)));
  int c = 0;
  for (; c + 1 < cols; c += 2) {
    double* x0 = X + static_cast<long>(c) * ldx;
    double* x1 = x0 + ldx;
    Pair x[R];
#pragma GCC unroll 16
    for (int i = 0; i < R; ++i) x[i] = Pair{x0[i], x1[i]};
#pragma GCC unroll 16
    for (int k = 0; k < R; ++k) {
      const Pair a = x[k] * inverse_diagonal[k];
      x[k] = a;
      if (a[0] == 0.0 && a[1] == 0.0) continue;
      const double* l = L + static_cast<long>(k) * ldl;
#pragma GCC unroll 16
      for (int i = k + 1; i < R; ++i) x[i] -= a * l[i];
    }
#pragma GCC unroll 16
    for (int i = 0; i < R; ++i) {
      x0[i] = x[i][0];
      x1[i] = x[i][1];
    }
  }
  if (c < cols) LowerSolveVectorFixed<R>(L, ldl, inverse_diagonal, X + static_cast<long>(c) * ldx);
}

// Calls Kernel<size>(args...) for 1 <= size <= R; false for other sizes.
template <int R, template <int> class Kernel, typename... Args>
bool DispatchSize(int size, Args... args) {
  if (size == R) {
    Kernel<R>::Run(args...);
    return true;
  }
  if constexpr (R > 1) {
    return DispatchSize<R - 1, Kernel>(size, args...);
  } else {
    return false;
  }
}

template <int R>
struct LowerSolveKernel {
  static void Run(const double* L, int ldl, const double* d, double* X, int ldx, int cols) {
    LowerSolvePairsFixed<R>(L, ldl, d, X, ldx, cols);
  }
};

template <int R>
struct LowerTransposeSolveKernel {
  static void Run(const double* L, int ldl, const double* d, double* x) {
    LowerTransposeSolveFixed<R>(L, ldl, d, x);
  }
};

// SubtractTransposeTimes for a square R × R A: the fixed size unrolls each column's dot product
// into independent partial sums that run side by side across columns (a dynamic trip count of
// a few iterations leaves one chain of dependent additions per column).
template <int R>
void SubtractTransposeTimesFixed(const double* A, int lda, const double* x, double* y) {
  using Square = Eigen::Matrix<double, R, R>;
  using Column = Eigen::Matrix<double, R, 1>;
  Eigen::Map<Column>(y).noalias() -=
      Eigen::Map<const Square, 0, Eigen::OuterStride<>>(A, R, R, Eigen::OuterStride<>(lda))
          .transpose()
          .lazyProduct(Eigen::Map<const Column>(x));
}

// AddTimes for a square R × R A: y stays in registers over the R column updates (measured
// 1.2× faster on the KKT sweeps at R = 15 than the loop over a dynamic row count).
template <int R>
struct AddTimesKernel {
  static void Run(const double* A, int lda, const double* x, double* y) {
    using Column = Eigen::Matrix<double, R, 1>;
    Column sum = Eigen::Map<const Column>(y);
    for (int j = 0; j < R; ++j) sum.noalias() += x[j] * Eigen::Map<const Column>(A + j * lda);
    Eigen::Map<Column> out(y);
    out = sum;
  }
};

template <int R>
struct SubtractTransposeTimesKernel {
  static void Run(const double* A, int lda, const double* x, double* y) {
    SubtractTransposeTimesFixed<R>(A, lda, x, y);
  }
};

}  // namespace small_dense_detail

/// X ← L⁻¹ X. L: size × size lower triangular (its upper triangle is not read),
/// inverse_diagonal: 1 / L(k, k) (size; below kSmallKernelLimit it replaces L's diagonal, a
/// multiplication instead of a division on the critical path); X: size × cols. Below the limit,
/// two columns of X at a time in registers (small_dense_detail::LowerSolvePairsFixed).
inline void LowerSolveInPlace(const double* L, int ldl, const double* inverse_diagonal, int size,
                              double* X, int ldx, int cols) {
  if (size >= kSmallKernelLimit && UseAvx2Kernels()) {
    avx2::LowerSolve(size, L, ldl, inverse_diagonal, X, ldx, cols);
    return;
  }
  if (size >= kSmallKernelLimit) {
    MatrixMap x(X, size, cols, Eigen::OuterStride<>(ldx));
    ConstMatrixMap(L, size, size, Eigen::OuterStride<>(ldl))
        .triangularView<Eigen::Lower>()
        .solveInPlace(x);
    return;
  }
  small_dense_detail::DispatchSize<kSmallKernelLimit - 1, small_dense_detail::LowerSolveKernel>(
      size, L, ldl, inverse_diagonal, X, ldx, cols);
}

/// x ← L⁻ᵀ x. L: size × size lower triangular whose strictly upper triangle holds Lᵀ's (L(i, k) =
/// L(k, i)), inverse_diagonal: 1 / L(k, k) (used as LowerSolveInPlace does); x: size. Below
/// kSmallKernelLimit, by columns of the upper triangle: once x_k is known, x_{0..k−1} −= L(k,
/// 0..k−1)ᵀ x_k, one contiguous axpy (dot products along L's columns would chain every term of
/// x_k's sum through one accumulator). From the limit up, Eigen's solve, which reads the lower
/// triangle only.
inline void LowerTransposeSolveInPlace(const double* L, int ldl, const double* inverse_diagonal,
                                       int size, double* x) {
  if (size >= kSmallKernelLimit) {
    Eigen::Map<Eigen::VectorXd> v(x, size);
    ConstMatrixMap(L, size, size, Eigen::OuterStride<>(ldl))
        .transpose()
        .triangularView<Eigen::Upper>()
        .solveInPlace(v);
    return;
  }
  small_dense_detail::DispatchSize<kSmallKernelLimit - 1,
                                   small_dense_detail::LowerTransposeSolveKernel>(
      size, L, ldl, inverse_diagonal, x);
}

/// y −= Aᵀ x. A: rows × cols; x: rows; y: cols (dot products along A's columns).
inline void SubtractTransposeTimes(const double* A, int lda, int rows, int cols, const double* x,
                                   double* y) {
  if (rows >= kSmallKernelLimit) {
    Eigen::Map<Eigen::VectorXd>(y, cols).noalias() -=
        ConstMatrixMap(A, rows, cols, Eigen::OuterStride<>(lda)).transpose() *
        Eigen::Map<const Eigen::VectorXd>(x, rows);
    return;
  }
  if (rows == cols &&
      small_dense_detail::DispatchSize<kSmallKernelLimit - 1,
                                       small_dense_detail::SubtractTransposeTimesKernel>(
          rows, A, lda, x, y)) {
    return;
  }
  for (int j = 0; j < cols; ++j) {
    const double* __restrict a = A + static_cast<long>(j) * lda;
    double s0 = 0.0, s1 = 0.0;
    int i = 0;
    for (; i + 1 < rows; i += 2) {
      s0 += a[i] * x[i];
      s1 += a[i + 1] * x[i + 1];
    }
    if (i < rows) s0 += a[i] * x[i];
    y[j] -= s0 + s1;
  }
}

/// y += A x. A: rows × cols; x: cols; y: rows (axpys along A's columns).
inline void AddTimes(const double* A, int lda, int rows, int cols, const double* x, double* y) {
  if (rows >= kSmallKernelLimit) {
    Eigen::Map<Eigen::VectorXd>(y, rows).noalias() +=
        ConstMatrixMap(A, rows, cols, Eigen::OuterStride<>(lda)) *
        Eigen::Map<const Eigen::VectorXd>(x, cols);
    return;
  }
  if (rows == cols &&
      small_dense_detail::DispatchSize<kSmallKernelLimit - 1, small_dense_detail::AddTimesKernel>(
          rows, A, lda, x, y)) {
    return;
  }
  for (int j = 0; j < cols; ++j) {
    const double* __restrict a = A + static_cast<long>(j) * lda;
    const double c = x[j];
    if (c == 0.0) continue;
    for (int i = 0; i < rows; ++i) y[i] += c * a[i];
  }
}

/// Four doubles as one GCC/Clang vector (one AVX register, or two SSE2 ones): the lanes of the
/// double-double kernels below, whose arithmetic is lane-wise IEEE double.
typedef double Lanes4 __attribute__((vector_size(32)));

/// The rounding error of product = fl(a b): a b = product + *error exactly (no overflow). T:
/// double or Lanes4 (lane-wise). kFma: one fma per lane (__builtin_fma: an fma instruction where
/// the caller is compiled for one, e.g. src/solver/extended_residual.cpp's fma variant, which
/// vectorizes the lanes' fmas; otherwise the C library's software fma). !kFma: Dekker's product
/// with Veltkamp's splitting, exact in IEEE double without fused operations (the
/// extended-residual KKT step measured 1.2–1.5× faster than the software fma, docs/solver.md).
/// Both are exact, so both give the same bits. References, not values: a vector argument's ABI
/// would depend on the instruction set.
template <bool kFma, typename T>
inline void TwoProductErrorInto(const T& a, const T& b, const T& product, T* error) {
  if constexpr (kFma) {
    if constexpr (std::is_same_v<T, double>) {
      *error = __builtin_fma(a, b, -product);
    } else {
      for (int l = 0; l < static_cast<int>(sizeof(T) / sizeof(double)); ++l) {
        (*error)[l] = __builtin_fma(a[l], b[l], -product[l]);
      }
    }
  } else {
    constexpr double kSplitter = 134217729.0;  // 2^27 + 1
    const T ta = kSplitter * a;
    const T a_hi = ta - (ta - a);
    const T a_lo = a - a_hi;
    const T tb = kSplitter * b;
    const T b_hi = tb - (tb - b);
    const T b_lo = b - b_hi;
    *error = ((a_hi * b_hi - product) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo;
  }
}

/// TwoProductErrorInto for doubles, returning the error.
template <bool kFma>
inline double TwoProductErrorWith(double a, double b, double product) {
  double error;
  TwoProductErrorInto<kFma>(a, b, product, &error);
  return error;
}

#ifdef __FMA__
constexpr bool kBuildHasFma = true;
#else
constexpr bool kBuildHasFma = false;
#endif

/// TwoProductErrorWith for the build's instruction set (-mfma, IDTO_NATIVE on an FMA machine).
inline double TwoProductError(double a, double b, double product) {
  return TwoProductErrorWith<kBuildHasFma>(a, b, product);
}

/// (hi + lo) ← (hi + lo) − a b in double-double arithmetic (T: double or Lanes4, lane-wise): the
/// product is split exactly by TwoProductErrorInto, the sum by Knuth's TwoSum; the low parts' own
/// rounding is of order ε |lo|. Requires that the compiler does not contract these expressions
/// into fmas (CMakeLists.txt compiles its users with -ffp-contract=off).
template <bool kFma, typename T>
inline void SubtractProductExactlyWith(const T& a, const T& b, T* hi, T* lo) {
  const T product = a * b;
  T product_error;  // a b = product + product_error
  TwoProductErrorInto<kFma>(a, b, product, &product_error);
  const T sum = *hi - product;
  const T virtual_b = sum - *hi;
  const T sum_error = (*hi - (sum - virtual_b)) + (-product - virtual_b);
  *hi = sum;
  *lo += sum_error - product_error;
}

inline void SubtractProductExactly(double a, double b, double* hi, double* lo) {
  SubtractProductExactlyWith<kBuildHasFma>(a, b, hi, lo);
}

/// T = Xᵀ. X: rows × cols; T: cols × rows.
inline void Transpose(const double* X, int ldx, int rows, int cols, double* T, int ldt) {
  for (int j = 0; j < cols; ++j) {
    const double* x = X + static_cast<long>(j) * ldx;
    for (int i = 0; i < rows; ++i) T[j + static_cast<long>(i) * ldt] = x[i];
  }
}

namespace small_dense_detail {

// SubtractSignedProduct for R rows known at compile time: column j of C accumulates in registers
// (R ≤ 15 doubles), so the update costs one load and one store of C per column instead of one
// per term (measured 2.5–3× faster than the loop over a dynamic row count at R = 8 and 11).
template <int R>
void SubtractSignedProductFixedRows(const double* T, int ldt, const double* X, int ldx, int inner,
                                    int cols, int n, double* C, int ldc) {
  using Column = Eigen::Matrix<double, R, 1>;
  for (int j = 0; j < cols; ++j) {
    const double* x = X + static_cast<long>(j) * ldx;
    Column sum = Column::Zero();
    for (int k = 0; k < inner; ++k) {
      const double a = k < n ? x[k] : -x[k];
      if (a == 0.0) continue;
      sum.noalias() += a * Eigen::Map<const Column>(T + static_cast<long>(k) * ldt);
    }
    Eigen::Map<Column>(C + static_cast<long>(j) * ldc) -= sum;
  }
}

template <int R>
void SubtractSignedProductDispatch(const double* T, int ldt, const double* X, int ldx, int rows,
                                   int inner, int cols, int n, double* C, int ldc) {
  if (rows == R) {
    SubtractSignedProductFixedRows<R>(T, ldt, X, ldx, inner, cols, n, C, ldc);
  } else if constexpr (R > 1) {
    SubtractSignedProductDispatch<R - 1>(T, ldt, X, ldx, rows, inner, cols, n, C, ldc);
  }
}

}  // namespace small_dense_detail

/// C ← C − T Σ X with Σ = diag(I_n, −I_{inner−n}): C(:, j) −= Σ_k σ_k X(k, j) T(:, k).
/// T: rows × inner; X: inner × cols; C: rows × cols. With `lower` (C square), only C's lower
/// triangle is needed: it is updated, and the strictly upper triangle is updated too or left
/// unchanged (below kSmallKernelLimit the whole columns are cheaper). Zero coefficients are
/// skipped (the constraint rows of the right-hand sides are often zero).
inline void SubtractSignedProduct(const double* T, int ldt, const double* X, int ldx, int rows,
                                  int inner, int cols, int n, bool lower, double* C, int ldc) {
  if (rows < kSmallKernelLimit) {
    small_dense_detail::SubtractSignedProductDispatch<kSmallKernelLimit - 1>(
        T, ldt, X, ldx, rows, inner, cols, n, C, ldc);
    return;
  }
  const int rest = inner - n;
  if (UseAvx2Kernels()) {
    avx2::AddProductNN(rows, cols, n, -1.0, T, ldt, X, ldx, lower, C, ldc);
    avx2::AddProductNN(rows, cols, rest, 1.0, T + static_cast<long>(n) * ldt, ldt, X + n, ldx,
                       lower, C, ldc);
    return;
  }
  const ConstMatrixMap t(T, rows, inner, Eigen::OuterStride<>(ldt));
  const ConstMatrixMap x(X, inner, cols, Eigen::OuterStride<>(ldx));
  MatrixMap c(C, rows, cols, Eigen::OuterStride<>(ldc));
  if (lower) {
    auto c_lower = c.triangularView<Eigen::Lower>();
    c_lower -= t.leftCols(n) * x.topRows(n);
    if (rest > 0) c_lower += t.rightCols(rest) * x.bottomRows(rest);
  } else {
    c.noalias() -= t.leftCols(n) * x.topRows(n);
    if (rest > 0) c.noalias() += t.rightCols(rest) * x.bottomRows(rest);
  }
}

namespace small_dense_detail {

// CholeskyColumnsInPlace below kSmallKernelLimit: right-looking column updates that skip zero
// multipliers. R > 0: size == R known at compile time (the banded KKT's small blocks); R = 0:
// size at run time. The same operations in the same order either way.
template <int R>
inline int CholeskyColumnsRightLooking(double tolerance, const double* diagonal, int size,
                                       int begin, int end, double* M, int ld,
                                       double* inverse_diagonal, double* relative_pivot) {
  const int s = R > 0 ? R : size;
  for (int k = begin; k < end; ++k) {
    double* __restrict mk = M + static_cast<long>(k) * ld;
    const double d = mk[k];
    if (!AcceptPivot(d, tolerance, diagonal[k], relative_pivot)) return k;
    const double lkk = std::sqrt(d);
    mk[k] = lkk;
    const double inverse = 1.0 / lkk;
    inverse_diagonal[k] = inverse;
    for (int i = k + 1; i < s; ++i) mk[i] *= inverse;
    for (int j = k + 1; j < s; ++j) {
      const double a = mk[j];
      if (a == 0.0) continue;
      double* __restrict mj = M + static_cast<long>(j) * ld;
      for (int i = j; i < s; ++i) mj[i] -= a * mk[i];
    }
  }
  return -1;
}

// CholeskyColumnsInPlace from kSmallKernelLimit up: left-looking (each column by one Eigen
// matrix-vector product with the columns before it), then the trailing block's update by one
// Eigen rank-(end − begin) product.
inline int CholeskyColumnsLeftLooking(double tolerance, const double* diagonal, int size, int begin,
                                      int end, double* M, int ld, double* inverse_diagonal,
                                      double* relative_pivot) {
  MatrixMap m(M, size, size, Eigen::OuterStride<>(ld));
  for (int k = begin; k < end; ++k) {
    const int below = size - k;
    if (k > begin) {
      m.col(k).tail(below).noalias() -=
          m.block(k, begin, below, k - begin) * m.row(k).segment(begin, k - begin).transpose();
    }
    const double d = m(k, k);
    if (!AcceptPivot(d, tolerance, diagonal[k], relative_pivot)) return k;
    const double lkk = std::sqrt(d);
    inverse_diagonal[k] = 1.0 / lkk;
    m(k, k) = lkk;
    m.col(k).tail(below - 1) *= inverse_diagonal[k];
  }
  const int rest = size - end;
  if (rest > 0 && end > begin) {
    const auto panel = m.block(end, begin, rest, end - begin);
    m.bottomRightCorner(rest, rest).triangularView<Eigen::Lower>() -= panel * panel.transpose();
  }
  return -1;
}

}  // namespace small_dense_detail

/// Cholesky of columns [begin, end) of the lower triangle of the size × size M, in place (the
/// columns before `begin` already eliminated into the rest): M(k:, k) becomes the factor's
/// column k and the trailing block below and right of `end` receives the Schur complement update
/// (lower triangle). A pivot d fails when !(d > tolerance · |diagonal[k]|), diagonal[k] the
/// caller's scale for that row (tolerance 0: d must be positive; NaN and Inf always fail).
/// Returns the failing column, or −1, and *relative_pivot = d / |diagonal[k]| of that column.
/// inverse_diagonal[k] receives 1 / L(k, k). Below kSmallKernelLimit right-looking column
/// updates that skip zero multipliers; from it up, left-looking Eigen products.
inline int CholeskyColumnsInPlace(double tolerance, const double* diagonal, int size, int begin,
                                  int end, double* M, int ld, double* inverse_diagonal,
                                  double* relative_pivot) {
  if (size >= kSmallKernelLimit && UseAvx2Kernels()) {
    return avx2::CholeskyColumns(tolerance, diagonal, size, begin, end, M, ld, inverse_diagonal,
                                 relative_pivot);
  }
  if (size >= kSmallKernelLimit) {
    return small_dense_detail::CholeskyColumnsLeftLooking(tolerance, diagonal, size, begin, end, M,
                                                          ld, inverse_diagonal, relative_pivot);
  }
  return small_dense_detail::CholeskyColumnsRightLooking<0>(
      tolerance, diagonal, size, begin, end, M, ld, inverse_diagonal, relative_pivot);
}

}  // namespace idto::internal
