#include "idto/solver/banded_kkt.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/parallel.hpp"
#include "idto/core/errors.hpp"
#include "math/small_dense.hpp"
#include "solver/extended_residual.hpp"

namespace idto {

// ------------------------------------------------------------------------------------------
// KktStatus

std::string KktStatus::Message() const {
  std::ostringstream os;
  os << "KKT factorization: ";
  switch (code) {
    case Code::kSuccess:
      os << "success";
      break;
    case Code::kNotFactored:
      os << "not factored";
      break;
    case Code::kHessianNotPositiveDefinite:
      os << "the Hessian is not positive definite at step j = " << step << " (row " << row
         << " of the block of q_" << step + 1 << ", relative pivot " << relative_pivot << ")";
      break;
    case Code::kConstraintsRankDeficient:
      os << "the constraints are rank-deficient at step j = " << step << " (row " << row << " of h_"
         << step << " depends on the rows of h_0..h_" << step << " before it, relative pivot "
         << relative_pivot << "); an unactuated DoF that no configuration can influence?";
      break;
  }
  return os.str();
}

// ------------------------------------------------------------------------------------------
// BandedKktSolver

BandedKktSolver::BandedKktSolver(int num_steps, int num_positions, int num_constraints) {
  Resize(num_steps, num_positions, num_constraints);
}

void BandedKktSolver::Resize(int num_steps, int num_positions, int num_constraints) {
  if (num_steps < 0 || num_positions < 0 || num_constraints < 0) {
    ThrowInvalidArgument("BandedKktSolver::Resize", "sizes (N, n, nu)",
                         std::to_string(num_steps) + ", " + std::to_string(num_positions) + ", " +
                             std::to_string(num_constraints),
                         "non-negative numbers");
  }
  num_steps_ = num_steps;
  n_ = num_positions;
  nu_ = num_constraints;
  m_ = n_ + nu_;
  const Eigen::MatrixXd mm = Eigen::MatrixXd::Zero(m_, m_);
  Vt1_.assign(num_steps_, mm);
  Vt2_.assign(num_steps_, mm);
  F_.assign(num_steps_, mm);
  const Eigen::VectorXd vm = Eigen::VectorXd::Zero(m_);
  for (Half& half : half_) half = Half{mm, mm, vm, KktStatus{}};
  // Two halves from a block size where the step's dense work outweighs a parallel phase
  // (measured: the hopper's m = 8 gains, ball + finger's m = 12 too) and a horizon with at
  // least 3 steps per half.
  two_half_split_ = m_ >= kTwoHalfMinBlock && num_steps_ >= 8 ? (num_steps_ - 2) / 2 : num_steps_;
  split_ = two_half_split_;
  for (int i = 0; i < 2; ++i) {
    E_[i] = Wt_[i] = mm;
    separator_scales_[0][i] = separator_scales_[1][i] = vm;
  }
  Wt1_ = C_ = mm;
  inverse_diagonal_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(num_steps_) * m_);
  z_ = Eigen::VectorXd::Zero(num_steps_ * m_);
  rp_ = Eigen::VectorXd::Zero(num_steps_ * n_);
  dp_ = rp_;
  rl_ = Eigen::VectorXd::Zero(num_steps_ * nu_);
  dl_ = rl_;
  work_m_[0] = work_m_[1] = Eigen::VectorXd::Zero(m_);
  status_ = KktStatus{};
  last_solve_extended_ = last_solve_needed_extended_ = false;
  H_ = nullptr;
  A_ = nullptr;
}

namespace {

/// Blocks of m = n + nu rows up to this have the factorization and the sweeps compiled for their
/// size (the spinner's m = 4, the acrobot's 3, the hopper's 8): the loops unroll and no call
/// dispatches on the size at run time. Larger blocks take the kernels of math/small_dense.hpp
/// with m at run time. Either way each entry gets the same operations in the same order.
constexpr int kMaxFixedKktBlock = 8;

/// Calls f(std::integral_constant<int, M>{}) with M = m for 1 <= m <= kMaxFixedKktBlock, else
/// with M = 0 (m at run time).
template <int M = 1, typename F>
decltype(auto) WithKktBlockSize(int m, F&& f) {
  if constexpr (M > kMaxFixedKktBlock) {
    return f(std::integral_constant<int, 0>{});
  } else {
    if (m == M) return f(std::integral_constant<int, M>{});
    return WithKktBlockSize<M + 1>(m, std::forward<F>(f));
  }
}

/// The dense kernels of the factorization and the sweeps on m × m blocks (leading dimension m):
/// M > 0 is m at compile time, M = 0 at run time.
template <int M>
struct KktKernels {
  /// X ← L⁻¹ X (X: m × cols), d = 1 / diag(L).
  static void LowerSolve(const double* L, const double* d, int m, double* X, int cols) {
    if constexpr (M > 0) {
      internal::small_dense_detail::LowerSolvePairsFixed<M>(L, M, d, X, M, cols);
    } else {
      internal::LowerSolveInPlace(L, m, d, m, X, m, cols);
    }
  }
  /// x ← L⁻ᵀ x (L's strictly upper triangle mirrors its lower one).
  static void LowerTransposeSolve(const double* L, const double* d, int m, double* x) {
    if constexpr (M > 0) {
      internal::small_dense_detail::LowerTransposeSolveFixed<M>(L, M, d, x);
    } else {
      internal::LowerTransposeSolveInPlace(L, m, d, m, x);
    }
  }
  /// y −= Aᵀ x.
  static void SubtractTransposeTimes(const double* A, int m, const double* x, double* y) {
    if constexpr (M > 0) {
      internal::small_dense_detail::SubtractTransposeTimesFixed<M>(A, M, x, y);
    } else {
      internal::SubtractTransposeTimes(A, m, m, m, x, y);
    }
  }
  /// y += A x.
  static void AddTimes(const double* A, int m, const double* x, double* y) {
    if constexpr (M > 0) {
      internal::small_dense_detail::AddTimesKernel<M>::Run(A, M, x, y);
    } else {
      internal::AddTimes(A, m, m, m, x, y);
    }
  }
  /// C ← C − T Σ X, Σ = diag(I_n, −I_{m−n}); `lower` as internal::SubtractSignedProduct.
  static void SubtractSignedProduct(const double* T, const double* X, int m, int n, bool lower,
                                    double* C) {
    if constexpr (M > 0) {
      internal::small_dense_detail::SubtractSignedProductFixedRows<M>(T, M, X, M, M, M, n, C, M);
    } else {
      internal::SubtractSignedProduct(T, m, X, m, m, m, m, n, lower, C, m);
    }
  }
  /// internal::CholeskyColumnsInPlace on the m × m block F.
  static int Cholesky(double tolerance, const double* scales, int m, int begin, int end, double* F,
                      double* inverse_diagonal, double* relative) {
    if constexpr (M > 0) {
      return internal::small_dense_detail::CholeskyColumnsRightLooking<M>(
          tolerance, scales, M, begin, end, F, M, inverse_diagonal, relative);
    } else {
      return internal::CholeskyColumnsInPlace(tolerance, scales, m, begin, end, F, m,
                                              inverse_diagonal, relative);
    }
  }
  /// T = Xᵀ (internal::Transpose, its loops bounded at compile time when M > 0).
  static void Transpose(const double* X, int m, double* T) {
    const int s = M > 0 ? M : m;
    internal::Transpose(X, s, s, s, T, s);
  }
};

/// Copies the r × c matrix B (column-major, leading dimension r), or its transpose, into the
/// block of the m × m matrix K whose top-left entry is (row, col).
inline void CopyBlock(const Eigen::MatrixXd& B, bool transpose, int row, int col, int m,
                      double* K) {
  const int rows = static_cast<int>(B.rows()), cols = static_cast<int>(B.cols());
  const double* b = B.data();
  if (transpose) {
    for (int j = 0; j < rows; ++j) {
      for (int i = 0; i < cols; ++i) K[row + i + (col + j) * m] = b[j + i * rows];
    }
  } else {
    for (int j = 0; j < cols; ++j) {
      for (int i = 0; i < rows; ++i) K[row + i + (col + j) * m] = b[i + j * rows];
    }
  }
}

}  // namespace

template <int M>
bool BandedKktSolver::FactorPivot(int r, double* scales, KktStatus* status) {
  // F holds D_r's lower triangle, D = [P Qᵀ; Q R] = F Σ Fᵀ with F = [Lp 0; Y Ls]: the first n
  // columns of a right-looking Cholesky give P = Lp Lpᵀ, Y = Q Lp⁻ᵀ and leave the Schur
  // complement S = R − Y Yᵀ in the trailing block; its negation −S = Ls Lsᵀ.
  const int m = M > 0 ? M : m_;
  const int n = n_;
  double* f = F_[r].data();
  for (int i = 0; i < n; ++i) scales[i] = f[i + i * m];
  double relative = 0.0;
  double* inverse = inverse_diagonal_.data() + static_cast<long>(r) * m;
  int row = KktKernels<M>::Cholesky(0.0, scales, m, 0, n, f, inverse, &relative);
  if (row >= 0) {
    *status = {KktStatus::Code::kHessianNotPositiveDefinite, r, row, relative};
    return false;
  }
  // The rank test's scale for constraint row u: the sum of the positive contributions to −S's
  // diagonal (|Y_u|² here, the p-parts of the earlier blocks in Eliminate*), about the row's
  // squared norm in the metric of H⁻¹, so d / scale is about the squared sine of the row's angle
  // with the span of the rows before it. (−S's own diagonal is no scale: for a dependent row it
  // is round-off itself.)
  for (int j = n; j < m; ++j) {
    for (int i = j; i < m; ++i) f[i + j * m] = -f[i + j * m];
    double norm = 0.0;
    for (int k = 0; k < n; ++k) norm += f[j + k * m] * f[j + k * m];
    scales[j] += norm;
  }
  row = KktKernels<M>::Cholesky(rank_tolerance_, scales, m, n, m, f, inverse, &relative);
  if (row >= 0) {
    *status = {KktStatus::Code::kConstraintsRankDeficient, r, row - n, relative};
    return false;
  }
  // The strictly upper triangle mirrors the lower one: row k of F, contiguous, for the backward
  // sweep's column-oriented F⁻ᵀ (internal::LowerTransposeSolveInPlace).
  for (int j = 1; j < m; ++j) {
    for (int i = 0; i < j; ++i) f[i + j * m] = f[j + i * m];
  }
  return true;
}

template <int M>
void BandedKktSolver::AddConstraintScale(const Eigen::MatrixXd& Vt, double* scales) const {
  const int m = M > 0 ? M : m_;
  const double* v = Vt.data();
  for (int j = n_; j < m; ++j) {
    double norm = 0.0;
    for (int i = 0; i < n_; ++i) norm += v[i + j * m] * v[i + j * m];
    scales[j] += norm;
  }
}

template <int M>
void BandedKktSolver::AssembleCoupling(int r, int c, Eigen::MatrixXd* Kt) const {
  const int m = M > 0 ? M : m_;
  double* k = Kt->data();
  std::fill(k, k + m * m, 0.0);
  if (c < r) {
    // K(c, r) = K(r, c)ᵀ: rows (p_c, λ_c), columns (p_r, λ_r): H(r, c)ᵀ and ∂h_r/∂q_{c+1}ᵀ; the
    // rows of λ_c are zero because h_c does not involve q_{r+1} for r > c.
    CopyBlock(c == r - 1 ? H_->B(r) : H_->A(r), true, 0, 0, m, k);
    CopyBlock(A_->Block(r, c + 1), true, 0, n_, m, k);
  } else {
    // K(c, r), c > r: H(c, r) and ∂h_c/∂q_{r+1}; the columns of λ_r are zero (h_r does not
    // involve q_{c+1}).
    CopyBlock(c == r + 1 ? H_->B(c) : H_->A(c), false, 0, 0, m, k);
    CopyBlock(A_->Block(c, r + 1), false, n_, 0, m, k);
  }
}

template <int M>
void BandedKktSolver::EliminateSecond(int r, int c2, bool diagonal, Eigen::MatrixXd* D,
                                      Eigen::MatrixXd* Vt2, double* scales, Half* half) const {
  const int m = M > 0 ? M : m_;
  double* d = D->data();
  std::fill(d, d + m * m, 0.0);
  if (diagonal) {
    CopyBlock(H_->C(r), false, 0, 0, m, d);
    CopyBlock(A_->Block(r, r + 1), false, n_, 0, m, d);
  }
  std::fill(scales + n_, scales + m, 0.0);
  if (c2 < 0) return;
  // Vt2 = F_c2⁻¹ K(c2, r); D −= Vt2ᵀ Σ Vt2.
  AssembleCoupling<M>(r, c2, Vt2);
  KktKernels<M>::LowerSolve(F_[c2].data(), InverseDiagonal(c2), m, Vt2->data(), m);
  AddConstraintScale<M>(*Vt2, scales);
  KktKernels<M>::Transpose(Vt2->data(), m, half->T2.data());
  KktKernels<M>::SubtractSignedProduct(half->T2.data(), Vt2->data(), m, n_, true, d);
}

template <int M>
void BandedKktSolver::EliminateFirst(int r, int c1, const Eigen::MatrixXd* Vt2, Eigen::MatrixXd* D,
                                     Eigen::MatrixXd* Vt1, double* scales, Half* half) const {
  if (c1 < 0) return;
  // U(r, c1)ᵀ = K(c1, r) − V(c1, c2) Σ V(r, c2)ᵀ, with T1 = V(c1, c2);
  // Vt1 = F_c1⁻¹ U(r, c1)ᵀ; D −= Vt1ᵀ Σ Vt1.
  const int m = M > 0 ? M : m_;
  AssembleCoupling<M>(r, c1, Vt1);
  if (Vt2 != nullptr) {
    KktKernels<M>::SubtractSignedProduct(half->T1.data(), Vt2->data(), m, n_, false, Vt1->data());
  }
  KktKernels<M>::LowerSolve(F_[c1].data(), InverseDiagonal(c1), m, Vt1->data(), m);
  AddConstraintScale<M>(*Vt1, scales);
  KktKernels<M>::Transpose(Vt1->data(), m, half->T1.data());
  KktKernels<M>::SubtractSignedProduct(half->T1.data(), Vt1->data(), m, n_, true, D->data());
}

template <int M>
void BandedKktSolver::FactorForwardHalf() {
  Half& half = half_[0];
  const int k = split_;
  double* scales = half.scales.data();
  for (int r = 0; r < k; ++r) {
    EliminateSecond<M>(r, r >= 2 ? r - 2 : -1, true, &F_[r], &Vt2_[r], scales, &half);
    EliminateFirst<M>(r, r - 1, r >= 2 ? &Vt2_[r] : nullptr, &F_[r], &Vt1_[r], scales, &half);
    if (!FactorPivot<M>(r, scales, &half.status)) return;
  }
  if (k == num_steps_) return;
  // The separator's forward part (k >= 3): D_k against k − 2 and k − 1; D_{k+1} against k − 1;
  // U(k + 1, k)ᵀ's part K(k, k + 1) − V(k, k − 1) Σ V(k + 1, k − 1)ᵀ, in Vt1_[k + 1].
  double* scales_k = separator_scales_[0][0].data();
  double* scales_k1 = separator_scales_[0][1].data();
  EliminateSecond<M>(k, k - 2, true, &F_[k], &Vt2_[k], scales_k, &half);
  EliminateFirst<M>(k, k - 1, &Vt2_[k], &F_[k], &Vt1_[k], scales_k, &half);
  EliminateSecond<M>(k + 1, k - 1, true, &F_[k + 1], &Vt2_[k + 1], scales_k1, &half);
  AssembleCoupling<M>(k + 1, k, &Vt1_[k + 1]);
  KktKernels<M>::SubtractSignedProduct(half.T1.data(), Vt2_[k + 1].data(), m_, n_, false,
                                       Vt1_[k + 1].data());
}

template <int M>
void BandedKktSolver::FactorBackwardHalf() {
  Half& half = half_[1];
  const int k = split_;
  const int N = num_steps_;
  if (k == N) return;
  double* scales = half.scales.data();
  for (int r = N - 1; r >= k + 2; --r) {
    EliminateSecond<M>(r, r + 2 < N ? r + 2 : -1, true, &F_[r], &Vt2_[r], scales, &half);
    EliminateFirst<M>(r, r + 1 < N ? r + 1 : -1, r + 2 < N ? &Vt2_[r] : nullptr, &F_[r], &Vt1_[r],
                      scales, &half);
    if (!FactorPivot<M>(r, scales, &half.status)) return;
    if (!BackwardPivotsWellScaled(r)) {
      half.weak_pivot = true;
      return;
    }
  }
  // The separator's backward part (N − k − 2 >= 3 steps above it): D_{k+1} against k + 3 and
  // k + 2; D_k against k + 2; C_ = −V(k, k + 2) Σ V(k + 1, k + 2)ᵀ. Without K's own blocks.
  double* scales_k = separator_scales_[1][0].data();
  double* scales_k1 = separator_scales_[1][1].data();
  EliminateSecond<M>(k + 1, k + 3, false, &E_[1], &Wt_[1], scales_k1, &half);
  EliminateFirst<M>(k + 1, k + 2, &Wt_[1], &E_[1], &Wt1_, scales_k1, &half);
  EliminateSecond<M>(k, k + 2, false, &E_[0], &Wt_[0], scales_k, &half);
  C_.setZero();  // half.T2 = Wt_[0]ᵀ = V(k, k + 2), from EliminateSecond
  KktKernels<M>::SubtractSignedProduct(half.T2.data(), Wt1_.data(), m_, n_, false, C_.data());
}

bool BandedKktSolver::BackwardPivotsWellScaled(int r) const {
  // 1e-6, i.e. ∂h_r/∂q_{r+1} about 1e-3 of h_r's other blocks: with every such block scaled by
  // eps the refined two-half step was 6e-16 off at eps = 1e-4, 3e-11 at 1e-5, 1e-7 at 1e-6
  // (BandedKkt.WeakNewestConstraintBlocksAreFactoredAccurately). In IDTO the block is about
  // M/δt² and the others are of its order, so the examples never fall back for this.
  constexpr double kBackwardPivotRatio = 1e-6;
  const Eigen::MatrixXd& F = F_[r];
  for (int u = 0; u < nu_; ++u) {
    double full = 0.0;
    for (int s = r - 1; s <= r + 1; ++s) {
      if (!A_->HasBlock(r, s)) continue;
      const Eigen::MatrixXd& J = A_->Block(r, s);
      const Eigen::MatrixXd& C = H_->C(s - 1);
      for (int i = 0; i < n_; ++i) {
        if (C(i, i) > 0.0) full += J(u, i) * J(u, i) / C(i, i);
      }
    }
    const double d = F(n_ + u, n_ + u) * F(n_ + u, n_ + u);
    if (!(d >= kBackwardPivotRatio * full)) return false;
  }
  return true;
}

template <int M>
bool BandedKktSolver::FactorSeparator() {
  const int k = split_;
  const int m = M > 0 ? M : m_;
  Half& half = half_[0];  // its scratch is free again
  // D_k and D_{k+1}: K's blocks less both halves' updates; U(k + 1, k)ᵀ likewise.
  for (int i = 0; i < 2; ++i) {
    F_[k + i].triangularView<Eigen::Lower>() += E_[i];
    separator_scales_[0][i].tail(nu_) += separator_scales_[1][i].tail(nu_);
  }
  Vt1_[k + 1] += C_;
  status_ = {KktStatus::Code::kSuccess, -1, -1, 0.0};
  if (!FactorPivot<M>(k, separator_scales_[0][0].data(), &status_)) return false;
  // Vt1 = F_k⁻¹ U(k + 1, k)ᵀ; D_{k+1} −= Vt1ᵀ Σ Vt1.
  double* scales = separator_scales_[0][1].data();
  Eigen::MatrixXd& Vt1 = Vt1_[k + 1];
  KktKernels<M>::LowerSolve(F_[k].data(), InverseDiagonal(k), m, Vt1.data(), m);
  AddConstraintScale<M>(Vt1, scales);
  KktKernels<M>::Transpose(Vt1.data(), m, half.T1.data());
  KktKernels<M>::SubtractSignedProduct(half.T1.data(), Vt1.data(), m, n_, true, F_[k + 1].data());
  return FactorPivot<M>(k + 1, scales, &status_);
}

KktStatus BandedKktSolver::Factor(const PentaDiagonalMatrix& H, const BlockConstraintJacobian& A) {
  if (H.num_blocks() != num_steps_ || H.block_size() != n_) {
    ThrowInvalidArgument(
        "BandedKktSolver::Factor", "H",
        std::to_string(H.num_blocks()) + " blocks of size " + std::to_string(H.block_size()),
        std::to_string(num_steps_) + " blocks of size " + std::to_string(n_));
  }
  if (A.num_steps() != num_steps_ || A.num_positions() != n_ || A.num_constraints() != nu_) {
    ThrowInvalidArgument(
        "BandedKktSolver::Factor", "A",
        "N, n, nu = " + std::to_string(A.num_steps()) + ", " + std::to_string(A.num_positions()) +
            ", " + std::to_string(A.num_constraints()),
        std::to_string(num_steps_) + ", " + std::to_string(n_) + ", " + std::to_string(nu_));
  }
  CheckBlockShapes(H, A);
  H_ = &H;
  A_ = &A;
  dispatch_size_ = compiled_block_sizes_ ? m_ : 0;
  return WithKktBlockSize(dispatch_size_,
                          [this](auto size) { return FactorInOrder<decltype(size)::value>(); });
}

void BandedKktSolver::CheckBlockShapes(const PentaDiagonalMatrix& H,
                                       const BlockConstraintJacobian& A) const {
  // The blocks are mutable references: one resized by its owner would be read out of bounds. The
  // message is built only on failure (no formatting per block on the hot path).
  const auto fits = [](const Eigen::MatrixXd& block, int rows, int cols) {
    return block.rows() == rows && block.cols() == cols;
  };
  const auto fail = [](const Eigen::MatrixXd& block, int rows, int cols, const char* argument,
                       const std::string& name) {
    ThrowInvalidArgument(
        "BandedKktSolver::Factor", argument,
        name + " of " + std::to_string(block.rows()) + " x " + std::to_string(block.cols()),
        std::to_string(rows) + " x " + std::to_string(cols));
  };
  for (int r = 0; r < num_steps_; ++r) {
    if (!fits(H.C(r), n_, n_)) fail(H.C(r), n_, n_, "H", "block C(" + std::to_string(r) + ")");
    if (r >= 1 && !fits(H.B(r), n_, n_)) {
      fail(H.B(r), n_, n_, "H", "block B(" + std::to_string(r) + ")");
    }
    if (r >= 2 && !fits(H.A(r), n_, n_)) {
      fail(H.A(r), n_, n_, "H", "block A(" + std::to_string(r) + ")");
    }
    for (int s = r - 1; s <= r + 1; ++s) {
      if (!A.HasBlock(r, s) || fits(A.Block(r, s), nu_, n_)) continue;
      fail(A.Block(r, s), nu_, n_, "A",
           "block (" + std::to_string(r) + ", " + std::to_string(s) + ")");
    }
  }
}

template <int M>
KktStatus BandedKktSolver::FactorInOrder() {
  // Signed block Cholesky of the interleaved matrix K (unknowns x_r = (p_r, λ_r)) in an
  // elimination order: K = G Σ̂ Gᵀ, G(r, r) = F_r, G(r, c) = V(r, c) Σ for the neighbours c
  // eliminated before r, with
  //   U(r, c) = K(r, c) − Σ_{i before c} V(r, i) Σ V(c, i)ᵀ,   V(r, c) = U(r, c) F_c⁻ᵀ,
  //   D_r = F_r Σ F_rᵀ = K(r, r) − Σ_{c before r} V(r, c) Σ V(r, c)ᵀ.
  // The order: steps 0..k−1 forward, N−1..k+2 backward, then k, k+1 (k = split_; the halves
  // are independent: no step of one is a neighbour of a step of the other). Each step has at
  // most two neighbours before it in its half and there is no fill-in, so U(r, c2) = K(r, c2).
  // Each off-diagonal block costs one triangular solve with F_c. D_r is symmetric: only its
  // lower triangle is formed (in F_[r]) and read. The products go through KktKernels<M> (sizes
  // fixed at compile time up to kMaxFixedKktBlock, else src/math/small_dense.hpp's kernels);
  // the transposes in Half turn the Σ-weighted products into column updates.
  for (Half& half : half_) {
    half.status = {KktStatus::Code::kSuccess, -1, -1, 0.0};
    half.weak_pivot = false;
  }
  split_ = two_half_split_;
  if (split_ < num_steps_) {
    ParallelFor(0, 2, std::min(num_threads_, 2), [this](int i, int) {
      if (i == 0) {
        FactorForwardHalf<M>();
      } else {
        FactorBackwardHalf<M>();
      }
    });
    if (half_[0].status.ok() && half_[1].status.ok() && !half_[1].weak_pivot &&
        FactorSeparator<M>()) {
      return status_;
    }
    // The backward half needs each ∂h_j/∂q_{j+1} of full row rank, and well scaled against h_j's
    // other blocks; the forward order only the leading rows h_0..h_j together (docs/solver.md,
    // "Two halves"): on any failure or weak pivot the forward order decides, and its status is
    // the one reported.
    split_ = num_steps_;
    half_[0].status = {KktStatus::Code::kSuccess, -1, -1, 0.0};
  }
  FactorForwardHalf<M>();
  status_ = half_[0].status;
  return status_;
}

void BandedKktSolver::set_num_threads(int threads) {
  if (threads < 1 || threads > kMaxParallelThreads) {
    ThrowInvalidArgument("BandedKktSolver::set_num_threads", "threads", std::to_string(threads),
                         "in [1, " + std::to_string(kMaxParallelThreads) + "]");
  }
  num_threads_ = threads;
}

void BandedKktSolver::set_extended_threshold(double threshold) {
  if (!(threshold >= 0.0)) {
    std::ostringstream value;
    value << threshold;
    ThrowInvalidArgument("BandedKktSolver::set_extended_threshold", "threshold", value.str(),
                         ">= 0 (infinity: never)");
  }
  extended_threshold_ = threshold;
}

int BandedKktSolver::Position(int r) const {
  const int k = split_;
  if (r < k) return r;
  if (r >= k + 2) return k + (num_steps_ - 1 - r);
  return num_steps_ - 2 + (r - k);
}

int BandedKktSolver::StepAt(int e) const {
  const int k = split_;
  if (e < k) return e;
  if (e < num_steps_ - 2) return num_steps_ - 1 - (e - k);
  return k + (e - (num_steps_ - 2));
}

const Eigen::MatrixXd& BandedKktSolver::Coupling(int r, int c) const {
  const int k = split_;
  if (r < k || (r <= k + 1 && c < r)) return c == r - 1 ? Vt1_[r] : Vt2_[r];
  if (r >= k + 2) return c == r + 1 ? Vt1_[r] : Vt2_[r];
  if (r == k) return Wt_[0];          // c = k + 2
  return c == k + 2 ? Wt1_ : Wt_[1];  // r = k + 1, c = k + 2 or k + 3
}

int BandedKktSolver::Neighbours(int r, int* c) const {
  int count = 0;
  for (int d : {-1, -2, 1, 2}) {
    if (r + d >= 0 && r + d < num_steps_) c[count++] = r + d;
  }
  return count;
}

template <int M>
void BandedKktSolver::ForwardSweep(int e_begin, int e_end) {
  const int m = M > 0 ? M : m_;
  double* z = z_.data();
  int c[4];
  for (int e = e_begin; e < e_end; ++e) {
    const int r = StepAt(e);
    double* zr = z + static_cast<long>(r) * m;
    const int count = Neighbours(r, c);
    for (int i = 0; i < count; ++i) {
      if (Position(c[i]) > e) continue;
      KktKernels<M>::SubtractTransposeTimes(Coupling(r, c[i]).data(), m,
                                            z + static_cast<long>(c[i]) * m, zr);
    }
    KktKernels<M>::LowerSolve(F_[r].data(), InverseDiagonal(r), m, zr, 1);
    for (int i = n_; i < m; ++i) zr[i] = -zr[i];
  }
}

template <int M>
void BandedKktSolver::BackwardSweep(int e_begin, int e_end, double* w) {
  const int m = M > 0 ? M : m_;
  double* z = z_.data();
  int c[4];
  for (int e = e_end - 1; e >= e_begin; --e) {
    const int r = StepAt(e);
    double* zr = z + static_cast<long>(r) * m;
    const int count = Neighbours(r, c);
    bool any = false;
    for (int i = 0; i < count; ++i) {
      if (Position(c[i]) < e) continue;
      if (!any) std::fill(w, w + m, 0.0);
      any = true;
      KktKernels<M>::AddTimes(Coupling(c[i], r).data(), m, z + static_cast<long>(c[i]) * m, w);
    }
    if (any) {
      for (int i = 0; i < n_; ++i) zr[i] -= w[i];
      for (int i = n_; i < m; ++i) zr[i] += w[i];
    }
    KktKernels<M>::LowerTransposeSolve(F_[r].data(), InverseDiagonal(r), m, zr);
  }
}

template <int M>
void BandedKktSolver::SolveInterleavedInPlace() {
  const int N = num_steps_;
  // Forward, G y = b in elimination order, stored as z_r = Σ y_r with y_r = F_r⁻¹ (b_r −
  // Σ_{c before r} V(r, c) z_c); backward, Gᵀ x = z, x_r = F_r⁻ᵀ (z_r − Σ Σ_{c after r}
  // V(c, r)ᵀ x_c). In the two-half order the halves' steps only meet at the separator (positions
  // N − 2, N − 1): forward, the halves are independent and the separator comes last; backward,
  // the separator comes first. Every step does the same arithmetic in either schedule.
  if (split_ >= N) {
    ForwardSweep<M>(0, N);
    BackwardSweep<M>(0, N, work_m_[0].data());
    return;
  }
  const int k = split_;
  ParallelFor(0, 2, std::min(num_threads_, 2),
              [this, k, N](int i, int) { ForwardSweep<M>(i == 0 ? 0 : k, i == 0 ? k : N - 2); });
  ForwardSweep<M>(N - 2, N);
  BackwardSweep<M>(N - 2, N, work_m_[0].data());
  ParallelFor(0, 2, std::min(num_threads_, 2), [this, k, N](int i, int) {
    BackwardSweep<M>(i == 0 ? 0 : k, i == 0 ? k : N - 2, work_m_[i].data());
  });
}

void BandedKktSolver::SolveOnce(const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                                Eigen::VectorXd* p, Eigen::VectorXd* lambda) {
  for (int r = 0; r < num_steps_; ++r) {
    z_.segment(r * m_, n_) = -g.segment(r * n_, n_);
    z_.segment(r * m_ + n_, nu_) = -h.segment(r * nu_, nu_);
  }
  WithKktBlockSize(dispatch_size_,
                   [this](auto size) { SolveInterleavedInPlace<decltype(size)::value>(); });
  for (int r = 0; r < num_steps_; ++r) {
    p->segment(r * n_, n_) = z_.segment(r * m_, n_);
    lambda->segment(r * nu_, nu_) = z_.segment(r * m_ + n_, nu_);
  }
}

void BandedKktSolver::Solve(const Eigen::VectorXd& g, const Eigen::VectorXd& h, Eigen::VectorXd* p,
                            Eigen::VectorXd* lambda) {
  CheckSize("BandedKktSolver::Solve", "g", g.size(), num_steps_ * n_, "N n");
  CheckSize("BandedKktSolver::Solve", "h", h.size(), num_steps_ * nu_, "N nu");
  if (p->size() != num_steps_ * n_) p->resize(num_steps_ * n_);
  if (lambda->size() != num_steps_ * nu_) lambda->resize(num_steps_ * nu_);
  last_solve_extended_ = false;
  last_solve_needed_extended_ = false;
  if (!status_.ok()) {
    p->setZero();
    lambda->setZero();
    return;
  }
  SolveOnce(g, h, p, lambda);
  if (extended_residual_) {
    // With the extended residual a second step pays: the first one's correction is only as
    // good as the factorization's contraction (κ ε growth), the residual no longer limits it.
    const double first = RefineOnce(g, h, true, p, lambda);
    for (int i = 1; i < std::max(refinement_steps_, 2); ++i) RefineOnce(g, h, true, p, lambda);
    last_solve_extended_ = true;
    last_solve_needed_extended_ = !(first <= extended_threshold_);
    return;
  }
  if (refinement_steps_ <= 0) return;
  double first = 0.0;
  if (extended_first_) {
    first = RefineOnce(g, h, true, p, lambda);
    last_solve_extended_ = true;
    last_solve_needed_extended_ = !(first <= extended_threshold_);
    FinishExtendedRefinement(g, h, first, 1, p, lambda);
    return;
  }
  for (int i = 0; i < refinement_steps_; ++i) {
    const double correction = RefineOnce(g, h, false, p, lambda);
    if (i == 0) first = correction;
  }
  // A large first correction is the signature of a conditioning κ that a residual in double
  // cannot resolve (the refined step then keeps an error of about that size, or more: the
  // residual's own rounding, amplified by κ): steps with the residual in double-double follow
  // (docs/solver.md, "Accuracy"). A NaN correction takes them too.
  if (!(first <= extended_threshold_)) {
    last_solve_extended_ = true;
    last_solve_needed_extended_ = true;
    FinishExtendedRefinement(g, h, RefineOnce(g, h, true, p, lambda), 1, p, lambda);
  }
}

void BandedKktSolver::SolveUnrefined(const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                                     Eigen::VectorXd* p, Eigen::VectorXd* lambda) {
  CheckSize("BandedKktSolver::SolveUnrefined", "g", g.size(), num_steps_ * n_, "N n");
  CheckSize("BandedKktSolver::SolveUnrefined", "h", h.size(), num_steps_ * nu_, "N nu");
  if (p->size() != num_steps_ * n_) p->resize(num_steps_ * n_);
  if (lambda->size() != num_steps_ * nu_) lambda->resize(num_steps_ * nu_);
  if (!status_.ok()) {
    p->setZero();
    lambda->setZero();
    return;
  }
  SolveOnce(g, h, p, lambda);
}

void BandedKktSolver::FinishExtendedRefinement(const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                                               double correction, int steps, Eigen::VectorXd* p,
                                               Eigen::VectorXd* lambda) {
  // A step with an exact residual multiplies the error by the refinement's contraction ρ: on the
  // examples ρ is about the error itself, so one step leaves about c² (c its correction); with
  // weak constraint blocks ρ reaches ~1e-3 whatever c. After one step: continue while c²
  // could exceed the threshold; after two or more, with ρ estimated from the last two
  // corrections, while ρ c could (docs/solver.md, "Accuracy").
  double previous = 0.0;
  while (steps < kMaxExtendedSteps) {
    const bool more = steps == 1 ? !(correction * correction <= extended_threshold_)
                                 : !(correction * (correction / previous) <= extended_threshold_);
    if (!more) break;
    previous = correction;
    correction = RefineOnce(g, h, true, p, lambda);
    ++steps;
  }
}

double BandedKktSolver::RefineOnce(const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                                   bool extended, Eigen::VectorXd* p, Eigen::VectorXd* lambda) {
  // K d = r with r = −[g; h] − K x: SolveOnce(−r) gives d.
  CalcResidual(g, h, *p, *lambda, extended, &rp_, &rl_);
  rp_ = -rp_;
  rl_ = -rl_;
  SolveOnce(rp_, rl_, &dp_, &dl_);
  *p += dp_;
  *lambda += dl_;
  // max(|dp|∞ / |p|∞, |dλ|∞ / |λ|∞): max-norms, which neither overflow nor underflow where
  // the entries do not; a part that is zero after the step counts only if it moved; NaN
  // propagates.
  auto relative = [](const Eigen::VectorXd& d, const Eigen::VectorXd& x) {
    if (d.size() == 0) return 0.0;
    const double dn = d.cwiseAbs().maxCoeff(), xn = x.cwiseAbs().maxCoeff();
    if (std::isnan(dn) || std::isnan(xn)) return std::numeric_limits<double>::quiet_NaN();
    if (xn > 0.0) return dn / xn;
    return dn > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
  };
  const double cp = relative(dp_, *p), cl = relative(dl_, *lambda);
  return std::isnan(cp) || std::isnan(cl) ? std::numeric_limits<double>::quiet_NaN()
                                          : std::max(cp, cl);
}

void BandedKktSolver::Residual(const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                               const Eigen::VectorXd& p, const Eigen::VectorXd& lambda,
                               Eigen::VectorXd* rp, Eigen::VectorXd* rl) {
  CalcResidual(g, h, p, lambda, extended_residual_, rp, rl);
}

void BandedKktSolver::CalcResidual(const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                                   const Eigen::VectorXd& p, const Eigen::VectorXd& lambda,
                                   bool extended, Eigen::VectorXd* rp, Eigen::VectorXd* rl) {
  if (H_ == nullptr || A_ == nullptr) {
    ThrowInvalidArgument("BandedKktSolver::Residual", "the solver", "not factored",
                         "a call to Factor first");
  }
  const int N = num_steps_, n = n_, nu = nu_;
  const PentaDiagonalMatrix& H = *H_;
  const BlockConstraintJacobian& A = *A_;
  if (!extended) {
    H.Multiply(p, rp);
    A.AddMultiplyTranspose(lambda, rp);
    *rp = -*rp - g;
    A.Multiply(p, rl);
    *rl = -*rl - h;
    return;
  }
  if (rp->size() != N * n) rp->resize(N * n);
  if (rl->size() != N * nu) rl->resize(N * nu);
  // Two halves of the steps on two threads when the factorization also runs in two halves.
  const int halves = split_ < N ? 2 : 1;
  ParallelFor(0, halves, std::min(num_threads_, 2), [&](int i, int) {
    internal::ExtendedKktResidual(H, A, g, h, p, lambda, i * N / halves, (i + 1) * N / halves, rp,
                                  rl);
  });
}

}  // namespace idto
