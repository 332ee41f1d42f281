#pragma once

// The Cholesky factorization of a PentaDiagonalMatrix in two halves that run on two threads
// (the penalty route's Newton step; docs/solver.md, "Two halves"). Private to src/.
//
// Blocks are eliminated in the order: 0..s-1 forward (the top half), N-1..s+2 backward (the
// bottom half), then the separator s, s+1 (s = (N-2)/2). H couples a block only to its two
// neighbours on each side, so no block of one half couples to a block of the other: the halves
// are independent, each the same block recursion as the natural order (the bottom one on the
// reversed blocks, whose off-diagonal blocks are the transposes of H's), with no fill-in and
// the flops of the natural order. The arithmetic does not depend on the thread count: one and
// two threads give bitwise the same factor and solution. Below kMinBlocks blocks or
// kMinBlockSize rows per block, the natural order (a parallel phase would cost more than it
// saves).

#include <Eigen/Core>

#include "idto/math/penta_diagonal_matrix.hpp"

namespace idto::internal {

class SplitPentaDiagonalCholesky {
 public:
  /// Smallest horizon and block size factored in two halves.
  static constexpr int kMinBlocks = 8;
  static constexpr int kMinBlockSize = 8;

  SplitPentaDiagonalCholesky() = default;
  /// Preallocates for N blocks of size n; `num_threads` >= 1 (two are used at most).
  SplitPentaDiagonalCholesky(int num_blocks, int block_size, int num_threads);

  /// Threads for the two halves, in [1, kMaxParallelThreads] (two are used at most; the result
  /// does not depend on it).
  void set_num_threads(int threads);

  /// Factors H (sizes as constructed; another size throws InvalidArgument). False when a pivot
  /// is not numerically positive definite; failed_block() then names its block row (when both
  /// halves fail, the top one's) and the factor is partly overwritten. No allocation.
  bool compute(const PentaDiagonalMatrix& H);
  int failed_block() const { return failed_block_; }
  /// True when the factorization runs in two halves (false: the natural order).
  bool two_halves() const { return split_ < num_blocks_; }

  /// Solves H x = b in place (b: N n); requires the last compute() to have succeeded. The halves of
  /// both sweeps run as two pool items (bitwise the same result on any thread count).
  void SolveInPlace(Eigen::VectorXd* b) const;

 private:
  template <typename X>
  void Solve(X&& x) const;
  bool FactorTop();
  void FactorBottom();
  bool FactorSeparator();

  const PentaDiagonalMatrix* H_{nullptr};  // during compute()
  int num_blocks_{0};
  int block_size_{0};
  int num_threads_{1};
  int split_{0};        // s; num_blocks_ when one-way
  int bottom_size_{0};  // R = N - s - 2 blocks in the bottom half
  // Top: positions 0..s+1 are blocks 0..s+1 (s and s+1: the separator's rows). Bottom:
  // position r is block N-1-r; positions R and R+1 (blocks s+1 and s) hold the separator rows'
  // entries in the bottom's columns (L1[R], L2[R], L2[R+1]) and, during compute(), the
  // bottom's contributions to the separator pivots (L0[R], L0[R+1]) and to H(s, s+1) (L1[R+1]).
  PentaDiagonalFactorBlocks top_, bottom_;
  int failed_block_{-1};
  int failed_half_[2]{-1, -1};
};

}  // namespace idto::internal
