#include "solver/trust_region.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.hpp"

namespace idto::internal {

void CalcScaling(const PentaDiagonalMatrix& H, ScalingMethod method, Eigen::VectorXd* D) {
  H.Diagonal(D);
  for (int i = 0; i < D->size(); ++i) {
    const double d = (*D)(i);
    if (method == ScalingMethod::kNone || !(d > 0.0) || !std::isfinite(d)) {
      (*D)(i) = 1.0;
    } else {
      (*D)(i) = method == ScalingMethod::kSqrt ? 1.0 / std::sqrt(d) : 1.0 / std::sqrt(std::sqrt(d));
    }
  }
}

bool FactorizeWithShift(PentaDiagonalMatrix* H, SplitPentaDiagonalCholesky* chol,
                        Eigen::VectorXd* diagonal, double* mu) {
  return FactorWithShift(H, diagonal, mu, [&] { return chol->compute(*H); });
}

void MultiplyInHalves(const PentaDiagonalMatrix& H, const Eigen::VectorXd& x, int num_threads,
                      Eigen::VectorXd* y) {
  const int N = H.num_blocks();
  if (y->size() != H.rows()) y->resize(H.rows());
  // Small blocks: a pool phase costs more than half the product saves.
  if (num_threads < 2 || H.block_size() < 8) return H.MultiplyRows(x, 0, N, y);
  ParallelFor(0, 2, std::min(num_threads, 2), [&](int half, int) {
    H.MultiplyRows(x, half == 0 ? 0 : N / 2, half == 0 ? N / 2 : N, y);
  });
}

void CalcCauchyPoint(const PentaDiagonalMatrix& H, const Eigen::VectorXd& g,
                     const Eigen::VectorXd& D, int num_threads, Eigen::VectorXd* d2g,
                     Eigen::VectorXd* Hd2g, Eigen::VectorXd* p_cauchy) {
  *d2g = D.cwiseProduct(D.cwiseProduct(g));
  MultiplyInHalves(H, *d2g, num_threads, Hd2g);
  const double gHg = d2g->dot(*Hd2g);
  const double gg = D.cwiseProduct(g).squaredNorm();
  if (gHg > 0.0) {
    *p_cauchy = (-gg / gHg) * (*d2g);
  } else {
    *p_cauchy = -(*d2g);
  }
}

DoglegStep CalcDoglegStep(const Eigen::VectorXd& p_newton, const Eigen::VectorXd& p_cauchy,
                          const Eigen::VectorXd& D, double radius, Eigen::VectorXd* w,
                          Eigen::VectorXd* u, Eigen::VectorXd* p, double* scaled_norm) {
  *w = p_newton.cwiseQuotient(D);  // D^-1 p_N
  const double newton_norm = w->norm();
  if (newton_norm <= radius) {
    *p = p_newton;
    *scaled_norm = newton_norm;
    return DoglegStep::kNewton;
  }
  *u = p_cauchy.cwiseQuotient(D);  // D^-1 p_C
  const double cauchy_norm = u->norm();
  if (cauchy_norm >= radius) {
    *p = (radius / cauchy_norm) * p_cauchy;
    *scaled_norm = radius;
    return DoglegStep::kCauchy;
  }
  // |u + t (w - u)| = radius, t in [0, 1].
  *w -= *u;
  const double a = w->squaredNorm();
  const double b = 2.0 * u->dot(*w);
  const double c = cauchy_norm * cauchy_norm - radius * radius;
  const double disc = std::sqrt(std::max(0.0, b * b - 4.0 * a * c));
  // Numerically stable root of the quadratic (c < 0, so the roots have opposite signs).
  const double t = b >= 0 ? (-2.0 * c) / (b + disc) : (disc - b) / (2.0 * a);
  *p = p_cauchy + t * (p_newton - p_cauchy);
  *scaled_norm = radius;
  return DoglegStep::kDogleg;
}

double ReductionRatio(double merit, double trial_merit, double predicted) {
  if (!std::isfinite(trial_merit) || !(predicted > 0.0)) {
    return -std::numeric_limits<double>::infinity();
  }
  return (merit - trial_merit) / predicted;
}

double UpdateTrustRadius(double ratio, double scaled_step_norm, double radius, double max_radius) {
  if (ratio < 0.25) return 0.25 * scaled_step_norm;
  if (ratio > 0.75 && scaled_step_norm >= radius * (1.0 - 1e-12)) {
    return std::min(2.0 * radius, max_radius);
  }
  return radius;
}

bool CostChangeConverged(double previous, double cost, const SolverOptions& options,
                         std::string* message) {
  const double change = std::abs(previous - cost) / std::max(1.0, std::abs(previous));
  if (!(change < options.cost_tolerance)) return false;
  *message = "relative cost change below cost_tolerance";
  return true;
}

bool GradientConverged(double g_dot_p, double cost, const SolverOptions& options,
                       std::string* message) {
  if (!(std::abs(g_dot_p) / std::max(1.0, std::abs(cost)) < options.gradient_tolerance)) {
    return false;
  }
  *message = "|g^T p| / L below gradient_tolerance";
  return true;
}

bool StepConverged(double step_norm, double q_norm, const SolverOptions& options,
                   std::string* message) {
  if (!(step_norm / std::max(1.0, q_norm) < options.step_tolerance)) return false;
  *message = "relative step below step_tolerance";
  return true;
}

bool PredictedReductionNegligible(double predicted, double merit) {
  return !(std::abs(predicted) > 1e-14 * std::max(1.0, std::abs(merit)));
}

}  // namespace idto::internal
