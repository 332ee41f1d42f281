#pragma once

/// @file
/// Symmetric block-pentadiagonal matrices (the Gauss-Newton Hessian of IDTO, paper §5.3) and
/// their block Cholesky factorization, O(N n^3) time and O(N n^2) memory.

#include <vector>

#include <Eigen/Core>

namespace idto {

/// A symmetric matrix of N x N blocks of size n x n whose nonzero blocks are (k, k-2),
/// (k, k-1) and (k, k) and their transposes. Only the lower blocks are stored:
/// A(k) = H(k, k-2), B(k) = H(k, k-1), C(k) = H(k, k) (C(k) symmetric, both triangles kept).
class PentaDiagonalMatrix {
 public:
  PentaDiagonalMatrix() = default;
  /// N block rows of size n; all blocks zero.
  PentaDiagonalMatrix(int num_blocks, int block_size);

  int num_blocks() const { return num_blocks_; }
  int block_size() const { return block_size_; }
  /// Total size N n.
  int rows() const { return num_blocks_ * block_size_; }

  Eigen::MatrixXd& A(int k) { return A_[k]; }
  Eigen::MatrixXd& B(int k) { return B_[k]; }
  Eigen::MatrixXd& C(int k) { return C_[k]; }
  const Eigen::MatrixXd& A(int k) const { return A_[k]; }
  const Eigen::MatrixXd& B(int k) const { return B_[k]; }
  const Eigen::MatrixXd& C(int k) const { return C_[k]; }

  void SetZero();
  /// y = H x (x, y: N n). y is resized; no allocation when already sized.
  void Multiply(const Eigen::VectorXd& x, Eigen::VectorXd* y) const;
  /// Block rows [begin, end) of y = H x (y already sized N n; other rows untouched). Each block
  /// row is computed on its own, so disjoint ranges can run on different threads with the same
  /// result as Multiply.
  void MultiplyRows(const Eigen::VectorXd& x, int begin, int end, Eigen::VectorXd* y) const;
  /// The diagonal (N n).
  void Diagonal(Eigen::VectorXd* d) const;
  /// Replaces H by D H D for a diagonal D given by its entries d (N n).
  void ScaleSymmetric(const Eigen::VectorXd& d);
  /// The dense matrix (for tests and small problems).
  Eigen::MatrixXd MakeDense() const;

 private:
  int num_blocks_{0};
  int block_size_{0};
  std::vector<Eigen::MatrixXd> A_, B_, C_;
};

namespace internal {
/// The blocks of a penta-diagonal Cholesky factor along an elimination order (position i):
/// L0[i] the lower Cholesky factor of the i-th pivot, L1[i] = L(i, i-1), L2[i] = L(i, i-2), each
/// n x n (src/math/penta_diagonal_blocks.hpp computes them).
struct PentaDiagonalFactorBlocks {
  std::vector<Eigen::MatrixXd> L0, L1, L2;
  /// 1 / diag(L0[i]) (n each), written and read by the fixed-size steps of blocks up to 6 rows.
  std::vector<Eigen::VectorXd> D0;
  /// `count` zero n x n blocks in each array (zero vectors in D0).
  void Resize(int count, int n);
};
}  // namespace internal

/// Block Cholesky factorization H = L L^T of a PentaDiagonalMatrix (L block lower triangular
/// with the same band). Eigen-like: construct (preallocates), compute(), info(), solve in place.
class PentaDiagonalCholesky {
 public:
  enum class Info { kSuccess, kNumericalIssue, kNotComputed };

  PentaDiagonalCholesky() = default;
  PentaDiagonalCholesky(int num_blocks, int block_size);

  /// Factors H. On failure (a block that is not numerically positive definite) info() is
  /// kNumericalIssue and failed_block() tells which block row; nothing throws.
  PentaDiagonalCholesky& compute(const PentaDiagonalMatrix& H);
  Info info() const { return info_; }
  int failed_block() const { return failed_block_; }

  /// Solves H x = b in place (b: N n). Requires info() == kSuccess.
  void SolveInPlace(Eigen::VectorXd* b) const;
  /// Solves H X = B in place for several right-hand sides (B: N n x m).
  void SolveInPlace(Eigen::MatrixXd* B) const;

  /// Forward substitution only: solves L Y = B in place (B: N n x m, any column block of a
  /// matrix). Rows above block `first_block` must be zero in B; they stay zero and are skipped
  /// (the Lagrange-multiplier step uses this: each constraint column is zero before its step).
  void SolveLowerInPlace(Eigen::Ref<Eigen::MatrixXd> B, int first_block = 0) const;
  /// Forward substitution L y = b in place (b: N n).
  void SolveLowerInPlace(Eigen::VectorXd* b) const;

 private:
  int num_blocks_{0};
  int block_size_{0};
  Info info_{Info::kNotComputed};
  int failed_block_{-1};
  // L0[k]: the lower Cholesky factor of pivot k; L1[k] = L(k, k-1), L2[k] = L(k, k-2).
  internal::PentaDiagonalFactorBlocks f_;
};

}  // namespace idto
