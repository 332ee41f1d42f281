#include "idto/solver/banded_kkt.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "idto/core/errors.hpp"
#include "math/small_dense.hpp"

namespace idto {

// ------------------------------------------------------------------------------------------
// BlockConstraintJacobian

BlockConstraintJacobian::BlockConstraintJacobian(int num_steps, int num_positions,
                                                 int num_constraints) {
  Resize(num_steps, num_positions, num_constraints);
}

void BlockConstraintJacobian::Resize(int num_steps, int num_positions, int num_constraints) {
  if (num_steps < 0 || num_positions < 0 || num_constraints < 0) {
    ThrowInvalidArgument("BlockConstraintJacobian::Resize", "sizes (N, n, nu)",
                         std::to_string(num_steps) + ", " + std::to_string(num_positions) + ", " +
                             std::to_string(num_constraints),
                         "non-negative numbers");
  }
  num_steps_ = num_steps;
  num_positions_ = num_positions;
  num_constraints_ = num_constraints;
  blocks_.assign(3 * static_cast<size_t>(num_steps),
                 Eigen::MatrixXd::Zero(num_constraints, num_positions));
}

namespace {

[[noreturn]] void ThrowNoBlock(int j, int s, int N) {
  ThrowInvalidArgument(
      "BlockConstraintJacobian::Block", "(j, s)",
      "(" + std::to_string(j) + ", " + std::to_string(s) + ")",
      "0 <= j < N = " + std::to_string(N) + " and s in {j-1, j, j+1} within [1, N]");
}

}  // namespace

Eigen::MatrixXd& BlockConstraintJacobian::Block(int j, int s) {
  if (!HasBlock(j, s)) ThrowNoBlock(j, s, num_steps_);
  return blocks_[Index(j, s)];
}

const Eigen::MatrixXd& BlockConstraintJacobian::Block(int j, int s) const {
  if (!HasBlock(j, s)) ThrowNoBlock(j, s, num_steps_);
  return blocks_[Index(j, s)];
}

void BlockConstraintJacobian::SetZero() {
  for (Eigen::MatrixXd& b : blocks_) b.setZero();
}

void BlockConstraintJacobian::Multiply(const Eigen::VectorXd& p, Eigen::VectorXd* Ap) const {
  CheckSize("BlockConstraintJacobian::Multiply", "p", p.size(), cols(), "N n");
  const int n = num_positions_;
  const int nu = num_constraints_;
  if (Ap->size() != rows()) Ap->resize(rows());
  for (int j = 0; j < num_steps_; ++j) {
    auto y = Ap->segment(j * nu, nu);
    y.setZero();
    for (int s = j - 1; s <= j + 1; ++s) {
      if (!HasBlock(j, s)) continue;
      y.noalias() += blocks_[Index(j, s)] * p.segment((s - 1) * n, n);
    }
  }
}

void BlockConstraintJacobian::MultiplyTranspose(const Eigen::VectorXd& lambda,
                                                Eigen::VectorXd* Atl) const {
  if (Atl->size() != cols()) Atl->resize(cols());
  Atl->setZero();
  AddMultiplyTranspose(lambda, Atl);
}

void BlockConstraintJacobian::AddMultiplyTranspose(const Eigen::VectorXd& lambda,
                                                   Eigen::VectorXd* y) const {
  CheckSize("BlockConstraintJacobian::AddMultiplyTranspose", "lambda", lambda.size(), rows(),
            "N nu");
  CheckSize("BlockConstraintJacobian::AddMultiplyTranspose", "y", y->size(), cols(), "N n");
  const int n = num_positions_;
  const int nu = num_constraints_;
  for (int j = 0; j < num_steps_; ++j) {
    const auto l = lambda.segment(j * nu, nu);
    for (int s = j - 1; s <= j + 1; ++s) {
      if (!HasBlock(j, s)) continue;
      y->segment((s - 1) * n, n).noalias() += blocks_[Index(j, s)].transpose() * l;
    }
  }
}

Eigen::MatrixXd BlockConstraintJacobian::MakeDense() const {
  const int n = num_positions_;
  const int nu = num_constraints_;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows(), cols());
  for (int j = 0; j < num_steps_; ++j) {
    for (int s = j - 1; s <= j + 1; ++s) {
      if (HasBlock(j, s)) A.block(j * nu, (s - 1) * n, nu, n) = blocks_[Index(j, s)];
    }
  }
  return A;
}

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
  T1_ = mm;
  T2_ = mm;
  diagonal_ = Eigen::VectorXd::Zero(m_);
  inverse_diagonal_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(num_steps_) * m_);
  z_ = Eigen::VectorXd::Zero(num_steps_ * m_);
  rp_ = Eigen::VectorXd::Zero(num_steps_ * n_);
  dp_ = rp_;
  rl_ = Eigen::VectorXd::Zero(num_steps_ * nu_);
  dl_ = rl_;
  work_m_ = Eigen::VectorXd::Zero(m_);
  extended_hi_ = Eigen::VectorXd::Zero(std::max(n_, nu_));
  extended_lo_ = extended_hi_;
  status_ = KktStatus{};
  H_ = nullptr;
  A_ = nullptr;
}

bool BandedKktSolver::FactorPivot(int r) {
  // F holds D_r's lower triangle, D = [P Qᵀ; Q R] = F Σ Fᵀ with F = [Lp 0; Y Ls]: the first n
  // columns of a right-looking Cholesky give P = Lp Lpᵀ, Y = Q Lp⁻ᵀ and leave the Schur
  // complement S = R − Y Yᵀ in the trailing block; its negation −S = Ls Lsᵀ.
  Eigen::MatrixXd& F = F_[r];
  const int m = m_;
  double* f = F.data();
  for (int i = 0; i < n_; ++i) diagonal_[i] = F(i, i);
  double relative = 0.0;
  double* inverse = inverse_diagonal_.data() + static_cast<long>(r) * m;
  int row =
      internal::CholeskyColumnsInPlace(0.0, diagonal_.data(), m, 0, n_, f, m, inverse, &relative);
  if (row >= 0) {
    status_ = {KktStatus::Code::kHessianNotPositiveDefinite, r, row, relative};
    return false;
  }
  // The rank test's scale for constraint row u: the sum of the positive contributions to −S's
  // diagonal (|Y_u|² here, the p-parts of the earlier blocks in Factor), about the row's squared
  // norm in the metric of H⁻¹, so d / scale is about the squared sine of the row's angle with the
  // span of the rows before it. (−S's own diagonal is no scale: for a dependent row it is
  // round-off itself.)
  for (int j = n_; j < m; ++j) {
    for (int i = j; i < m; ++i) F(i, j) = -F(i, j);
    diagonal_[j] += F.row(j).head(n_).squaredNorm();
  }
  row = internal::CholeskyColumnsInPlace(rank_tolerance_, diagonal_.data(), m, n_, m, f, m, inverse,
                                         &relative);
  if (row >= 0) {
    status_ = {KktStatus::Code::kConstraintsRankDeficient, r, row - n_, relative};
    return false;
  }
  F.triangularView<Eigen::StrictlyUpper>().setZero();
  return true;
}

void BandedKktSolver::AddConstraintScale(const Eigen::MatrixXd& Vt) {
  for (int u = 0; u < nu_; ++u) diagonal_[n_ + u] += Vt.col(n_ + u).head(n_).squaredNorm();
}

void BandedKktSolver::AssembleOffDiagonalTransposed(int r, int c, Eigen::MatrixXd* Kt) const {
  // K(r, c)ᵀ: rows (p_c, λ_c), columns (p_r, λ_r), c < r: H(r, c)ᵀ and ∂h_r/∂q_{c+1}ᵀ; the rows
  // of λ_c are zero because h_c does not involve q_{r+1} for r > c.
  Kt->topLeftCorner(n_, n_) = (c == r - 1 ? H_->B(r) : H_->A(r)).transpose();
  Kt->topRightCorner(n_, nu_) = A_->Block(r, c + 1).transpose();
  Kt->bottomRows(nu_).setZero();
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
  H_ = &H;
  A_ = &A;
  // Signed block Cholesky of the interleaved matrix K (unknowns x_r = (p_r, λ_r)):
  // K = G Σ̂ Gᵀ, G(r, r) = F_r, G(r, c) = V(r, c) Σ for c < r, with
  //   U(r, c) = K(r, c) − Σ_{i<c} V(r, i) Σ V(c, i)ᵀ,   V(r, c) = U(r, c) F_c⁻ᵀ,
  //   D_r = F_r Σ F_rᵀ = K(r, r) − Σ_{c<r} V(r, c) Σ V(r, c)ᵀ.
  // K(r, r−2) and K(r, r−1) are the only blocks left of the diagonal and there is no fill-in
  // below r − 2, so U(r, r−2) = K(r, r−2). The same pivots as a block LDLᵀ (D_r = F_r Σ F_rᵀ),
  // but each off-diagonal block costs one triangular solve with F_c instead of a solve with D_c.
  // D_r is symmetric: only its lower triangle is formed (in F_[r]) and read. The products go
  // through internal:: kernels (src/math/small_dense.hpp); the transposes T1_, T2_ of Vt turn the
  // Σ-weighted products into column updates.
  const int m = m_;
  for (int r = 0; r < num_steps_; ++r) {
    Eigen::MatrixXd& D = F_[r];
    D.topLeftCorner(n_, n_) = H.C(r);
    D.bottomLeftCorner(nu_, n_) = A.Block(r, r + 1);
    D.bottomRightCorner(nu_, nu_).setZero();
    diagonal_.tail(nu_).setZero();
    if (r >= 2) {
      // Vt2 = F_{r−2}⁻¹ K(r, r−2)ᵀ; D −= Vt2ᵀ Σ Vt2.
      Eigen::MatrixXd& Vt2 = Vt2_[r];
      AssembleOffDiagonalTransposed(r, r - 2, &Vt2);
      internal::LowerSolveInPlace(F_[r - 2].data(), m, InverseDiagonal(r - 2), m, Vt2.data(), m, m);
      AddConstraintScale(Vt2);
      internal::Transpose(Vt2.data(), m, m, m, T2_.data(), m);
      internal::SubtractSignedProduct(T2_.data(), m, Vt2.data(), m, m, m, m, n_, true, D.data(), m);
    }
    if (r >= 1) {
      // U(r, r−1)ᵀ = K(r, r−1)ᵀ − V(r−1, r−2) Σ V(r, r−2)ᵀ, with T1_ = Vt1_[r−1]ᵀ;
      // Vt1 = F_{r−1}⁻¹ U(r, r−1)ᵀ; D −= Vt1ᵀ Σ Vt1.
      Eigen::MatrixXd& Vt1 = Vt1_[r];
      AssembleOffDiagonalTransposed(r, r - 1, &Vt1);
      if (r >= 2) {
        internal::SubtractSignedProduct(T1_.data(), m, Vt2_[r].data(), m, m, m, m, n_, false,
                                        Vt1.data(), m);
      }
      internal::LowerSolveInPlace(F_[r - 1].data(), m, InverseDiagonal(r - 1), m, Vt1.data(), m, m);
      AddConstraintScale(Vt1);
      internal::Transpose(Vt1.data(), m, m, m, T1_.data(), m);
      internal::SubtractSignedProduct(T1_.data(), m, Vt1.data(), m, m, m, m, n_, true, D.data(), m);
    }
    if (!FactorPivot(r)) return status_;
  }
  status_ = {KktStatus::Code::kSuccess, -1, -1, 0.0};
  return status_;
}

void BandedKktSolver::SolveInterleavedInPlace() {
  const int m = m_;
  double* z = z_.data();
  // Forward: G y = b, stored as z_r = Σ y_r with y_r = F_r⁻¹ (b_r − Σ_{c<r} V(r, c) z_c).
  for (int r = 0; r < num_steps_; ++r) {
    double* zr = z + static_cast<long>(r) * m;
    if (r >= 1) internal::SubtractTransposeTimes(Vt1_[r].data(), m, m, m, zr - m, zr);
    if (r >= 2) internal::SubtractTransposeTimes(Vt2_[r].data(), m, m, m, zr - 2 * m, zr);
    internal::LowerSolveInPlace(F_[r].data(), m, InverseDiagonal(r), m, zr, m, 1);
    for (int i = n_; i < m; ++i) zr[i] = -zr[i];
  }
  // Backward: Gᵀ x = z, x_r = F_r⁻ᵀ (z_r − Σ Σ_{c>r} V(c, r)ᵀ x_c).
  double* w = work_m_.data();
  for (int r = num_steps_ - 1; r >= 0; --r) {
    double* zr = z + static_cast<long>(r) * m;
    if (r + 1 < num_steps_) {
      std::fill(w, w + m, 0.0);
      internal::AddTimes(Vt1_[r + 1].data(), m, m, m, zr + m, w);
      if (r + 2 < num_steps_) internal::AddTimes(Vt2_[r + 2].data(), m, m, m, zr + 2 * m, w);
      for (int i = 0; i < n_; ++i) zr[i] -= w[i];
      for (int i = n_; i < m; ++i) zr[i] += w[i];
    }
    internal::LowerTransposeSolveInPlace(F_[r].data(), m, InverseDiagonal(r), m, zr);
  }
}

void BandedKktSolver::SolveOnce(const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                                Eigen::VectorXd* p, Eigen::VectorXd* lambda) {
  for (int r = 0; r < num_steps_; ++r) {
    z_.segment(r * m_, n_) = -g.segment(r * n_, n_);
    z_.segment(r * m_ + n_, nu_) = -h.segment(r * nu_, nu_);
  }
  SolveInterleavedInPlace();
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
  if (!status_.ok()) {
    p->setZero();
    lambda->setZero();
    return;
  }
  SolveOnce(g, h, p, lambda);
  // With the extended residual a second step pays: the first one's correction is only as good
  // as the factorization's contraction (κ ε growth), the residual no longer limits it.
  const int steps = extended_residual_ ? std::max(refinement_steps_, 2) : refinement_steps_;
  for (int i = 0; i < steps; ++i) {
    // K d = r with r = −[g; h] − K x: SolveOnce(−r) gives d.
    Residual(g, h, *p, *lambda, &rp_, &rl_);
    rp_ = -rp_;
    rl_ = -rl_;
    SolveOnce(rp_, rl_, &dp_, &dl_);
    *p += dp_;
    *lambda += dl_;
  }
}

void BandedKktSolver::Residual(const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                               const Eigen::VectorXd& p, const Eigen::VectorXd& lambda,
                               Eigen::VectorXd* rp, Eigen::VectorXd* rl) {
  if (H_ == nullptr || A_ == nullptr) {
    ThrowInvalidArgument("BandedKktSolver::Residual", "the solver", "not factored",
                         "a call to Factor first");
  }
  const int N = num_steps_, n = n_, nu = nu_;
  const PentaDiagonalMatrix& H = *H_;
  const BlockConstraintJacobian& A = *A_;
  if (!extended_residual_) {
    H.Multiply(p, rp);
    A.AddMultiplyTranspose(lambda, rp);
    *rp = -*rp - g;
    A.Multiply(p, rl);
    *rl = -*rl - h;
    return;
  }
  // Accumulated exactly enough in double-double arithmetic (each product split exactly by an
  // fma, each sum by TwoSum) and rounded once: the refinement then corrects the error that the
  // conditioning of K (up to ~1e10 on the examples) puts into the double solve, not only the
  // factorization's round-off (docs/solver.md, "Accuracy"). Every loop runs along a stored column.
  if (rp->size() != N * n) rp->resize(N * n);
  if (rl->size() != N * nu) rl->resize(N * nu);
  double* hi = extended_hi_.data();
  double* lo = extended_lo_.data();
  for (int r = 0; r < N; ++r) {
    for (int i = 0; i < n; ++i) {
      hi[i] = -g(r * n + i);
      lo[i] = 0.0;
    }
    // Blocks left of the diagonal and the diagonal one, H(r, c) = A(r), B(r), C(r): by columns.
    for (int c = std::max(0, r - 2); c <= r; ++c) {
      const Eigen::MatrixXd& M = c == r ? H.C(r) : (c == r - 1 ? H.B(r) : H.A(r));
      for (int j = 0; j < n; ++j) {
        const double pj = p(c * n + j);
        const double* column = M.col(j).data();
        for (int i = 0; i < n; ++i) internal::SubtractProductExactly(column[i], pj, &hi[i], &lo[i]);
      }
    }
    // Right of the diagonal, H(r, c) = M(c)ᵀ: row i of it is column i of M(c).
    for (int c = r + 1; c <= std::min(N - 1, r + 2); ++c) {
      const Eigen::MatrixXd& M = c == r + 1 ? H.B(c) : H.A(c);
      const double* pc = p.data() + c * n;
      for (int i = 0; i < n; ++i) {
        const double* column = M.col(i).data();
        for (int j = 0; j < n; ++j)
          internal::SubtractProductExactly(column[j], pc[j], &hi[i], &lo[i]);
      }
    }
    // Aᵀλ: the constraints h_j that involve q_{r+1}; row i of J(j, r+1)ᵀ is its column i.
    for (int j = r; j <= std::min(N - 1, r + 2); ++j) {
      const Eigen::MatrixXd& J = A.Block(j, r + 1);
      const double* l = lambda.data() + j * nu;
      for (int i = 0; i < n; ++i) {
        const double* column = J.col(i).data();
        for (int u = 0; u < nu; ++u)
          internal::SubtractProductExactly(column[u], l[u], &hi[i], &lo[i]);
      }
    }
    for (int i = 0; i < n; ++i) (*rp)(r * n + i) = hi[i] + lo[i];
  }
  for (int j = 0; j < N; ++j) {
    for (int u = 0; u < nu; ++u) {
      hi[u] = -h(j * nu + u);
      lo[u] = 0.0;
    }
    for (int s = std::max(1, j - 1); s <= std::min(N, j + 1); ++s) {
      const Eigen::MatrixXd& J = A.Block(j, s);
      for (int i = 0; i < n; ++i) {
        const double pi = p((s - 1) * n + i);
        const double* column = J.col(i).data();
        for (int u = 0; u < nu; ++u)
          internal::SubtractProductExactly(column[u], pi, &hi[u], &lo[u]);
      }
    }
    for (int u = 0; u < nu; ++u) (*rl)(j * nu + u) = hi[u] + lo[u];
  }
}

}  // namespace idto
