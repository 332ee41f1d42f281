#include "idto/solver/banded_kkt.hpp"

#include <string>

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

void BlockConstraintJacobian::ThrowNoBlock(int j, int s) const {
  ThrowInvalidArgument(
      "BlockConstraintJacobian::Block", "(j, s)",
      "(" + std::to_string(j) + ", " + std::to_string(s) + ")",
      "0 <= j < N = " + std::to_string(num_steps_) + " and s in {j-1, j, j+1} within [1, N]");
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

}  // namespace idto
