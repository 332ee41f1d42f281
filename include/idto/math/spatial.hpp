#pragma once

/// @file
/// Spatial algebra (Featherstone) on fixed-size Eigen types, templated on the scalar type
/// (double, or an automatic-differentiation scalar in the tests); nothing here allocates for
/// double. The value types are small and defined in this header (inline) so that the double
/// kernels keep them inlined; `Foo` is `FooTpl<double>`.
///
/// A spatial motion is the pair (w, v): angular velocity and the linear velocity of the point at
/// the origin of the frame it is expressed in. A spatial force is (n, f): moment about that
/// origin and force. Rigid transforms are poses: X_AB = (R_AB, p_AB) maps coordinates in B to
/// coordinates in A.

#include <Eigen/Core>

#include "idto/math/scalar.hpp"

namespace idto {

/// Skew-symmetric matrix [w]x with [w]x u = w x u.
template <typename Scalar>
inline Matrix3<Scalar> Skew(const Vector3<Scalar>& w) {
  Matrix3<Scalar> S;
  S << Scalar(0), -w.z(), w.y(), w.z(), Scalar(0), -w.x(), -w.y(), w.x(), Scalar(0);
  return S;
}

/// A spatial motion (twist or spatial acceleration): angular part w, linear part v.
template <typename Scalar>
struct SpatialMotionTpl {
  using Vec3 = Vector3<Scalar>;
  Vec3 w{Vec3::Zero()};
  Vec3 v{Vec3::Zero()};

  SpatialMotionTpl() = default;
  SpatialMotionTpl(const Vec3& w_in, const Vec3& v_in) : w(w_in), v(v_in) {}
  static SpatialMotionTpl Zero() { return {}; }
  SpatialMotionTpl operator+(const SpatialMotionTpl& o) const { return {w + o.w, v + o.v}; }
  SpatialMotionTpl operator-(const SpatialMotionTpl& o) const { return {w - o.w, v - o.v}; }
  SpatialMotionTpl& operator+=(const SpatialMotionTpl& o) {
    w += o.w;
    v += o.v;
    return *this;
  }
  SpatialMotionTpl operator*(const Scalar& s) const { return {w * s, v * s}; }
  /// As a 6-vector [w; v].
  Vector6<Scalar> vector() const {
    Vector6<Scalar> x;
    x << w, v;
    return x;
  }
  template <typename NewScalar>
  SpatialMotionTpl<NewScalar> cast() const {
    return {w.template cast<NewScalar>(), v.template cast<NewScalar>()};
  }
};

/// A spatial force (wrench): moment n about the frame origin and force f.
template <typename Scalar>
struct SpatialForceTpl {
  using Vec3 = Vector3<Scalar>;
  Vec3 n{Vec3::Zero()};
  Vec3 f{Vec3::Zero()};

  SpatialForceTpl() = default;
  SpatialForceTpl(const Vec3& n_in, const Vec3& f_in) : n(n_in), f(f_in) {}
  static SpatialForceTpl Zero() { return {}; }
  SpatialForceTpl operator+(const SpatialForceTpl& o) const { return {n + o.n, f + o.f}; }
  SpatialForceTpl operator-(const SpatialForceTpl& o) const { return {n - o.n, f - o.f}; }
  SpatialForceTpl& operator+=(const SpatialForceTpl& o) {
    n += o.n;
    f += o.f;
    return *this;
  }
  SpatialForceTpl& operator-=(const SpatialForceTpl& o) {
    n -= o.n;
    f -= o.f;
    return *this;
  }
  /// As a 6-vector [n; f].
  Vector6<Scalar> vector() const {
    Vector6<Scalar> x;
    x << n, f;
    return x;
  }
  template <typename NewScalar>
  SpatialForceTpl<NewScalar> cast() const {
    return {n.template cast<NewScalar>(), f.template cast<NewScalar>()};
  }
};

/// Power: the scalar product of a motion and a force expressed in the same frame.
template <typename Scalar>
IDTO_ALWAYS_INLINE Scalar Dot(const SpatialMotionTpl<Scalar>& m, const SpatialForceTpl<Scalar>& F) {
  return m.w.dot(F.n) + m.v.dot(F.f);
}

/// Motion cross product m1 x m2 = [w1 x w2; w1 x v2 + v1 x w2].
template <typename Scalar>
IDTO_ALWAYS_INLINE SpatialMotionTpl<Scalar> Cross(const SpatialMotionTpl<Scalar>& m1,
                                                  const SpatialMotionTpl<Scalar>& m2) {
  return {m1.w.cross(m2.w), m1.w.cross(m2.v) + m1.v.cross(m2.w)};
}

/// Force cross product m x* F = [w x n + v x f; w x f].
template <typename Scalar>
IDTO_ALWAYS_INLINE SpatialForceTpl<Scalar> CrossForce(const SpatialMotionTpl<Scalar>& m,
                                                      const SpatialForceTpl<Scalar>& F) {
  return {m.w.cross(F.n) + m.v.cross(F.f), m.w.cross(F.f)};
}

/// A rigid transform (pose) X_AB: rotation R_AB and position p_AB of B's origin in A.
template <typename Scalar>
struct RigidTransformTpl {
  using Vec3 = Vector3<Scalar>;
  using Mat3 = Matrix3<Scalar>;
  Mat3 R{Mat3::Identity()};
  Vec3 p{Vec3::Zero()};

  RigidTransformTpl() = default;
  RigidTransformTpl(const Mat3& R_in, const Vec3& p_in) : R(R_in), p(p_in) {}
  static RigidTransformTpl Identity() { return {}; }

  /// X_AC = X_AB * X_BC.
  RigidTransformTpl operator*(const RigidTransformTpl& X_BC) const {
    return {R * X_BC.R, R * X_BC.p + p};
  }
  /// p_AQ = X_AB * p_BQ.
  Vec3 operator*(const Vec3& p_BQ) const { return R * p_BQ + p; }
  RigidTransformTpl inverse() const {
    const Mat3 Rt = R.transpose();
    return {Rt, -(Rt * p)};
  }

  /// A motion expressed in B (at Bo) re-expressed in A (at Ao).
  SpatialMotionTpl<Scalar> ActOn(const SpatialMotionTpl<Scalar>& m_B) const {
    const Vec3 w = R * m_B.w;
    return {w, R * m_B.v + p.cross(w)};
  }
  /// A motion expressed in A (at Ao) re-expressed in B (at Bo).
  SpatialMotionTpl<Scalar> InverseActOn(const SpatialMotionTpl<Scalar>& m_A) const {
    return {R.transpose() * m_A.w, R.transpose() * (m_A.v - p.cross(m_A.w))};
  }
  /// A force expressed in B (about Bo) re-expressed in A (about Ao).
  SpatialForceTpl<Scalar> ActOn(const SpatialForceTpl<Scalar>& F_B) const {
    const Vec3 f = R * F_B.f;
    return {R * F_B.n + p.cross(f), f};
  }
  /// A force expressed in A (about Ao) re-expressed in B (about Bo).
  SpatialForceTpl<Scalar> InverseActOn(const SpatialForceTpl<Scalar>& F_A) const {
    return {R.transpose() * (F_A.n - p.cross(F_A.f)), R.transpose() * F_A.f};
  }
  template <typename NewScalar>
  RigidTransformTpl<NewScalar> cast() const {
    return {R.template cast<NewScalar>(), p.template cast<NewScalar>()};
  }
};

/// Spatial inertia of a rigid body about the origin of the frame it is expressed in: mass m,
/// first moment h = m c (c: centre of mass) and rotational inertia Ibar about the origin.
template <typename Scalar>
struct SpatialInertiaTpl {
  using Vec3 = Vector3<Scalar>;
  using Mat3 = Matrix3<Scalar>;
  Scalar mass{0.0};
  Vec3 h{Vec3::Zero()};
  Mat3 Ibar{Mat3::Zero()};

  SpatialInertiaTpl() = default;
  SpatialInertiaTpl(const Scalar& m, const Vec3& h_in, const Mat3& Ibar_in)
      : mass(m), h(h_in), Ibar(Ibar_in) {}

  /// From mass, centre of mass c and rotational inertia I_c about the centre of mass.
  static SpatialInertiaTpl FromMassComInertia(const Scalar& m, const Vec3& c, const Mat3& I_c) {
    // Ibar = I_c + m ([c]x [c]x)^T = I_c + m (|c|^2 I - c c^T) (parallel axis theorem).
    return {m, m * c, I_c + m * (c.squaredNorm() * Mat3::Identity() - c * c.transpose())};
  }
  static SpatialInertiaTpl Zero() { return {}; }

  Vec3 com() const { return mass > 0.0 ? Vec3(h / mass) : Vec3(Vec3::Zero()); }
  /// Rotational inertia about the centre of mass.
  Mat3 InertiaAboutCom() const {
    if (!(mass > 0.0)) return Ibar;
    const Vec3 c = h / mass;
    return Ibar - mass * (c.squaredNorm() * Mat3::Identity() - c * c.transpose());
  }

  /// Momentum I * m: [Ibar w + h x v; m v - h x w].
  IDTO_ALWAYS_INLINE SpatialForceTpl<Scalar> operator*(const SpatialMotionTpl<Scalar>& m) const {
    return {Ibar * m.w + h.cross(m.v), mass * m.v - h.cross(m.w)};
  }
  SpatialInertiaTpl& operator+=(const SpatialInertiaTpl& o) {
    mass += o.mass;
    h += o.h;
    Ibar += o.Ibar;
    return *this;
  }
  SpatialInertiaTpl operator+(const SpatialInertiaTpl& o) const {
    SpatialInertiaTpl s = *this;
    s += o;
    return s;
  }

  /// The same inertia expressed in frame A, given X_AB (this inertia is expressed in B).
  IDTO_ALWAYS_INLINE SpatialInertiaTpl ExpressedIn(const RigidTransformTpl<Scalar>& X_AB) const {
    const Vec3 hR = X_AB.R * h;
    const Vec3& p = X_AB.p;
    // R Ibar R^T, its upper triangle computed and mirrored (exactly symmetric, 18 fewer products).
    const Mat3 T = X_AB.R * Ibar;
    Mat3 I;
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r <= c; ++r) {
        I(r, c) = T(r, 0) * X_AB.R(c, 0) + T(r, 1) * X_AB.R(c, 1) + T(r, 2) * X_AB.R(c, 2);
        I(c, r) = I(r, c);
      }
    }
    // Parallel-axis shift of the origin from Bo to Ao (see docs/architecture.md).
    I -= hR * p.transpose() + p * hR.transpose() + mass * p * p.transpose();
    I.diagonal().array() += 2.0 * hR.dot(p) + mass * p.squaredNorm();
    return {mass, hR + mass * p, I};
  }

  /// The 6x6 matrix acting on [w; v].
  Matrix6<Scalar> matrix() const {
    Matrix6<Scalar> M;
    M.template topLeftCorner<3, 3>() = Ibar;
    M.template topRightCorner<3, 3>() = Skew(h);
    M.template bottomLeftCorner<3, 3>() = -Skew(h);
    M.template bottomRightCorner<3, 3>() = mass * Mat3::Identity();
    return M;
  }
  template <typename NewScalar>
  SpatialInertiaTpl<NewScalar> cast() const {
    return {NewScalar(mass), h.template cast<NewScalar>(), Ibar.template cast<NewScalar>()};
  }
};

using SpatialMotion = SpatialMotionTpl<double>;
using SpatialForce = SpatialForceTpl<double>;
using RigidTransform = RigidTransformTpl<double>;
using SpatialInertia = SpatialInertiaTpl<double>;

}  // namespace idto
