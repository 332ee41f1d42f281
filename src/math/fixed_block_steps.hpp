#pragma once

// The penta-diagonal Cholesky's block steps (math/penta_diagonal_blocks.hpp) for blocks of
// n <= kMaxFixedBlock rows known at compile time, and the dispatch on the block size that
// PentaDiagonalMatrix::MultiplyRows shares; private to src/. At these sizes the general
// kernels (AVX2 tiles of 4, or Eigen's dynamic-size products) spend most of their time on loop
// control and packing: the pendulum, acrobot, spinner and hopper have blocks of 1-5 (measured in
// docs/benchmarks.md, "session 32"). The loops below unroll completely; each entry gets the
// same operations in the same order on every thread count (and on the portable and AVX2 builds
// alike, which both take this path at these sizes). All blocks are column-major n x n.

#include <cmath>
#include <type_traits>

#include <Eigen/Core>

#include "math/small_dense.hpp"

namespace idto::internal {

/// Block sizes up to this take the fixed-size steps.
constexpr int kMaxFixedBlock = 6;

namespace fixed_block_detail {

// X <- X L^-T for lower-triangular L with Dinv = 1 / diag(L): column j of the result is
// (x_j - sum_{p<j} y_p L(j, p)) / L(j, j), times the stored reciprocal (the factor's chain of
// dependent divisions and square roots is what these small steps wait on).
template <int n>
inline void SolveRightLowerTransposed(const double* __restrict L, const double* __restrict Dinv,
                                      double* __restrict X) {
  for (int j = 0; j < n; ++j) {
    for (int p = 0; p < j; ++p) {
      const double l = L[j + p * n];
      for (int r = 0; r < n; ++r) X[r + j * n] -= X[r + p * n] * l;
    }
    for (int r = 0; r < n; ++r) X[r + j * n] *= Dinv[j];
  }
}

// C -= A B^T.
template <int n>
inline void SubtractProductNT(const double* __restrict A, const double* __restrict B,
                              double* __restrict C) {
  for (int c = 0; c < n; ++c) {
    for (int p = 0; p < n; ++p) {
      const double b = B[c + p * n];
      for (int r = 0; r < n; ++r) C[r + c * n] -= A[r + p * n] * b;
    }
  }
}

// Lower triangle of P -= L L^T.
template <int n>
inline void SubtractGramLower(const double* __restrict L, double* __restrict P) {
  for (int c = 0; c < n; ++c) {
    for (int p = 0; p < n; ++p) {
      const double l = L[c + p * n];
      for (int r = c; r < n; ++r) P[r + c * n] -= L[r + p * n] * l;
    }
  }
}

// In-place lower Cholesky factor (reads the lower triangle, zeroes the strict upper one) and the
// reciprocals of its diagonal in Dinv; false when a pivot is not positive and finite.
template <int n>
inline bool CholeskyLower(double* __restrict M, double* __restrict Dinv) {
  for (int j = 0; j < n; ++j) {
    double d = M[j + j * n];
    for (int p = 0; p < j; ++p) d -= M[j + p * n] * M[j + p * n];
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    const double l = std::sqrt(d);
    const double inverse = 1.0 / l;
    Dinv[j] = inverse;
    M[j + j * n] = l;
    for (int i = j + 1; i < n; ++i) {
      double s = M[i + j * n];
      for (int p = 0; p < j; ++p) s -= M[i + p * n] * M[j + p * n];
      M[i + j * n] = s * inverse;
    }
  }
  for (int j = 1; j < n; ++j) {
    for (int i = 0; i < j; ++i) M[i + j * n] = 0.0;
  }
  return true;
}

// y <- L^-T y for lower-triangular L with Dinv = 1 / diag(L) (L^-1 y: small_dense.hpp's
// LowerSolveVectorFixed).
template <int n>
inline void LowerTransposeSolve(const double* __restrict L, const double* __restrict Dinv,
                                double* __restrict y) {
  for (int j = n - 1; j >= 0; --j) {
    double s = y[j];
    for (int p = j + 1; p < n; ++p) s -= L[p + j * n] * y[p];
    y[j] = s * Dinv[j];
  }
}

// y -= X x (transposed: y -= X^T x).
template <int n, bool kTransposed>
inline void SubtractTimes(const double* __restrict X, const double* __restrict x,
                          double* __restrict y) {
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) {
      if constexpr (kTransposed) {
        y[c] -= X[r + c * n] * x[r];
      } else {
        y[r] -= X[r + c * n] * x[c];
      }
    }
  }
}

}  // namespace fixed_block_detail

/// The step's blocks for FactorStepFixed: L0, L1, L2 and D0 = 1 / diag(L0) of step i, and the
/// earlier steps' L0, D0 (i - 1, i - 2) and L1 (i - 1); null where i < 1 or 2.
struct FixedStepBlocks {
  double *L0, *L1, *L2, *D0;
  const double *L0m1, *D0m1, *L1m1, *L0m2, *D0m2;
};

/// FactorStep (math/penta_diagonal_blocks.hpp) for blocks of n rows; also writes b.D0.
template <int n>
bool FactorStepFixed(const FixedStepBlocks& b) {
  namespace d = fixed_block_detail;
  if (b.L0m2 != nullptr) {
    d::SolveRightLowerTransposed<n>(b.L0m2, b.D0m2, b.L2);
    d::SubtractProductNT<n>(b.L2, b.L1m1, b.L1);
  }
  if (b.L0m1 != nullptr) {
    d::SolveRightLowerTransposed<n>(b.L0m1, b.D0m1, b.L1);
    d::SubtractGramLower<n>(b.L1, b.L0);
  }
  if (b.L0m2 != nullptr) d::SubtractGramLower<n>(b.L2, b.L0);
  return d::CholeskyLower<n>(b.L0, b.D0);
}

/// Forward substitution step of one vector: y -= L1 y1 (y1 not null), y -= L2 y2 (y2 not
/// null), then y <- L0^-1 y (D0 = 1 / diag(L0)).
template <int n>
void ForwardStepFixed(const double* L0, const double* D0, const double* L1, const double* L2,
                      const double* y1, const double* y2, double* y) {
  namespace d = fixed_block_detail;
  if (y1 != nullptr) d::SubtractTimes<n, false>(L1, y1, y);
  if (y2 != nullptr) d::SubtractTimes<n, false>(L2, y2, y);
  small_dense_detail::LowerSolveVectorFixed<n>(L0, n, D0, y);
}

/// Backward substitution step of one vector: y -= L1n^T y1 (y1 not null), y -= L2n^T y2 (y2
/// not null), then y <- L0^-T y. L1n = L1[i+1], L2n = L2[i+2], D0 = 1 / diag(L0).
template <int n>
void BackwardStepFixed(const double* L0, const double* D0, const double* L1n, const double* L2n,
                       const double* y1, const double* y2, double* y) {
  namespace d = fixed_block_detail;
  if (y1 != nullptr) d::SubtractTimes<n, true>(L1n, y1, y);
  if (y2 != nullptr) d::SubtractTimes<n, true>(L2n, y2, y);
  d::LowerTransposeSolve<n>(L0, D0, y);
}

/// Calls F<n>() through `f` for the n in [1, kMaxFixedBlock] equal to `size` (f is a generic
/// lambda taking std::integral_constant<int, n>); false for other sizes.
template <int n = 1, typename F>
bool WithFixedBlockSize(int size, F&& f) {
  if (size == n) {
    f(std::integral_constant<int, n>{});
    return true;
  }
  if constexpr (n < kMaxFixedBlock) {
    return WithFixedBlockSize<n + 1>(size, f);
  } else {
    return false;
  }
}

}  // namespace idto::internal
