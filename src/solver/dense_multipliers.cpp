#include "solver/dense_multipliers.hpp"

#include <algorithm>

namespace idto::internal {

void DenseMultipliers::Resize(int num_steps, int nq, int num_unactuated) {
  if (N_ == num_steps && nq_ == nq && nu_ == num_unactuated && At_.size() > 0) return;
  N_ = num_steps;
  nq_ = nq;
  nu_ = num_unactuated;
  const int m = N_ * nu_;
  At_ = Eigen::MatrixXd::Zero(N_ * nq_, m);
  Y_ = At_;
  S_ = Eigen::MatrixXd::Zero(m, m);
  // compute() sizes the factor and defines its status (LLT(size) leaves it undefined).
  S_llt_.compute(Eigen::MatrixXd::Identity(m, m));
  Linv_g_ = Eigen::VectorXd::Zero(N_ * nq_);
}

bool DenseMultipliers::Compute(const Transcription& transcription,
                               const TrajectoryDerivatives& derivatives,
                               const PentaDiagonalCholesky& chol, const Eigen::VectorXd& g,
                               const Eigen::VectorXd& h, Eigen::VectorXd* lambda,
                               Eigen::VectorXd* g_merit, std::string* why) {
  transcription.CalcDenseConstraintJacobianTranspose(derivatives, &At_);
  Y_ = At_;
  // Forward substitutions skip each constraint column's leading zero blocks (the rows of tau_j
  // only involve q_{j-1}, q_j, q_{j+1}).
  for (int j = 0; j < N_; ++j) {
    chol.SolveLowerInPlace(Y_.middleCols(j * nu_, nu_), std::max(j - 2, 0));
  }
  S_.setZero();
  S_.selfadjointView<Eigen::Lower>().rankUpdate(Y_.transpose());
  S_llt_.compute(S_);  // reads the lower triangle only
  if (S_llt_.info() != Eigen::Success) {
    *why = "A H^-1 A^T is not positive definite (constraints not independent)";
    return false;
  }
  Linv_g_ = g;
  chol.SolveLowerInPlace(&Linv_g_);
  *lambda = h;
  lambda->noalias() -= Y_.transpose() * Linv_g_;
  S_llt_.solveInPlace(*lambda);
  *g_merit = g;
  g_merit->noalias() += At_ * (*lambda);
  return true;
}

}  // namespace idto::internal
