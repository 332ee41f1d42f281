#include "idto/contact/contact_law.hpp"

#include <cmath>

#include "idto/core/errors.hpp"

namespace idto {

void ContactParameters::Validate(const std::string& where) const {
  CheckPositive(where, "contact stiffness", stiffness);
  CheckPositive(where, "contact smoothing", smoothing);
  CheckPositive(where, "contact dissipation_velocity", dissipation_velocity);
  CheckNonNegative(where, "contact friction_coefficient", friction_coefficient);
  CheckPositive(where, "contact stiction_velocity", stiction_velocity);
}

double Softplus(double x) {
  // log(1 + e^x) = max(x, 0) + log1p(e^-|x|): no overflow, full precision in both tails.
  return std::max(x, 0.0) + std::log1p(std::exp(-std::abs(x)));
}

double Logistic(double x) {
  if (x >= 0.0) return 1.0 / (1.0 + std::exp(-x));
  const double e = std::exp(x);
  return e / (1.0 + e);
}

void ComplianceAndDerivative(const ContactParameters& p, double phi, double* c, double* dc_dphi) {
  const double x = -phi / p.smoothing;
  *c = p.smoothing * p.stiffness * Softplus(x);
  *dc_dphi = -p.stiffness * Logistic(x);
}

void DissipationAndDerivative(const ContactParameters& p, double vn, double* d, double* dd_dvn) {
  const double x = vn / p.dissipation_velocity;
  if (x < 0.0) {
    *d = 1.0 - x;
    *dd_dvn = -1.0 / p.dissipation_velocity;
  } else if (x < 2.0) {
    *d = 0.25 * (x - 2.0) * (x - 2.0);
    *dd_dvn = 0.5 * (x - 2.0) / p.dissipation_velocity;
  } else {
    *d = 0.0;
    *dd_dvn = 0.0;
  }
}

ContactForce CalcContactForce(const ContactParameters& p, double phi, double vn,
                              const Eigen::Vector3d& vt, const Eigen::Vector3d& normal) {
  ContactForce out;
  double dc_dphi, dd_dvn;
  ComplianceAndDerivative(p, phi, &out.compliance, &dc_dphi);
  DissipationAndDerivative(p, vn, &out.dissipation, &dd_dvn);
  out.fn = out.compliance * out.dissipation;
  out.dfn_dphi = dc_dphi * out.dissipation;
  out.dfn_dvn = out.compliance * dd_dvn;
  // ft = -mu fn vt / s, s = sqrt(vs^2 + |vt|^2) >= vs > 0: smooth everywhere, zero at vt = 0.
  const double s = std::sqrt(p.stiction_velocity * p.stiction_velocity + vt.squaredNorm());
  const Eigen::Vector3d t = vt / s;  // |t| < 1
  const double mu = p.friction_coefficient;
  out.ft = -mu * out.fn * t;
  out.f = out.fn * normal + out.ft;
  out.dft_dphi = -mu * out.dfn_dphi * t;
  out.dft_dvn = -mu * out.dfn_dvn * t;
  out.dft_dvt = (-mu * out.fn / s) * (Eigen::Matrix3d::Identity() - t * t.transpose());
  return out;
}

double ContactCutoffDistance(const ContactParameters& p, double force_tolerance) {
  CheckPositive("ContactCutoffDistance", "force_tolerance", force_tolerance);
  // c(phi) = tol  <=>  softplus(-phi / sigma) = tol / (sigma k)
  //               <=>  phi = -sigma log(expm1(tol / (sigma k))).
  const double y = force_tolerance / (p.smoothing * p.stiffness);
  // log(expm1(y)) = y + log1p(-exp(-y)): no overflow for large y.
  const double log_expm1 = y > 30.0 ? y + std::log1p(-std::exp(-y)) : std::log(std::expm1(y));
  return -p.smoothing * log_expm1;
}

}  // namespace idto
