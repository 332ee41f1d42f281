#pragma once

/// @file
/// The gradient of the cost from the cost alone (the reference of the derivatives study) and the
/// error of the solver's gradient against it.

#include <vector>

#include <Eigen/Core>

#include "idto/problem/derivative_method.hpp"
#include "idto/solver/trajectory_optimizer.hpp"

namespace idto::tradeoffs {

/// Initial steps of the reference, relative to max(1, |q_i|); per coordinate the one with the
/// smaller error estimate wins.
constexpr double kReferenceSteps[] = {1e-4, 1e-5};

struct Reference {
  Eigen::VectorXd g;  ///< the reference gradient
  double error{0.0};  ///< |per-coordinate error estimates|_2
  int cost_evaluations{0};
};

/// The gradient of the cost L(q) with respect to q_1..q_N from L alone (none of the solver's
/// derivatives): per coordinate, the mean of the forward-side and backward-side Richardson
/// extrapolations of one-sided differences. Where L is C^1 both sides converge to the
/// derivative, so half their difference (with the tableau corrections) estimates the
/// reference's error.
Reference ReferenceGradient(TrajectoryOptimizer* optimizer, std::vector<Eigen::VectorXd> q);

/// ‖g − reference‖ for the solver's gradient with `method` and relative step `step` (0: the
/// method's default; ignored by kAnalytic). Leaves the optimizer's step at 0.
double GradientError(TrajectoryOptimizer* optimizer, const std::vector<Eigen::VectorXd>& q,
                     DerivativeMethod method, const Eigen::VectorXd& reference, double step = 0.0);

}  // namespace idto::tradeoffs
