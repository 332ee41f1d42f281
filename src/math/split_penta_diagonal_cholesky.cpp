#include "math/split_penta_diagonal_cholesky.hpp"

#include <algorithm>
#include <string>

#include "core/parallel.hpp"
#include "idto/core/errors.hpp"
#include "math/penta_diagonal_blocks.hpp"

// The fixed-size steps (blocks up to kMaxFixedBlock rows) keep 1 / diag(L0) for the
// substitution; the separator steps here do not write it, so the two-half order must stay
// above that size.
static_assert(idto::internal::SplitPentaDiagonalCholesky::kMinBlockSize >
                  idto::internal::kMaxFixedBlock,
              "two-half order only for blocks the fixed-size steps do not take");

namespace idto::internal {

SplitPentaDiagonalCholesky::SplitPentaDiagonalCholesky(int num_blocks, int block_size,
                                                       int num_threads)
    : num_blocks_(num_blocks), block_size_(block_size) {
  if (num_blocks < 0 || block_size < 0) {
    ThrowInvalidArgument("SplitPentaDiagonalCholesky", "size",
                         std::to_string(num_blocks) + " x " + std::to_string(block_size),
                         "non-negative numbers of blocks and block size");
  }
  set_num_threads(num_threads);
  const bool split = num_blocks >= kMinBlocks && block_size >= kMinBlockSize;
  split_ = split ? (num_blocks - 2) / 2 : num_blocks;
  bottom_size_ = split ? num_blocks - split_ - 2 : 0;
  top_.Resize(split ? split_ + 2 : num_blocks, block_size);
  bottom_.Resize(split ? bottom_size_ + 2 : 0, block_size);
}

void SplitPentaDiagonalCholesky::set_num_threads(int threads) {
  if (threads < 1 || threads > kMaxParallelThreads) {
    ThrowInvalidArgument("SplitPentaDiagonalCholesky::set_num_threads", "threads",
                         std::to_string(threads),
                         "in [1, " + std::to_string(kMaxParallelThreads) + "]");
  }
  num_threads_ = threads;
}

bool SplitPentaDiagonalCholesky::FactorTop() {
  const PentaDiagonalMatrix& H = *H_;
  const int end = two_halves() ? split_ : num_blocks_;
  for (int k = 0; k < end; ++k) {
    if (k >= 2) top_.L2[k] = H.A(k);
    if (k >= 1) top_.L1[k] = H.B(k);
    top_.L0[k] = H.C(k);
    if (!FactorStep(k, &top_)) {
      failed_half_[0] = k;
      return false;
    }
  }
  if (!two_halves()) return true;
  // The separator rows' entries in the top's columns, and the top's contributions to their
  // pivots and to H(s+1, s): all of step s but its Cholesky factor, the part of step s+1 that
  // does not need L0[s].
  const int s = split_;
  top_.L2[s] = H.A(s);
  top_.L1[s] = H.B(s);
  top_.L0[s] = H.C(s);
  EliminateSecondNeighbour(s, &top_);
  EliminateFirstNeighbour(s, &top_);
  top_.L2[s + 1] = H.A(s + 1);
  top_.L1[s + 1] = H.B(s + 1);
  top_.L0[s + 1] = H.C(s + 1);
  EliminateSecondNeighbour(s + 1, &top_);
  return true;
}

void SplitPentaDiagonalCholesky::FactorBottom() {
  const PentaDiagonalMatrix& H = *H_;
  const int N = num_blocks_, R = bottom_size_;
  // Position r is block N-1-r: H(N-1-r, N+1-r) = A(N+1-r)^T, H(N-1-r, N-r) = B(N-r)^T.
  for (int r = 0; r < R; ++r) {
    if (r >= 2) bottom_.L2[r] = H.A(N + 1 - r).transpose();
    if (r >= 1) bottom_.L1[r] = H.B(N - r).transpose();
    bottom_.L0[r] = H.C(N - 1 - r);
    if (!FactorStep(r, &bottom_)) {
      failed_half_[1] = N - 1 - r;
      return;
    }
  }
  // Position R (block s+1) and R+1 (block s): the bottom's columns of the separator rows, with
  // the bottom's contributions accumulated from zero in L0[R], L0[R+1] (the pivots) and
  // L1[R+1] (H(s, s+1); H(s, s+1) itself is added by the top).
  bottom_.L2[R] = H.A(N + 1 - R).transpose();
  bottom_.L1[R] = H.B(N - R).transpose();
  bottom_.L0[R].setZero();
  EliminateSecondNeighbour(R, &bottom_);
  EliminateFirstNeighbour(R, &bottom_);
  bottom_.L2[R + 1] = H.A(N - R).transpose();
  bottom_.L1[R + 1].setZero();
  bottom_.L0[R + 1].setZero();
  EliminateSecondNeighbour(R + 1, &bottom_);
}

bool SplitPentaDiagonalCholesky::FactorSeparator() {
  const int s = split_, R = bottom_size_;
  top_.L0[s].triangularView<Eigen::Lower>() += bottom_.L0[R + 1];
  if (!CholeskyInPlace(&top_.L0[s])) {
    failed_block_ = s;
    return false;
  }
  top_.L1[s + 1] += bottom_.L1[R + 1].transpose();
  top_.L0[s + 1].triangularView<Eigen::Lower>() += bottom_.L0[R];
  EliminateFirstNeighbour(s + 1, &top_);
  if (!CholeskyInPlace(&top_.L0[s + 1])) {
    failed_block_ = s + 1;
    return false;
  }
  return true;
}

bool SplitPentaDiagonalCholesky::compute(const PentaDiagonalMatrix& H) {
  if (H.num_blocks() != num_blocks_ || H.block_size() != block_size_) {
    ThrowInvalidArgument(
        "SplitPentaDiagonalCholesky::compute", "H",
        std::to_string(H.num_blocks()) + " x " + std::to_string(H.block_size()),
        std::to_string(num_blocks_) + " blocks of size " + std::to_string(block_size_));
  }
  H_ = &H;
  failed_block_ = failed_half_[0] = failed_half_[1] = -1;
  bool ok = true;
  if (!two_halves()) {
    ok = FactorTop();
    failed_block_ = failed_half_[0];
  } else {
    ParallelFor(0, 2, std::min(num_threads_, 2), [this](int half, int) {
      if (half == 0) {
        FactorTop();
      } else {
        FactorBottom();
      }
    });
    if (failed_half_[0] >= 0 || failed_half_[1] >= 0) {
      failed_block_ = failed_half_[0] >= 0 ? failed_half_[0] : failed_half_[1];
      ok = false;
    } else {
      ok = FactorSeparator();
    }
  }
  H_ = nullptr;
  return ok;
}

template <typename X>
void SplitPentaDiagonalCholesky::Solve(X&& x) const {
  const int n = block_size_, N = num_blocks_;
  const auto top = [&x, n](int k) { return x.middleRows(k * n, n); };
  if (!two_halves()) {
    for (int k = 0; k < N; ++k) ForwardSubstitutionStep(top_, k, 0, top);
    for (int k = N - 1; k >= 0; --k) BackwardSubstitutionStep(top_, k, N, top);
    return;
  }
  const int s = split_, R = bottom_size_;
  const auto bottom = [&x, n, N](int r) { return x.middleRows((N - 1 - r) * n, n); };
  // L y = b: the halves (independent: two pool items, the same arithmetic on one thread), the
  // bottom's columns of the separator rows, then the separator.
  ParallelFor(0, 2, std::min(num_threads_, 2), [&](int half, int) {
    if (half == 0) {
      for (int k = 0; k < s; ++k) ForwardSubstitutionStep(top_, k, 0, top);
    } else {
      for (int r = 0; r < R; ++r) ForwardSubstitutionStep(bottom_, r, 0, bottom);
    }
  });
  top(s).noalias() -= bottom_.L2[R + 1] * bottom(R - 1);
  top(s + 1).noalias() -= bottom_.L1[R] * bottom(R - 1);
  top(s + 1).noalias() -= bottom_.L2[R] * bottom(R - 2);
  ForwardSubstitutionStep(top_, s, 0, top);
  ForwardSubstitutionStep(top_, s + 1, 0, top);
  // L^T x = y: the separator, then each half (two pool items again; the bottom reads the
  // separator as its positions R and R+1, L1[R+1] unused).
  BackwardSubstitutionStep(top_, s + 1, s + 2, top);
  BackwardSubstitutionStep(top_, s, s + 2, top);
  ParallelFor(0, 2, std::min(num_threads_, 2), [&](int half, int) {
    if (half == 0) {
      for (int k = s - 1; k >= 0; --k) BackwardSubstitutionStep(top_, k, s + 2, top);
    } else {
      for (int r = R - 1; r >= 0; --r) BackwardSubstitutionStep(bottom_, r, R + 2, bottom);
    }
  });
}

void SplitPentaDiagonalCholesky::SolveInPlace(Eigen::VectorXd* b) const { Solve(*b); }

}  // namespace idto::internal
