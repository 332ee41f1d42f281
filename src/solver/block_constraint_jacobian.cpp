#include "idto/solver/banded_kkt.hpp"

#include <algorithm>
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
  CheckBlockShapes("BlockConstraintJacobian::Multiply");
  const int n = num_positions_;
  const int nu = num_constraints_;
  if (Ap->size() != rows()) Ap->resize(rows());
  if (nu != 1) {
    for (int j = 0; j < num_steps_; ++j) {
      auto y = Ap->segment(j * nu, nu);
      y.setZero();
      for (int s = std::max(j - 1, 1); s <= std::min(j + 1, num_steps_); ++s) {
        y.noalias() += blocks_[Index(j, s)] * p.segment((s - 1) * n, n);
      }
    }
    return;
  }
  // One constraint per step (the spinner, acrobot, hopper): each block is a row of n entries,
  // and Eigen's dynamic-size products spend most of their time dispatching (2.2 µs for one
  // product of the spinner's 40 x 3 blocks, docs/benchmarks.md, session 42). One dot product
  // per block, added in the order above (the solver baselines are unchanged bit for bit).
  for (int j = 0; j < num_steps_; ++j) {
    double y = 0.0;
    for (int s = std::max(j - 1, 1); s <= std::min(j + 1, num_steps_); ++s) {
      const double* B = blocks_[Index(j, s)].data();
      const double* x = p.data() + static_cast<Eigen::Index>(s - 1) * n;
      double dot = 0.0;
      for (int c = 0; c < n; ++c) dot += B[c] * x[c];
      y += dot;
    }
    (*Ap)(j) = y;
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
  CheckBlockShapes("BlockConstraintJacobian::AddMultiplyTranspose");
  const int n = num_positions_;
  const int nu = num_constraints_;
  if (nu != 1) {
    for (int j = 0; j < num_steps_; ++j) {
      const auto l = lambda.segment(j * nu, nu);
      for (int s = std::max(j - 1, 1); s <= std::min(j + 1, num_steps_); ++s) {
        y->segment((s - 1) * n, n).noalias() += blocks_[Index(j, s)].transpose() * l;
      }
    }
    return;
  }
  // One constraint per step: plain loops, as in Multiply.
  for (int j = 0; j < num_steps_; ++j) {
    const double l = lambda(j);
    for (int s = std::max(j - 1, 1); s <= std::min(j + 1, num_steps_); ++s) {
      const double* B = blocks_[Index(j, s)].data();
      double* out = y->data() + static_cast<Eigen::Index>(s - 1) * n;
      for (int c = 0; c < n; ++c) out[c] += B[c] * l;
    }
  }
}

void BlockConstraintJacobian::CheckBlockShapes(const char* function) const {
  // The blocks are mutable references (Block): one resized by its owner would be read out of
  // bounds by the loops above. The message is built only on failure.
  for (size_t i = 0; i < blocks_.size(); ++i) {
    const Eigen::MatrixXd& b = blocks_[i];
    if (b.rows() == num_constraints_ && b.cols() == num_positions_) continue;
    const int j = static_cast<int>(i / 3), s = j - 1 + static_cast<int>(i % 3);
    ThrowInvalidArgument(
        function, "block (" + std::to_string(j) + ", " + std::to_string(s) + ")",
        std::to_string(b.rows()) + " x " + std::to_string(b.cols()),
        std::to_string(num_constraints_) + " x " + std::to_string(num_positions_) + " (nu x n)");
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
