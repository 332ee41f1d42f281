#pragma once

/// @file
/// The paper's smooth compliant contact law (§ Contact modeling), with analytic partials.
///
/// For a pair (A, B) with signed distance phi (m, negative in penetration), unit normal n from A
/// to B, and contact velocity v_c of B's contact point relative to A's (m/s), split into
/// v_n = n . v_c (positive when separating) and v_t = v_c - v_n n:
///
///   f_n = c(phi) d(v_n),        c(phi) = sigma k log(1 + exp(-phi / sigma)),
///   d(v_n) = 1 - x              for x = v_n / v_d < 0,
///            (x - 2)^2 / 4      for 0 <= x < 2,
///            0                  for x >= 2,
///   f_t = -mu v_t / sqrt(v_s^2 + |v_t|^2) f_n,
///   f   = f_n n + f_t           (the force on B; A receives -f).
///
/// Every quantity is evaluated without overflow for any phi / sigma (log-sum-exp form), and
/// every derivative is finite, including at v_t = 0 and phi = 0.

#include <string>

#include <Eigen/Core>

namespace idto {

/// Parameters of the contact law. Defaults are the paper's quadruped values (Table 2) with its
/// recommended dissipation velocity; every example sets its own.
struct ContactParameters {
  double stiffness{2000.0};          ///< k, N/m: slope of the normal force in penetration
  double smoothing{0.01};            ///< sigma, m: force-at-a-distance length scale
  double dissipation_velocity{0.1};  ///< v_d, m/s: lower is stiffer and less bouncy
  double friction_coefficient{1.0};  ///< mu, dimensionless
  double stiction_velocity{0.1};     ///< v_s, m/s: sliding speed during "stiction"

  /// Throws InvalidArgument naming `where`, the field and its value unless every field is
  /// finite and positive (friction may be zero).
  void Validate(const std::string& where) const;
};

/// Normal force, friction and their partial derivatives for one contact, on Scalar (double,
/// or an automatic-differentiation scalar in the tests); ContactForce is the double one.
template <typename Scalar>
struct ContactForceTpl {
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
  Scalar compliance{0.0};   ///< c(phi), N
  Scalar dissipation{0.0};  ///< d(v_n), dimensionless
  Scalar fn{0.0};           ///< normal force magnitude, N (>= 0)
  Vec3 ft{Vec3::Zero()};    ///< friction force on B, N (world)
  Vec3 f{Vec3::Zero()};     ///< total force on B: fn n + ft, N (world)

  Scalar dfn_dphi{0.0};  ///< N/m
  Scalar dfn_dvn{0.0};   ///< N s/m
  /// Partials of ft (3) with respect to phi, v_n and v_t (3 x 3), world frame.
  Vec3 dft_dphi{Vec3::Zero()};
  Vec3 dft_dvn{Vec3::Zero()};
  Eigen::Matrix<Scalar, 3, 3> dft_dvt{Eigen::Matrix<Scalar, 3, 3>::Zero()};
};

using ContactForce = ContactForceTpl<double>;

/// softplus(x) = log(1 + exp(x)) without overflow or loss of precision for any x.
double Softplus(double x);
/// The logistic function 1 / (1 + exp(-x)) (= d softplus / dx), stable for any x.
double Logistic(double x);

/// c(phi) and dc/dphi.
void ComplianceAndDerivative(const ContactParameters& p, double phi, double* c, double* dc_dphi);
/// d(v_n) and dd/dv_n.
void DissipationAndDerivative(const ContactParameters& p, double vn, double* d, double* dd_dvn);

/// The contact force of the law above. `normal` (3) is the unit normal n from A to B, `vn` the
/// normal component of the relative velocity and `vt` (3) its tangential part (orthogonal to n).
/// Branch points of d(v_n) (x = 0 and x = 2) take the derivative of the branch on the right
/// (x >= 0 uses the quadratic, x >= 2 the zero branch): a one-sided derivative.
ContactForce CalcContactForce(const ContactParameters& p, double phi, double vn,
                              const Eigen::Vector3d& vt, const Eigen::Vector3d& normal);

/// CalcContactForce on any Scalar (defined in contact_law-inl.hpp; double compiled once).
template <typename Scalar>
ContactForceTpl<Scalar> CalcContactForceTpl(const ContactParameters& p, const Scalar& phi,
                                            const Scalar& vn, const Eigen::Matrix<Scalar, 3, 1>& vt,
                                            const Eigen::Matrix<Scalar, 3, 1>& normal);

extern template ContactForceTpl<double> CalcContactForceTpl<double>(const ContactParameters&,
                                                                    const double&, const double&,
                                                                    const Eigen::Vector3d&,
                                                                    const Eigen::Vector3d&);

/// The signed distance beyond which c(phi) < force_tolerance: pairs farther apart than this
/// exert less than force_tolerance * d(v_n) (N) and may be skipped. Finite for any positive
/// tolerance; grows like sigma log(sigma k / tolerance) for small tolerances.
double ContactCutoffDistance(const ContactParameters& p, double force_tolerance);

}  // namespace idto
