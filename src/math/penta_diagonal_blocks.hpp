#pragma once

// The block recursion of the penta-diagonal Cholesky factorization H = L L^T, shared by the
// natural-order factor (PentaDiagonalCholesky) and the two-half one
// (SplitPentaDiagonalCholesky). Private to src/.
//
// Along an elimination order of the blocks (index i = position in the order), L0[i] is the
// lower Cholesky factor of the i-th pivot, L1[i] = L(i, i-1) and L2[i] = L(i, i-2). A step
// starts with L2[i] = H(i, i-2), L1[i] = H(i, i-1) and L0[i] = H(i, i) loaded (only L0's lower
// triangle is read) and ends with the factor's blocks:
//   L2[i] = H(i, i-2) L0[i-2]^-T,
//   L1[i] = (H(i, i-1) - L2[i] L1[i-1]^T) L0[i-1]^-T,
//   L0[i] = chol(H(i, i) - L2[i] L2[i]^T - L1[i] L1[i]^T).

#include <Eigen/Core>

#include "idto/math/penta_diagonal_matrix.hpp"
#include "math/fixed_block_steps.hpp"

namespace idto::internal {

// In-place lower Cholesky of a small dense block: reads the lower triangle, zeroes the strict
// upper one. False when a pivot is not positive and finite (no allocation).
bool CholeskyInPlace(Eigen::MatrixXd* S);

// The part of step i that needs L0[i-2] (i >= 2): L2[i] <- L2[i] L0[i-2]^-T,
// L1[i] -= L2[i] L1[i-1]^T, lower(L0[i]) -= L2[i] L2[i]^T.
void EliminateSecondNeighbour(int i, PentaDiagonalFactorBlocks* f);

// The part of step i that needs L0[i-1] (i >= 1): L1[i] <- L1[i] L0[i-1]^-T,
// lower(L0[i]) -= L1[i] L1[i]^T.
void EliminateFirstNeighbour(int i, PentaDiagonalFactorBlocks* f);

// Both parts, then the pivot's Cholesky factor; false when the pivot is not positive definite.
bool FactorStep(int i, PentaDiagonalFactorBlocks* f);

// Forward substitution step i of L y = b in place: x(i) -= L1[i] x(i-1) + L2[i] x(i-2) for the
// neighbours at positions >= first, then x(i) <- L0[i]^-1 x(i). x(j): the rows of position j
// (an n-row block of a vector or matrix).
template <typename XBlock>
void ForwardSubstitutionStep(const PentaDiagonalFactorBlocks& f, int i, int first,
                             const XBlock& x) {
  auto xi = x(i);
  using Xi = decltype(xi);
  if constexpr (Xi::ColsAtCompileTime == 1 && Xi::InnerStrideAtCompileTime == 1) {
    const auto fixed = [&](auto size) {
      ForwardStepFixed<decltype(size)::value>(
          f.L0[i].data(), f.D0[i].data(), f.L1[i].data(), f.L2[i].data(),
          i - 1 >= first ? x(i - 1).data() : nullptr, i - 2 >= first ? x(i - 2).data() : nullptr,
          xi.data());
    };
    if (WithFixedBlockSize(static_cast<int>(xi.rows()), fixed)) return;
  }
  if (i - 1 >= first) xi.noalias() -= f.L1[i] * x(i - 1);
  if (i - 2 >= first) xi.noalias() -= f.L2[i] * x(i - 2);
  f.L0[i].template triangularView<Eigen::Lower>().solveInPlace(xi);
}

// Backward substitution step i of L^T x = y in place, positions up to end - 1 already solved:
// x(i) -= L1[i+1]^T x(i+1) + L2[i+2]^T x(i+2) (those below `end`), then x(i) <- L0[i]^-T x(i).
template <typename XBlock>
void BackwardSubstitutionStep(const PentaDiagonalFactorBlocks& f, int i, int end, const XBlock& x) {
  auto xi = x(i);
  using Xi = decltype(xi);
  if constexpr (Xi::ColsAtCompileTime == 1 && Xi::InnerStrideAtCompileTime == 1) {
    const auto fixed = [&](auto size) {
      BackwardStepFixed<decltype(size)::value>(
          f.L0[i].data(), f.D0[i].data(), i + 1 < end ? f.L1[i + 1].data() : nullptr,
          i + 2 < end ? f.L2[i + 2].data() : nullptr, i + 1 < end ? x(i + 1).data() : nullptr,
          i + 2 < end ? x(i + 2).data() : nullptr, xi.data());
    };
    if (WithFixedBlockSize(static_cast<int>(xi.rows()), fixed)) return;
  }
  if (i + 1 < end) xi.noalias() -= f.L1[i + 1].transpose() * x(i + 1);
  if (i + 2 < end) xi.noalias() -= f.L2[i + 2].transpose() * x(i + 2);
  f.L0[i].template triangularView<Eigen::Lower>().transpose().solveInPlace(xi);
}

}  // namespace idto::internal
