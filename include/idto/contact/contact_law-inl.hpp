#pragma once

/// @file
/// Definitions of the Scalar-templated contact law (include to instantiate it with a scalar
/// other than double). For a non-double Scalar, log1p is evaluated as log(1 + x): its value
/// loses relative accuracy where exp(-|phi|/sigma) is below machine epsilon, its derivative
/// does not.

#include <cmath>
#include <type_traits>

#include "idto/contact/contact_law.hpp"

namespace idto {
namespace internal {

template <typename S>
S Log1pTpl(const S& x) {
  if constexpr (std::is_same_v<S, double>) {
    return std::log1p(x);
  } else {
    using std::log;
    return log(S(1.0) + x);
  }
}

// log(1 + e^x) = max(x, 0) + log1p(e^-|x|): no overflow, full precision in both tails. Written
// with one branch per sign (not max and abs) so that a derivative scalar gets the smooth
// derivative at x = 0 too.
template <typename S>
S SoftplusTpl(const S& x) {
  using std::exp;
  if (x > 0.0) return x + Log1pTpl<S>(exp(-x));
  return Log1pTpl<S>(exp(x));
}

template <typename S>
S LogisticTpl(const S& x) {
  using std::exp;
  if (x >= 0.0) return S(1.0) / (S(1.0) + exp(-x));
  const S e = exp(x);
  return e / (S(1.0) + e);
}

// d(v_n) = 1 - x (x < 0), (x - 2)^2 / 4 (0 <= x < 2), 0 (x >= 2), x = v_n / v_d, and its
// derivative (at x = 0 and x = 2: the branch on the right).
template <typename S>
void DissipationTpl(const ContactParameters& p, const S& vn, S* d, S* dd_dvn) {
  const S x = vn / p.dissipation_velocity;
  if (x < 0.0) {
    *d = S(1.0) - x;
    *dd_dvn = S(-1.0 / p.dissipation_velocity);
  } else if (x < 2.0) {
    *d = 0.25 * (x - 2.0) * (x - 2.0);
    *dd_dvn = 0.5 * (x - 2.0) / p.dissipation_velocity;
  } else {
    *d = S(0.0);
    *dd_dvn = S(0.0);
  }
}

}  // namespace internal

template <typename Scalar>
ContactForceTpl<Scalar> CalcContactForceTpl(const ContactParameters& p, const Scalar& phi,
                                            const Scalar& vn, const Eigen::Matrix<Scalar, 3, 1>& vt,
                                            const Eigen::Matrix<Scalar, 3, 1>& normal) {
  using std::sqrt;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  ContactForceTpl<Scalar> out;
  // c(phi) = sigma k softplus(-phi / sigma), dc/dphi = -k logistic(-phi / sigma).
  const Scalar xc = -phi / p.smoothing;
  out.compliance = (p.smoothing * p.stiffness) * internal::SoftplusTpl<Scalar>(xc);
  const Scalar dc_dphi = -p.stiffness * internal::LogisticTpl<Scalar>(xc);
  Scalar dd_dvn;
  internal::DissipationTpl<Scalar>(p, vn, &out.dissipation, &dd_dvn);
  out.fn = out.compliance * out.dissipation;
  out.dfn_dphi = dc_dphi * out.dissipation;
  out.dfn_dvn = out.compliance * dd_dvn;
  // ft = -mu fn vt / s, s = sqrt(vs^2 + |vt|^2) >= vs > 0: smooth everywhere, zero at vt = 0.
  const Scalar s = sqrt(p.stiction_velocity * p.stiction_velocity + vt.squaredNorm());
  const Vec3 t = vt / s;  // |t| < 1
  const double mu = p.friction_coefficient;
  out.ft = (-mu * out.fn) * t;
  out.f = out.fn * normal + out.ft;
  out.dft_dphi = (-mu * out.dfn_dphi) * t;
  out.dft_dvn = (-mu * out.dfn_dvn) * t;
  out.dft_dvt = (-mu * out.fn / s) * (Eigen::Matrix<Scalar, 3, 3>::Identity() - t * t.transpose());
  return out;
}

}  // namespace idto
