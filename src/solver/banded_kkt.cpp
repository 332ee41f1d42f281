#include "idto/solver/banded_kkt.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "idto/core/errors.hpp"
#include "math/cholesky_in_place.hpp"

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
  K2_ = mm;
  K1_ = mm;
  U1t_ = mm;
  SVt_ = mm;
  D_ = mm;
  z_ = Eigen::VectorXd::Zero(num_steps_ * m_);
  rp_ = Eigen::VectorXd::Zero(num_steps_ * n_);
  dp_ = rp_;
  rl_ = Eigen::VectorXd::Zero(num_steps_ * nu_);
  dl_ = rl_;
  work_m_ = Eigen::VectorXd::Zero(m_);
  extended_.assign(std::max(n_, nu_), 0.0L);
  status_ = KktStatus{};
  H_ = nullptr;
  A_ = nullptr;
}

bool BandedKktSolver::FactorPivot(int r, const Eigen::MatrixXd& D) {
  // D = [P Qᵀ; Q R] = F Σ Fᵀ, F = [Lp 0; Y Ls]: P = Lp Lpᵀ, Y = Q Lp⁻ᵀ, −S = Y Yᵀ − R = Ls Lsᵀ
  // (S the Schur complement of P in D).
  Eigen::MatrixXd& F = F_[r];
  auto Lp = F.topLeftCorner(n_, n_);
  Lp = D.topLeftCorner(n_, n_);
  double relative = 0.0;
  int row = internal::CholeskyLowerInPlace(0.0, Lp, &relative);
  if (row >= 0) {
    status_ = {KktStatus::Code::kHessianNotPositiveDefinite, r, row, relative};
    return false;
  }
  if (nu_ == 0) return true;
  F.topRightCorner(n_, nu_).setZero();
  auto Y = F.bottomLeftCorner(nu_, n_);
  Y = D.bottomLeftCorner(nu_, n_);
  Lp.triangularView<Eigen::Lower>().transpose().solveInPlace<Eigen::OnTheRight>(Y);
  auto Ls = F.bottomRightCorner(nu_, nu_);
  Ls = -D.bottomRightCorner(nu_, nu_);
  Ls.noalias() += Y * Y.transpose();
  row = internal::CholeskyLowerInPlace(rank_tolerance_, Ls, &relative);
  if (row >= 0) {
    status_ = {KktStatus::Code::kConstraintsRankDeficient, r, row, relative};
    return false;
  }
  return true;
}

void BandedKktSolver::AssembleOffDiagonal(int r, int c, Eigen::MatrixXd* K) const {
  // Rows (p_r, λ_r), columns (p_c, λ_c), c < r: H(r, c) and ∂h_r/∂q_{c+1}; the columns of λ_c
  // are zero because h_c does not involve q_{r+1} for r > c.
  K->topLeftCorner(n_, n_) = c == r - 1 ? H_->B(r) : H_->A(r);
  K->topRightCorner(n_, nu_).setZero();
  K->bottomLeftCorner(nu_, n_) = A_->Block(r, c + 1);
  K->bottomRightCorner(nu_, nu_).setZero();
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
  // D_r is symmetric: only its lower triangle is formed and read.
  for (int r = 0; r < num_steps_; ++r) {
    D_.topLeftCorner(n_, n_) = H.C(r);
    D_.bottomLeftCorner(nu_, n_) = A.Block(r, r + 1);
    D_.bottomRightCorner(nu_, nu_).setZero();
    auto D_lower = D_.triangularView<Eigen::Lower>();
    if (r >= 2) {
      AssembleOffDiagonal(r, r - 2, &K2_);
      Eigen::MatrixXd& Vt2 = Vt2_[r];
      Vt2 = K2_.transpose();
      F_[r - 2].triangularView<Eigen::Lower>().solveInPlace(Vt2);
      SVt_ = Vt2;
      SVt_.bottomRows(nu_) *= -1.0;
      D_lower -= Vt2.transpose() * SVt_;
    }
    if (r >= 1) {
      AssembleOffDiagonal(r, r - 1, &K1_);
      U1t_ = K1_.transpose();
      // U(r, r−1)ᵀ = K(r, r−1)ᵀ − V(r−1, r−2) Σ V(r, r−2)ᵀ (SVt_ holds Σ V(r, r−2)ᵀ).
      if (r >= 2) U1t_.noalias() -= Vt1_[r - 1].transpose() * SVt_;
      Eigen::MatrixXd& Vt1 = Vt1_[r];
      Vt1 = U1t_;
      F_[r - 1].triangularView<Eigen::Lower>().solveInPlace(Vt1);
      SVt_ = Vt1;
      SVt_.bottomRows(nu_) *= -1.0;
      D_lower -= Vt1.transpose() * SVt_;
    }
    if (!FactorPivot(r, D_)) return status_;
  }
  status_ = {KktStatus::Code::kSuccess, -1, -1, 0.0};
  return status_;
}

void BandedKktSolver::SolveInterleavedInPlace() {
  const int m = m_;
  // Forward: G y = b, stored as z_r = Σ y_r with y_r = F_r⁻¹ (b_r − Σ_{c<r} V(r, c) z_c).
  for (int r = 0; r < num_steps_; ++r) {
    auto zr = z_.segment(r * m, m);
    if (r >= 1) zr.noalias() -= Vt1_[r].transpose() * z_.segment((r - 1) * m, m);
    if (r >= 2) zr.noalias() -= Vt2_[r].transpose() * z_.segment((r - 2) * m, m);
    F_[r].triangularView<Eigen::Lower>().solveInPlace(zr);
    zr.tail(nu_) *= -1.0;
  }
  // Backward: Gᵀ x = z, x_r = F_r⁻ᵀ (z_r − Σ Σ_{c>r} V(c, r)ᵀ x_c).
  for (int r = num_steps_ - 1; r >= 0; --r) {
    auto zr = z_.segment(r * m, m);
    if (r + 1 < num_steps_) {
      work_m_.noalias() = Vt1_[r + 1] * z_.segment((r + 1) * m, m);
      if (r + 2 < num_steps_) work_m_.noalias() += Vt2_[r + 2] * z_.segment((r + 2) * m, m);
      work_m_.tail(nu_) *= -1.0;
      zr -= work_m_;
    }
    F_[r].triangularView<Eigen::Lower>().transpose().solveInPlace(zr);
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
  for (int i = 0; i < refinement_steps_; ++i) {
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
  // Accumulated in long double (a 64-bit significand on x86-64) and rounded once: the
  // refinement then corrects the error that the conditioning of K puts into the double solve,
  // not only the round-off of the factorization (docs/solver.md, "Accuracy"). Every loop runs
  // along a stored column.
  if (rp->size() != N * n) rp->resize(N * n);
  if (rl->size() != N * nu) rl->resize(N * nu);
  long double* acc = extended_.data();
  for (int r = 0; r < N; ++r) {
    for (int i = 0; i < n; ++i) acc[i] = -static_cast<long double>(g(r * n + i));
    // Blocks left of the diagonal and the diagonal one, H(r, c) = A(r), B(r), C(r): by columns.
    for (int c = std::max(0, r - 2); c <= r; ++c) {
      const Eigen::MatrixXd& M = c == r ? H.C(r) : (c == r - 1 ? H.B(r) : H.A(r));
      for (int j = 0; j < n; ++j) {
        const long double pj = p(c * n + j);
        const double* column = M.col(j).data();
        for (int i = 0; i < n; ++i) acc[i] -= column[i] * pj;
      }
    }
    // Right of the diagonal, H(r, c) = M(c)ᵀ: row i of it is column i of M(c).
    for (int c = r + 1; c <= std::min(N - 1, r + 2); ++c) {
      const Eigen::MatrixXd& M = c == r + 1 ? H.B(c) : H.A(c);
      const double* pc = p.data() + c * n;
      for (int i = 0; i < n; ++i) {
        const double* column = M.col(i).data();
        long double sum = 0.0L;
        for (int j = 0; j < n; ++j) sum += static_cast<long double>(column[j]) * pc[j];
        acc[i] -= sum;
      }
    }
    // Aᵀλ: the constraints h_j that involve q_{r+1}; row i of J(j, r+1)ᵀ is its column i.
    for (int j = r; j <= std::min(N - 1, r + 2); ++j) {
      const Eigen::MatrixXd& J = A.Block(j, r + 1);
      const double* l = lambda.data() + j * nu;
      for (int i = 0; i < n; ++i) {
        const double* column = J.col(i).data();
        for (int u = 0; u < nu; ++u) acc[i] -= static_cast<long double>(column[u]) * l[u];
      }
    }
    for (int i = 0; i < n; ++i) (*rp)(r * n + i) = static_cast<double>(acc[i]);
  }
  for (int j = 0; j < N; ++j) {
    for (int u = 0; u < nu; ++u) acc[u] = -static_cast<long double>(h(j * nu + u));
    for (int s = std::max(1, j - 1); s <= std::min(N, j + 1); ++s) {
      const Eigen::MatrixXd& J = A.Block(j, s);
      for (int i = 0; i < n; ++i) {
        const long double pi = p((s - 1) * n + i);
        const double* column = J.col(i).data();
        for (int u = 0; u < nu; ++u) acc[u] -= column[u] * pi;
      }
    }
    for (int u = 0; u < nu; ++u) (*rl)(j * nu + u) = static_cast<double>(acc[u]);
  }
}

}  // namespace idto
