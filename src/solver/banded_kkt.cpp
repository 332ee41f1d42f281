#include "idto/solver/banded_kkt.hpp"

#include <cmath>
#include <sstream>

#include "idto/core/errors.hpp"

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
  Lt1_.assign(num_steps_, mm);
  Lt2_.assign(num_steps_, mm);
  Lp_.assign(num_steps_, Eigen::MatrixXd::Zero(n_, n_));
  Y_.assign(num_steps_, Eigen::MatrixXd::Zero(nu_, n_));
  Ls_.assign(num_steps_, Eigen::MatrixXd::Zero(nu_, nu_));
  K2_ = mm;
  K1_ = mm;
  K1_prev_ = mm;
  D_ = mm;
  z_ = Eigen::VectorXd::Zero(num_steps_ * m_);
  rp_ = Eigen::VectorXd::Zero(num_steps_ * n_);
  dp_ = rp_;
  rl_ = Eigen::VectorXd::Zero(num_steps_ * nu_);
  dl_ = rl_;
  status_ = KktStatus{};
  H_ = nullptr;
  A_ = nullptr;
}

namespace {

// In-place lower Cholesky of the square matrix M (no allocation), the upper triangle zeroed.
// A pivot d (before the square root) fails when !(d > tolerance * diagonal entry before
// elimination) (tolerance 0: d must be positive; NaN always fails). Returns the failing row or
// −1, and the relative pivot d / M_ii of that row.
int CholeskyInPlace(double tolerance, Eigen::MatrixXd* M_in, double* relative_pivot) {
  Eigen::MatrixXd& M = *M_in;
  const int n = static_cast<int>(M.rows());
  for (int j = 0; j < n; ++j) {
    const double diagonal = M(j, j);
    double d = diagonal;
    for (int p = 0; p < j; ++p) d -= M(j, p) * M(j, p);
    if (!(d > tolerance * std::abs(diagonal)) || !std::isfinite(d)) {
      *relative_pivot = diagonal != 0.0 ? d / std::abs(diagonal) : d;
      return j;
    }
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
  return -1;
}

}  // namespace

bool BandedKktSolver::FactorPivot(int r, Eigen::MatrixXd* D) {
  // D = [P Qᵀ; Q R] = [Lp 0; Y I] [I 0; 0 −Ls Lsᵀ] [Lpᵀ Yᵀ; 0 I]: P = Lp Lpᵀ, Y = Q Lp⁻ᵀ,
  // −S = Y Yᵀ − R = Ls Lsᵀ (S the Schur complement of P in D).
  Eigen::MatrixXd& Lp = Lp_[r];
  Lp = D->topLeftCorner(n_, n_);
  double relative = 0.0;
  int row = CholeskyInPlace(0.0, &Lp, &relative);
  if (row >= 0) {
    status_ = {KktStatus::Code::kHessianNotPositiveDefinite, r, row, relative};
    return false;
  }
  if (nu_ == 0) return true;
  Eigen::MatrixXd& Y = Y_[r];
  Y = D->bottomLeftCorner(nu_, n_);
  Lp.triangularView<Eigen::Lower>().transpose().solveInPlace<Eigen::OnTheRight>(Y);
  Eigen::MatrixXd& Ls = Ls_[r];
  Ls = -D->bottomRightCorner(nu_, nu_);
  Ls.noalias() += Y * Y.transpose();
  row = CholeskyInPlace(rank_tolerance_, &Ls, &relative);
  if (row >= 0) {
    status_ = {KktStatus::Code::kConstraintsRankDeficient, r, row, relative};
    return false;
  }
  return true;
}

template <typename Derived>
void BandedKktSolver::PivotSolveInPlace(int r, Eigen::MatrixBase<Derived>& X) const {
  auto Xa = X.topRows(n_);
  const auto Lp = Lp_[r].triangularView<Eigen::Lower>();
  Lp.solveInPlace(Xa);  // w = Lp⁻¹ a
  if (nu_ > 0) {
    auto Xb = X.bottomRows(nu_);
    Xb = -Xb;
    Xb.noalias() += Y_[r] * Xa;  // Y w − b
    const auto Ls = Ls_[r].triangularView<Eigen::Lower>();
    Ls.solveInPlace(Xb);
    Ls.transpose().solveInPlace(Xb);  // y = (Ls Lsᵀ)⁻¹ (Y w − b)
    Xa.noalias() -= Y_[r].transpose() * Xb;
  }
  Lp.transpose().solveInPlace(Xa);  // x = Lp⁻ᵀ (w − Yᵀ y)
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
  // Block LDLᵀ of the interleaved matrix K (unknowns x_r = (p_r, λ_r)); K(r, r−2) and
  // K(r, r−1) are the only blocks left of the diagonal. With U(r, c) = K(r, c) − Σ L(r, i) D_i
  // L(c, i)ᵀ: L(r, c) = U(r, c) D_c⁻¹, D_r = K(r, r) − Σ_c L(r, c) U(r, c)ᵀ. No fill-in below
  // r − 2, so U(r, r−2) = K(r, r−2).
  // D_r is symmetric: only its lower triangle is formed and read. The λ columns of
  // U(r, r−2) = K(r, r−2) are zero, so its products run over the first n columns only.
  for (int r = 0; r < num_steps_; ++r) {
    D_.topLeftCorner(n_, n_) = H.C(r);
    D_.bottomLeftCorner(nu_, n_) = A.Block(r, r + 1);
    D_.bottomRightCorner(nu_, nu_).setZero();
    auto D_lower = D_.triangularView<Eigen::Lower>();
    if (r >= 2) {
      AssembleOffDiagonal(r, r - 2, &K2_);
      Lt2_[r] = K2_.transpose();
      PivotSolveInPlace(r - 2, Lt2_[r]);
      D_lower -= Lt2_[r].topRows(n_).transpose() * K2_.leftCols(n_).transpose();
    }
    if (r >= 1) {
      AssembleOffDiagonal(r, r - 1, &K1_);
      if (r >= 2) K1_.noalias() -= Lt2_[r].transpose() * K1_prev_.transpose();
      Lt1_[r] = K1_.transpose();
      PivotSolveInPlace(r - 1, Lt1_[r]);
      D_lower -= Lt1_[r].transpose() * K1_.transpose();
      K1_prev_.swap(K1_);  // U(r, r−1), needed by row r + 1
    }
    if (!FactorPivot(r, &D_)) return status_;
  }
  status_ = {KktStatus::Code::kSuccess, -1, -1, 0.0};
  return status_;
}

void BandedKktSolver::SolveInterleavedInPlace() {
  const int m = m_;
  for (int r = 1; r < num_steps_; ++r) {
    auto zr = z_.segment(r * m, m);
    zr.noalias() -= Lt1_[r].transpose() * z_.segment((r - 1) * m, m);
    if (r >= 2) zr.noalias() -= Lt2_[r].transpose() * z_.segment((r - 2) * m, m);
  }
  for (int r = 0; r < num_steps_; ++r) {
    auto zr = z_.segment(r * m, m);
    PivotSolveInPlace(r, zr);
  }
  for (int r = num_steps_ - 2; r >= 0; --r) {
    auto zr = z_.segment(r * m, m);
    zr.noalias() -= Lt1_[r + 1] * z_.segment((r + 1) * m, m);
    if (r + 2 < num_steps_) zr.noalias() -= Lt2_[r + 2] * z_.segment((r + 2) * m, m);
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
  H_->Multiply(p, rp);
  A_->AddMultiplyTranspose(lambda, rp);
  *rp = -*rp - g;
  A_->Multiply(p, rl);
  *rl = -*rl - h;
}

}  // namespace idto
