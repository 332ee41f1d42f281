#pragma once

/// @file
/// Central-difference Jacobians for checking analytic derivatives.

#include <functional>

#include <Eigen/Core>

namespace idto::test {

/// J(i, j) = d f_i / d x_j by central differences with step h (fourth-order Richardson
/// extrapolation when `richardson` is set, error O(h^4)).
inline Eigen::MatrixXd FiniteDifferenceJacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
    double h = 1e-6, bool richardson = false) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  Eigen::VectorXd xp = x;
  auto central = [&](Eigen::Index j, double step) {
    xp(j) = x(j) + step;
    const Eigen::VectorXd fp = f(xp);
    xp(j) = x(j) - step;
    const Eigen::VectorXd fm = f(xp);
    xp(j) = x(j);
    return Eigen::VectorXd((fp - fm) / (2 * step));
  };
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    if (richardson) {
      J.col(j) = (4.0 * central(j, h / 2) - central(j, h)) / 3.0;
    } else {
      J.col(j) = central(j, h);
    }
  }
  return J;
}

/// Derivative of a scalar function of a scalar by central differences.
inline double FiniteDifferenceDerivative(const std::function<double(double)>& f, double x,
                                         double h = 1e-6) {
  return (f(x + h) - f(x - h)) / (2 * h);
}

}  // namespace idto::test
