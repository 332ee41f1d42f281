#include "idto/math/penta_diagonal_matrix.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "idto/core/errors.hpp"
#include "math/block_kernels.hpp"
#include "math/penta_diagonal_blocks.hpp"

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
  if (y->size() != rows()) y->resize(rows());
  MultiplyRows(x, 0, num_blocks_, y);
}

namespace {

// MultiplyRows for blocks of n rows known at compile time: fixed-size products, unrolled (Eigen's
// dynamic-size matrix-vector products spend most of their time dispatching at these sizes).
template <int n>
void MultiplyRowsFixed(const std::vector<Eigen::MatrixXd>& A, const std::vector<Eigen::MatrixXd>& B,
                       const std::vector<Eigen::MatrixXd>& C, const double* x, int begin, int end,
                       double* y) {
  using Block = Eigen::Map<const Eigen::Matrix<double, n, n>>;
  using Segment = Eigen::Map<const Eigen::Matrix<double, n, 1>>;
  const int N = static_cast<int>(C.size());
  for (int k = begin; k < end; ++k) {
    Eigen::Matrix<double, n, 1> yk = Block(C[k].data()) * Segment(x + k * n);
    if (k >= 1) yk.noalias() += Block(B[k].data()) * Segment(x + (k - 1) * n);
    if (k >= 2) yk.noalias() += Block(A[k].data()) * Segment(x + (k - 2) * n);
    if (k + 1 < N) yk.noalias() += Block(B[k + 1].data()).transpose() * Segment(x + (k + 1) * n);
    if (k + 2 < N) yk.noalias() += Block(A[k + 2].data()).transpose() * Segment(x + (k + 2) * n);
    Eigen::Map<Eigen::Matrix<double, n, 1>>(y + k * n) = yk;
  }
}

}  // namespace

void PentaDiagonalMatrix::MultiplyRows(const Eigen::VectorXd& x, int begin, int end,
                                       Eigen::VectorXd* y) const {
  const int n = block_size_;
  const int N = num_blocks_;
  const auto fixed = [&](auto size) {
    MultiplyRowsFixed<decltype(size)::value>(A_, B_, C_, x.data(), begin, end, y->data());
  };
  if (internal::WithFixedBlockSize(n, fixed)) return;
  for (int k = begin; k < end; ++k) {
    // y_k = C_k x_k + B_k x_{k-1} + A_k x_{k-2} + B_{k+1}^T x_{k+1} + A_{k+2}^T x_{k+2}.
    auto yk = y->segment(k * n, n);
    yk.noalias() = C_[k] * x.segment(k * n, n);
    if (k >= 1) yk.noalias() += B_[k] * x.segment((k - 1) * n, n);
    if (k >= 2) yk.noalias() += A_[k] * x.segment((k - 2) * n, n);
    if (k + 1 < N) yk.noalias() += B_[k + 1].transpose() * x.segment((k + 1) * n, n);
    if (k + 2 < N) yk.noalias() += A_[k + 2].transpose() * x.segment((k + 2) * n, n);
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
  f_.Resize(num_blocks, block_size);
}

PentaDiagonalCholesky& PentaDiagonalCholesky::compute(const PentaDiagonalMatrix& H) {
  if (H.num_blocks() != num_blocks_ || H.block_size() != block_size_) {
    *this = PentaDiagonalCholesky(H.num_blocks(), H.block_size());
  }
  failed_block_ = -1;
  for (int k = 0; k < num_blocks_; ++k) {
    if (k >= 2) f_.L2[k] = H.A(k);
    if (k >= 1) f_.L1[k] = H.B(k);
    f_.L0[k] = H.C(k);
    if (!internal::FactorStep(k, &f_)) {
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
void ForwardSubstitution(const internal::PentaDiagonalFactorBlocks& f, int n, int first, X&& x) {
  const auto block = [&x, n](int k) { return x.middleRows(k * n, n); };
  const int num_blocks = static_cast<int>(f.L0.size());
  for (int k = std::max(first, 0); k < num_blocks; ++k) {
    internal::ForwardSubstitutionStep(f, k, first, block);
  }
}

// L^T X = Y in place (backward substitution).
template <typename X>
void BackwardSubstitution(const internal::PentaDiagonalFactorBlocks& f, int n, X&& x) {
  const auto block = [&x, n](int k) { return x.middleRows(k * n, n); };
  const int num_blocks = static_cast<int>(f.L0.size());
  for (int k = num_blocks - 1; k >= 0; --k) {
    internal::BackwardSubstitutionStep(f, k, num_blocks, block);
  }
}

}  // namespace

void PentaDiagonalCholesky::SolveInPlace(Eigen::VectorXd* b) const {
  ForwardSubstitution(f_, block_size_, 0, *b);
  BackwardSubstitution(f_, block_size_, *b);
}

void PentaDiagonalCholesky::SolveInPlace(Eigen::MatrixXd* B) const {
  ForwardSubstitution(f_, block_size_, 0, *B);
  BackwardSubstitution(f_, block_size_, *B);
}

void PentaDiagonalCholesky::SolveLowerInPlace(Eigen::Ref<Eigen::MatrixXd> B,
                                              int first_block) const {
  ForwardSubstitution(f_, block_size_, first_block, B);
}

void PentaDiagonalCholesky::SolveLowerInPlace(Eigen::VectorXd* b) const {
  ForwardSubstitution(f_, block_size_, 0, *b);
}

namespace internal {

void PentaDiagonalFactorBlocks::Resize(int count, int n) {
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(n, n);
  L0.assign(count, zero);
  L1.assign(count, zero);
  L2.assign(count, zero);
  D0.assign(count, Eigen::VectorXd::Zero(n));
}

bool CholeskyInPlace(Eigen::MatrixXd* S) {
  const int n = static_cast<int>(S->rows());
  if (UseAvx2Kernels()) return avx2::CholeskyInPlace(n, S->data(), n);
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

namespace {

// Lower triangle of P -= L L^T. Only the lower triangle is formed, except on the portable path
// below blocks of 8, where the full product is faster (measured: the spinner's blocks of 3 took
// 1.6x as long with Eigen's rankUpdate).
void SubtractGram(const Eigen::MatrixXd& L, Eigen::MatrixXd* P) {
  if (!UseAvx2Kernels() && L.rows() < 8) {
    P->noalias() -= L * L.transpose();
  } else {
    AddProductNT(-1.0, L, L, true, *P);
  }
}

void SolveRightLowerTransposed(const Eigen::MatrixXd& L, Eigen::MatrixXd* X) {
  if (UseAvx2Kernels()) {
    const int m = static_cast<int>(X->rows()), n = static_cast<int>(L.rows());
    avx2::SolveRightLowerTransposed(m, n, L.data(), n, X->data(), m);
    return;
  }
  L.transpose().triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(*X);
}

}  // namespace

void EliminateSecondNeighbour(int i, PentaDiagonalFactorBlocks* f) {
  SolveRightLowerTransposed(f->L0[i - 2], &f->L2[i]);
  AddProductNT(-1.0, f->L2[i], f->L1[i - 1], false, f->L1[i]);
  SubtractGram(f->L2[i], &f->L0[i]);
}

void EliminateFirstNeighbour(int i, PentaDiagonalFactorBlocks* f) {
  SolveRightLowerTransposed(f->L0[i - 1], &f->L1[i]);
  SubtractGram(f->L1[i], &f->L0[i]);
}

bool FactorStep(int i, PentaDiagonalFactorBlocks* f) {
  bool ok = false;
  const auto fixed = [&](auto size) {
    const bool one = i >= 1, two = i >= 2;
    const FixedStepBlocks b{f->L0[i].data(),
                            f->L1[i].data(),
                            f->L2[i].data(),
                            f->D0[i].data(),
                            one ? f->L0[i - 1].data() : nullptr,
                            one ? f->D0[i - 1].data() : nullptr,
                            two ? f->L1[i - 1].data() : nullptr,
                            two ? f->L0[i - 2].data() : nullptr,
                            two ? f->D0[i - 2].data() : nullptr};
    ok = FactorStepFixed<decltype(size)::value>(b);
  };
  if (WithFixedBlockSize(static_cast<int>(f->L0[i].rows()), fixed)) return ok;
  // The operations of EliminateSecondNeighbour and EliminateFirstNeighbour, with the pivot
  // updated by L1 before L2 (the order of the natural-order factorization since issue 5).
  if (i >= 2) {
    SolveRightLowerTransposed(f->L0[i - 2], &f->L2[i]);
    AddProductNT(-1.0, f->L2[i], f->L1[i - 1], false, f->L1[i]);
  }
  if (i >= 1) EliminateFirstNeighbour(i, f);
  if (i >= 2) SubtractGram(f->L2[i], &f->L0[i]);
  return CholeskyInPlace(&f->L0[i]);
}

}  // namespace internal

}  // namespace idto
