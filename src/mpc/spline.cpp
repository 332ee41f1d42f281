#include "idto/mpc/spline.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "idto/core/errors.hpp"

namespace idto::mpc {

CubicSpline::CubicSpline(const std::vector<double>& times,
                         const std::vector<Eigen::VectorXd>& values) {
  Fit(times, values);
}

void CubicSpline::Fit(const std::vector<double>& times,
                      const std::vector<Eigen::VectorXd>& values) {
  static constexpr const char* kWhere = "CubicSpline";
  const int m = static_cast<int>(times.size());
  if (m < 2) ThrowInvalidArgument(kWhere, "times", std::to_string(m) + " knots", "at least 2");
  if (static_cast<int>(values.size()) != m) {
    ThrowInvalidArgument(kWhere, "values", std::to_string(values.size()) + " knots",
                         std::to_string(m) + " (one per time)");
  }
  const int n = static_cast<int>(values[0].size());
  for (int i = 0; i < m; ++i) {
    CheckFinite(kWhere, "times[" + std::to_string(i) + "]", times[i]);
    if (i > 0 && !(times[i] > times[i - 1])) {
      ThrowInvalidArgument(
          kWhere, "times[" + std::to_string(i) + "]", FormatValue(times[i]),
          "greater than times[" + std::to_string(i - 1) + "] = " + FormatValue(times[i - 1]));
    }
    if (values[i].size() != n) {
      CheckSize(kWhere, "values[" + std::to_string(i) + "]", values[i].size(), n, "values[0]");
    }
  }
  n_ = n;
  t_ = times;
  if (x_.rows() != n || x_.cols() != m) {
    x_.resize(n, m);
    m2_.resize(n, m);
    diag_.resize(m);
    rhs_scratch_.resize(m);
  }
  for (int i = 0; i < m; ++i) x_.col(i) = values[i];
  m2_.setZero();
  if (m == 2) return;  // a straight line
  // Natural spline: for i = 1..m-2,
  //   h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1}
  //     = 6 ((x_{i+1} - x_i) / h_i - (x_i - x_{i-1}) / h_{i-1}),  M_0 = M_{m-1} = 0.
  // Thomas algorithm; the elimination factors are shared by all n coordinates.
  for (int i = 1; i < m - 1; ++i) {
    const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
    m2_.col(i) = 6.0 * ((x_.col(i + 1) - x_.col(i)) / h1 - (x_.col(i) - x_.col(i - 1)) / h0);
    diag_(i) = 2.0 * (h0 + h1);
    if (i > 1) {
      const double w = h0 / diag_(i - 1);  // sub-diagonal h0 over the previous pivot
      diag_(i) -= w * h0;                  // previous super-diagonal is h0 too
      m2_.col(i) -= w * m2_.col(i - 1);
    }
  }
  for (int i = m - 2; i >= 1; --i) {
    const double h1 = t_[i + 1] - t_[i];
    if (i < m - 2) m2_.col(i) -= h1 * m2_.col(i + 1);
    m2_.col(i) /= diag_(i);
  }
}

void CubicSpline::Evaluate(double t, Eigen::VectorXd* x, Eigen::VectorXd* xdot,
                           Eigen::VectorXd* xddot) const {
  const int m = num_knots();
  auto in_interval = [&](int i, double tt, Eigen::VectorXd* xo, Eigen::VectorXd* vo,
                         Eigen::VectorXd* ao) {
    const double h = t_[i + 1] - t_[i];
    const double A = t_[i + 1] - tt, B = tt - t_[i];
    if (xo != nullptr) {
      *xo = (m2_.col(i) * (A * A * A) + m2_.col(i + 1) * (B * B * B)) / (6.0 * h) +
            (x_.col(i) / h - m2_.col(i) * (h / 6.0)) * A +
            (x_.col(i + 1) / h - m2_.col(i + 1) * (h / 6.0)) * B;
    }
    if (vo != nullptr) {
      *vo = (m2_.col(i + 1) * (B * B) - m2_.col(i) * (A * A)) / (2.0 * h) +
            (x_.col(i + 1) - x_.col(i)) / h - (m2_.col(i + 1) - m2_.col(i)) * (h / 6.0);
    }
    if (ao != nullptr) *ao = (m2_.col(i) * A + m2_.col(i + 1) * B) / h;
  };
  if (t < t_.front() || t > t_.back()) {
    // Linear extension with the end slope (the natural spline has x'' = 0 there).
    const bool before = t < t_.front();
    const int i = before ? 0 : m - 2;
    const double t_end = before ? t_.front() : t_.back();
    Eigen::VectorXd* slope = xdot;
    Eigen::VectorXd local;
    if (slope == nullptr) slope = &local;
    in_interval(i, t_end, x, slope, nullptr);
    if (x != nullptr) *x += (t - t_end) * (*slope);
    if (xddot != nullptr) xddot->setZero(n_);
    return;
  }
  const int i =
      std::min(m - 2, static_cast<int>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1);
  in_interval(std::max(i, 0), t, x, xdot, xddot);
}

}  // namespace idto::mpc
