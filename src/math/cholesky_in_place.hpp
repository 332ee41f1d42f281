#pragma once

// The in-place lower Cholesky of the banded KKT factorization's pivot blocks, with a relative
// pivot tolerance (private to src/). (PentaDiagonalCholesky keeps its scalar loop: at block sizes
// below ~10 it measured faster than these column updates; at 23 these were 10 % faster.)

#include <cmath>

#include <Eigen/Core>

namespace idto::internal {

/// Factors the square matrix M = L Lᵀ in place, reading its lower triangle only, writing L there
/// and zeroing the upper triangle; no allocation (column updates by matrix-vector products). A
/// pivot d (before the square root) fails when !(d > tolerance · M_jj), M_jj the diagonal entry
/// before elimination (tolerance 0: d must be positive; NaN and Inf always fail). Returns the
/// failing row, or −1 on success, and *relative_pivot = d / |M_jj| of that row.
inline int CholeskyLowerInPlace(double tolerance, Eigen::Ref<Eigen::MatrixXd> M,
                                double* relative_pivot) {
  const int n = static_cast<int>(M.rows());
  for (int j = 0; j < n; ++j) {
    const double diagonal = M(j, j);
    const double d = diagonal - M.row(j).head(j).squaredNorm();
    if (!(d > tolerance * std::abs(diagonal)) || !std::isfinite(d)) {
      *relative_pivot = diagonal != 0.0 ? d / std::abs(diagonal) : d;
      return j;
    }
    const double ljj = std::sqrt(d);
    M(j, j) = ljj;
    const int below = n - j - 1;
    if (below > 0) {
      auto column = M.col(j).tail(below);
      column.noalias() -= M.bottomLeftCorner(below, j) * M.row(j).head(j).transpose();
      column /= ljj;
    }
  }
  M.triangularView<Eigen::StrictlyUpper>().setZero();
  return -1;
}

}  // namespace idto::internal
