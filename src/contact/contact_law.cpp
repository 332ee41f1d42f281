#include "idto/contact/contact_law.hpp"

#include <cmath>

#include "idto/contact/contact_law-inl.hpp"
#include "idto/core/errors.hpp"

namespace idto {

void ContactParameters::Validate(const std::string& where) const {
  CheckPositive(where, "contact stiffness", stiffness);
  CheckPositive(where, "contact smoothing", smoothing);
  CheckPositive(where, "contact dissipation_velocity", dissipation_velocity);
  CheckNonNegative(where, "contact friction_coefficient", friction_coefficient);
  CheckPositive(where, "contact stiction_velocity", stiction_velocity);
}

double Softplus(double x) { return internal::SoftplusTpl<double>(x); }

double Logistic(double x) { return internal::LogisticTpl<double>(x); }

void ComplianceAndDerivative(const ContactParameters& p, double phi, double* c, double* dc_dphi) {
  const double x = -phi / p.smoothing;
  *c = p.smoothing * p.stiffness * Softplus(x);
  *dc_dphi = -p.stiffness * Logistic(x);
}

void DissipationAndDerivative(const ContactParameters& p, double vn, double* d, double* dd_dvn) {
  internal::DissipationTpl<double>(p, vn, d, dd_dvn);
}

template ContactForceTpl<double> CalcContactForceTpl<double>(const ContactParameters&,
                                                             const double&, const double&,
                                                             const Eigen::Vector3d&,
                                                             const Eigen::Vector3d&);

ContactForce CalcContactForce(const ContactParameters& p, double phi, double vn,
                              const Eigen::Vector3d& vt, const Eigen::Vector3d& normal) {
  return CalcContactForceTpl<double>(p, phi, vn, vt, normal);
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
