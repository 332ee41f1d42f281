#pragma once

// Dense kernels for the blocks of the Gauss-Newton Hessian and of its block Cholesky factor
// (sizes nq, a few to a few dozen), private to src/. The library is compiled for baseline
// x86-64 (SSE2, no FMA), where Eigen's products on such small dynamic-size blocks run below a
// quarter of the FMA machine's peak. On a CPU with AVX2 and FMA these kernels run register-tiled
// 4-lane FMA code compiled for that CPU (a function-level target, chosen once at run time), and
// elsewhere the same Eigen expressions as before. Every entry is accumulated in a fixed order, so
// the results do not depend on the thread count; they differ in rounding between the two paths
// (FMA), never between two runs on one machine.
//
// All matrices are column-major with a leading dimension (ld) and are read and written in place.

#include <cmath>

#include <Eigen/Core>

namespace idto::internal {

/// The pivot test of the Cholesky kernels: true when pivot d is acceptable, d > tolerance ·
/// |original| and finite (tolerance 0: d must be positive; NaN and Inf always fail). Otherwise
/// *relative_pivot = d / |original| (d when original is 0).
inline bool AcceptPivot(double d, double tolerance, double original, double* relative_pivot) {
  if (d > tolerance * std::abs(original) && std::isfinite(d)) return true;
  *relative_pivot = original != 0.0 ? d / std::abs(original) : d;
  return false;
}

/// True when the CPU has AVX2 and FMA (and the build targets x86-64 with GCC or Clang).
bool Avx2KernelsAvailable();

/// True when the AVX2/FMA kernels run (the CPU has both and they are not switched off).
bool UseAvx2Kernels();

/// Switches the AVX2/FMA kernels off (false) or back on where the CPU has them (true), for
/// tests that compare both paths; the initial state is on where available, unless the
/// environment variable IDTO_PORTABLE_KERNELS is set (and not "0"). Call it only while no solve
/// runs.
void SetAvx2KernelsEnabledForTesting(bool enabled);

namespace avx2 {

/// C (m x n) += alpha A B^T for A (m x k) and B (n x k). With lower_only (m == n), only the
/// entries on and below C's diagonal are read and written. Aliasing: C must not overlap A or B.
/// Requires UseAvx2Kernels().
void AddProductNT(int m, int n, int k, double alpha, const double* A, int lda, const double* B,
                  int ldb, bool lower_only, double* C, int ldc);

/// C (m x n) += alpha A B for A (m x k) and B (k x n, leading dimension ldb); lower_only as in
/// AddProductNT. Requires UseAvx2Kernels().
void AddProductNN(int m, int n, int k, double alpha, const double* A, int lda, const double* B,
                  int ldb, bool lower_only, double* C, int ldc);

/// X (size x cols) <- L^-1 X for L (size x size) lower triangular, given the reciprocals of its
/// diagonal (only the strictly lower triangle of L is read). Requires UseAvx2Kernels().
void LowerSolve(int size, const double* L, int ldl, const double* inverse_diagonal, double* X,
                int ldx, int cols);

/// X (m x n) <- X L^-T for L (n x n) lower triangular with a nonzero diagonal (only its lower
/// triangle is read). Requires UseAvx2Kernels().
void SolveRightLowerTransposed(int m, int n, const double* L, int ldl, double* X, int ldx);

/// In-place lower Cholesky factor of S (n x n): reads the lower triangle, zeroes the strict upper
/// one. False when a pivot is not positive and finite. Requires UseAvx2Kernels().
bool CholeskyInPlace(int n, double* S, int lds);

/// Cholesky of columns [begin, end) of the lower triangle of the size x size M, in place, with
/// the pivot test AcceptPivot(d, tolerance, diagonal[k]), as CholeskyColumnsInPlace of
/// math/small_dense.hpp (which calls it from blocks of 16 up): the trailing block receives the
/// Schur complement update (lower triangle); entries above the diagonal inside [begin, end)
/// are left modified (not part of the result). Returns the failing column or -1;
/// inverse_diagonal[k] = 1 / L(k, k). diagonal and inverse_diagonal may be null (scales 0, no
/// reciprocals stored). Requires UseAvx2Kernels().
int CholeskyColumns(double tolerance, const double* diagonal, int size, int begin, int end,
                    double* M, int ld, double* inverse_diagonal, double* relative_pivot);

}  // namespace avx2

/// C += alpha A B^T for A and B with C's row count as rows and the same column count, through
/// the AVX2/FMA kernel where it runs and Eigen's product elsewhere (with lower_only, C square:
/// only C's lower triangle is updated; Eigen's symmetric rank update when A and B are the same
/// matrix).
inline void AddProductNT(double alpha, const Eigen::Ref<const Eigen::MatrixXd>& A,
                         const Eigen::Ref<const Eigen::MatrixXd>& B, bool lower_only,
                         Eigen::Ref<Eigen::MatrixXd> C) {
  if (UseAvx2Kernels()) {
    avx2::AddProductNT(
        static_cast<int>(C.rows()), static_cast<int>(C.cols()), static_cast<int>(A.cols()), alpha,
        A.data(), static_cast<int>(A.outerStride()), B.data(), static_cast<int>(B.outerStride()),
        lower_only, C.data(), static_cast<int>(C.outerStride()));
  } else if (lower_only && A.data() == B.data()) {
    C.selfadjointView<Eigen::Lower>().rankUpdate(A, alpha);
  } else if (lower_only) {
    C.triangularView<Eigen::Lower>() += alpha * A * B.transpose();
  } else {
    C.noalias() += alpha * A * B.transpose();
  }
}

}  // namespace idto::internal
