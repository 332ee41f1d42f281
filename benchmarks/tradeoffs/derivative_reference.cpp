// The reference gradient of the derivatives study: Richardson-extrapolated one-sided
// differences of the cost alone.

#include "derivative_reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace idto::tradeoffs {
namespace {

/// Richardson extrapolation to h -> 0 of the one-sided difference (L(s h) - L(0)) / (s h) at
/// h = h0, h0/2, h0/4, h0/8 (a full tableau: the h, h^2 and h^3 error terms are eliminated).
/// One-sided, so it stays valid where L is only C^1 at the point itself. *estimate is the last
/// correction of the tableau.
template <typename F>
double OneSidedRichardson(const F& cost, double f0, double side, double h0, double* estimate) {
  constexpr int kSteps = 4;
  double r[kSteps][kSteps];
  for (int j = 0; j < kSteps; ++j) {
    const double h = side * h0 / static_cast<double>(1 << j);
    r[j][0] = (cost(h) - f0) / h;
  }
  for (int m = 1; m < kSteps; ++m) {
    const double factor = static_cast<double>(1 << m);
    for (int j = 0; j + m < kSteps; ++j) {
      r[j][m] = (factor * r[j + 1][m - 1] - r[j][m - 1]) / (factor - 1.0);
    }
  }
  *estimate = std::abs(r[0][kSteps - 1] - r[1][kSteps - 2]);
  return r[0][kSteps - 1];
}

}  // namespace

Reference ReferenceGradient(TrajectoryOptimizer* optimizer, std::vector<Eigen::VectorXd> q) {
  const int N = static_cast<int>(q.size()) - 1;
  const int nq = static_cast<int>(q[0].size());
  Reference ref;
  ref.g.resize(N * nq);
  const double f0 = optimizer->EvalCost(q);
  double error2 = 0.0;
  for (int k = 1; k <= N; ++k) {
    for (int i = 0; i < nq; ++i) {
      const double x = q[k](i);
      const auto cost = [&](double h) {
        q[k](i) = x + h;
        const double value = optimizer->EvalCost(q);
        q[k](i) = x;
        ++ref.cost_evaluations;
        return value;
      };
      double best = 0.0, best_error = std::numeric_limits<double>::infinity();
      for (double step : kReferenceSteps) {
        const double h0 = step * std::max(1.0, std::abs(x));
        double e_plus = 0.0, e_minus = 0.0;
        const double plus = OneSidedRichardson(cost, f0, 1.0, h0, &e_plus);
        const double minus = OneSidedRichardson(cost, f0, -1.0, h0, &e_minus);
        const double error = std::max({0.5 * std::abs(plus - minus), e_plus, e_minus});
        if (error < best_error) {
          best_error = error;
          best = 0.5 * (plus + minus);
        }
      }
      ref.g((k - 1) * nq + i) = best;
      error2 += best_error * best_error;
    }
  }
  ref.error = std::sqrt(error2);
  return ref;
}

double GradientError(TrajectoryOptimizer* optimizer, const std::vector<Eigen::VectorXd>& q,
                     DerivativeMethod method, const Eigen::VectorXd& reference, double step) {
  optimizer->mutable_options().derivative_method = method;
  optimizer->mutable_options().finite_difference_step = step;
  Eigen::VectorXd g;
  optimizer->EvalGradient(q, &g);
  optimizer->mutable_options().finite_difference_step = 0.0;
  return (g - reference).norm();
}

}  // namespace idto::tradeoffs
