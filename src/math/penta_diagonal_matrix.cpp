#include "idto/math/penta_diagonal_matrix.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "idto/core/errors.hpp"

namespace idto {

PentaDiagonalMatrix::PentaDiagonalMatrix(int num_blocks, int block_size)
    : num_blocks_(num_blocks), block_size_(block_size) {
  if (num_blocks < 0 || block_size < 0) {
    ThrowInvalidArgument("PentaDiagonalMatrix", "size",
                         std::to_string(num_blocks) + " x " + std::to_string(block_size),
                         "non-negative numbers of blocks and block size");
  }
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(block_size, block_size);
  A_.assign(num_blocks, zero);
  B_.assign(num_blocks, zero);
  C_.assign(num_blocks, zero);
}

void PentaDiagonalMatrix::SetZero() {
  for (int k = 0; k < num_blocks_; ++k) {
    A_[k].setZero();
    B_[k].setZero();
    C_[k].setZero();
  }
}

void PentaDiagonalMatrix::Multiply(const Eigen::VectorXd& x, Eigen::VectorXd* y) const {
  const int n = block_size_;
  if (y->size() != rows()) y->resize(rows());
  y->setZero();
  for (int k = 0; k < num_blocks_; ++k) {
    auto yk = y->segment(k * n, n);
    yk.noalias() += C_[k] * x.segment(k * n, n);
    if (k >= 1) {
      yk.noalias() += B_[k] * x.segment((k - 1) * n, n);
      y->segment((k - 1) * n, n).noalias() += B_[k].transpose() * x.segment(k * n, n);
    }
    if (k >= 2) {
      yk.noalias() += A_[k] * x.segment((k - 2) * n, n);
      y->segment((k - 2) * n, n).noalias() += A_[k].transpose() * x.segment(k * n, n);
    }
  }
}

void PentaDiagonalMatrix::Diagonal(Eigen::VectorXd* d) const {
  const int n = block_size_;
  if (d->size() != rows()) d->resize(rows());
  for (int k = 0; k < num_blocks_; ++k) d->segment(k * n, n) = C_[k].diagonal();
}

void PentaDiagonalMatrix::ScaleSymmetric(const Eigen::VectorXd& d) {
  const int n = block_size_;
  for (int k = 0; k < num_blocks_; ++k) {
    const auto dk = d.segment(k * n, n);
    C_[k] = dk.asDiagonal() * C_[k] * dk.asDiagonal();
    if (k >= 1) B_[k] = dk.asDiagonal() * B_[k] * d.segment((k - 1) * n, n).asDiagonal();
    if (k >= 2) A_[k] = dk.asDiagonal() * A_[k] * d.segment((k - 2) * n, n).asDiagonal();
  }
}

Eigen::MatrixXd PentaDiagonalMatrix::MakeDense() const {
  const int n = block_size_;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(rows(), rows());
  for (int k = 0; k < num_blocks_; ++k) {
    H.block(k * n, k * n, n, n) = C_[k];
    if (k >= 1) {
      H.block(k * n, (k - 1) * n, n, n) = B_[k];
      H.block((k - 1) * n, k * n, n, n) = B_[k].transpose();
    }
    if (k >= 2) {
      H.block(k * n, (k - 2) * n, n, n) = A_[k];
      H.block((k - 2) * n, k * n, n, n) = A_[k].transpose();
    }
  }
  return H;
}

PentaDiagonalCholesky::PentaDiagonalCholesky(int num_blocks, int block_size)
    : num_blocks_(num_blocks), block_size_(block_size) {
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(block_size, block_size);
  L2_.assign(num_blocks, zero);
  L1_.assign(num_blocks, zero);
  L0_.assign(num_blocks, zero);
  work_ = zero;
}

namespace {

// In-place lower Cholesky of a small dense block (no allocation). Returns false when a pivot is
// not positive and finite.
bool CholeskyInPlace(Eigen::MatrixXd* S) {
  const int n = static_cast<int>(S->rows());
  Eigen::MatrixXd& M = *S;
  for (int j = 0; j < n; ++j) {
    double d = M(j, j);
    for (int p = 0; p < j; ++p) d -= M(j, p) * M(j, p);
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    const double ljj = std::sqrt(d);
    M(j, j) = ljj;
    for (int i = j + 1; i < n; ++i) {
      double s = M(i, j);
      for (int p = 0; p < j; ++p) s -= M(i, p) * M(j, p);
      M(i, j) = s / ljj;
    }
  }
  for (int j = 1; j < n; ++j) {
    for (int i = 0; i < j; ++i) M(i, j) = 0.0;
  }
  return true;
}

}  // namespace

PentaDiagonalCholesky& PentaDiagonalCholesky::compute(const PentaDiagonalMatrix& H) {
  if (H.num_blocks() != num_blocks_ || H.block_size() != block_size_) {
    *this = PentaDiagonalCholesky(H.num_blocks(), H.block_size());
  }
  failed_block_ = -1;
  for (int k = 0; k < num_blocks_; ++k) {
    // L(k,k-2) = A(k) L(k-2,k-2)^-T
    if (k >= 2) {
      L2_[k] = H.A(k);
      L0_[k - 2].transpose().triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(L2_[k]);
    }
    // L(k,k-1) = (B(k) - L(k,k-2) L(k-1,k-2)^T) L(k-1,k-1)^-T
    if (k >= 1) {
      L1_[k] = H.B(k);
      if (k >= 2) L1_[k].noalias() -= L2_[k] * L1_[k - 1].transpose();
      L0_[k - 1].transpose().triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(L1_[k]);
    }
    // L(k,k) = chol(C(k) - L(k,k-2) L(k,k-2)^T - L(k,k-1) L(k,k-1)^T)
    L0_[k] = H.C(k);
    if (k >= 1) L0_[k].noalias() -= L1_[k] * L1_[k].transpose();
    if (k >= 2) L0_[k].noalias() -= L2_[k] * L2_[k].transpose();
    if (!CholeskyInPlace(&L0_[k])) {
      info_ = Info::kNumericalIssue;
      failed_block_ = k;
      return *this;
    }
  }
  info_ = Info::kSuccess;
  return *this;
}

namespace {

// L Y = B in place (forward substitution), rows above `first` known to be zero and skipped.
// X: a vector or a matrix (any block of columns).
template <typename X>
void ForwardSubstitution(const std::vector<Eigen::MatrixXd>& L0,
                         const std::vector<Eigen::MatrixXd>& L1,
                         const std::vector<Eigen::MatrixXd>& L2, int n, int first, X&& x) {
  const int num_blocks = static_cast<int>(L0.size());
  for (int k = std::max(first, 0); k < num_blocks; ++k) {
    auto xk = x.middleRows(k * n, n);
    if (k - 1 >= first) xk.noalias() -= L1[k] * x.middleRows((k - 1) * n, n);
    if (k - 2 >= first) xk.noalias() -= L2[k] * x.middleRows((k - 2) * n, n);
    L0[k].template triangularView<Eigen::Lower>().solveInPlace(xk);
  }
}

// L^T X = Y in place (backward substitution).
template <typename X>
void BackwardSubstitution(const std::vector<Eigen::MatrixXd>& L0,
                          const std::vector<Eigen::MatrixXd>& L1,
                          const std::vector<Eigen::MatrixXd>& L2, int n, X&& x) {
  const int num_blocks = static_cast<int>(L0.size());
  for (int k = num_blocks - 1; k >= 0; --k) {
    auto xk = x.middleRows(k * n, n);
    if (k + 1 < num_blocks) {
      xk.noalias() -= L1[k + 1].transpose() * x.middleRows((k + 1) * n, n);
    }
    if (k + 2 < num_blocks) {
      xk.noalias() -= L2[k + 2].transpose() * x.middleRows((k + 2) * n, n);
    }
    L0[k].template triangularView<Eigen::Lower>().transpose().solveInPlace(xk);
  }
}

}  // namespace

void PentaDiagonalCholesky::SolveInPlace(Eigen::VectorXd* b) const {
  ForwardSubstitution(L0_, L1_, L2_, block_size_, 0, *b);
  BackwardSubstitution(L0_, L1_, L2_, block_size_, *b);
}

void PentaDiagonalCholesky::SolveInPlace(Eigen::MatrixXd* B) const {
  ForwardSubstitution(L0_, L1_, L2_, block_size_, 0, *B);
  BackwardSubstitution(L0_, L1_, L2_, block_size_, *B);
}

void PentaDiagonalCholesky::SolveLowerInPlace(Eigen::Ref<Eigen::MatrixXd> B,
                                              int first_block) const {
  ForwardSubstitution(L0_, L1_, L2_, block_size_, first_block, B);
}

void PentaDiagonalCholesky::SolveLowerInPlace(Eigen::VectorXd* b) const {
  ForwardSubstitution(L0_, L1_, L2_, block_size_, 0, *b);
}

}  // namespace idto
