#pragma once

/// @file
/// C²-continuous cubic splines through knots (natural end conditions), one per coordinate,
/// used to resample plans (warm-start shift) and to feed the PD+ controller.

#include <vector>

#include <Eigen/Core>

namespace idto::mpc {

/// A natural cubic spline x(t) through (t_i, x_i), i = 0..m-1 (m >= 2, strictly increasing
/// times), each x_i a vector of the same size n. x, x', x'' are continuous; x'' = 0 at both ends.
/// Outside [t_0, t_{m-1}] the spline is extended linearly (constant first derivative).
class CubicSpline {
 public:
  CubicSpline() = default;
  /// Throws InvalidArgument on fewer than 2 knots, non-increasing or non-finite times, or knots
  /// of different sizes.
  CubicSpline(const std::vector<double>& times, const std::vector<Eigen::VectorXd>& values);

  /// Refits to new knots, reusing storage when the sizes are unchanged.
  void Fit(const std::vector<double>& times, const std::vector<Eigen::VectorXd>& values);

  int num_knots() const { return static_cast<int>(t_.size()); }
  int size() const { return n_; }
  double start_time() const { return t_.front(); }
  double end_time() const { return t_.back(); }

  /// Value, first and second derivatives at t (each of size n; outputs may be null).
  void Evaluate(double t, Eigen::VectorXd* x, Eigen::VectorXd* xdot = nullptr,
                Eigen::VectorXd* xddot = nullptr) const;

 private:
  int n_{0};
  std::vector<double> t_;
  Eigen::MatrixXd x_;   // n x m knot values
  Eigen::MatrixXd m2_;  // n x m second derivatives at the knots
  Eigen::VectorXd diag_, rhs_scratch_;
};

}  // namespace idto::mpc
