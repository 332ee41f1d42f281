#pragma once

/// @file
/// Spatial algebra (Featherstone) on fixed-size Eigen types; nothing here allocates.
///
/// A spatial motion is the pair (w, v): angular velocity and the linear velocity of the point at
/// the origin of the frame it is expressed in. A spatial force is (n, f): moment about that
/// origin and force. Rigid transforms are poses: X_AB = (R_AB, p_AB) maps coordinates in B to
/// coordinates in A.

#include <Eigen/Core>

namespace idto {

/// Skew-symmetric matrix [w]x with [w]x u = w x u.
inline Eigen::Matrix3d Skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d S;
  S << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return S;
}

/// A spatial motion (twist or spatial acceleration): angular part w, linear part v.
struct SpatialMotion {
  Eigen::Vector3d w{Eigen::Vector3d::Zero()};
  Eigen::Vector3d v{Eigen::Vector3d::Zero()};

  SpatialMotion() = default;
  SpatialMotion(const Eigen::Vector3d& w_in, const Eigen::Vector3d& v_in) : w(w_in), v(v_in) {}
  static SpatialMotion Zero() { return {}; }
  SpatialMotion operator+(const SpatialMotion& o) const { return {w + o.w, v + o.v}; }
  SpatialMotion operator-(const SpatialMotion& o) const { return {w - o.w, v - o.v}; }
  SpatialMotion& operator+=(const SpatialMotion& o) {
    w += o.w;
    v += o.v;
    return *this;
  }
  SpatialMotion operator*(double s) const { return {w * s, v * s}; }
  /// As a 6-vector [w; v].
  Eigen::Matrix<double, 6, 1> vector() const {
    Eigen::Matrix<double, 6, 1> x;
    x << w, v;
    return x;
  }
};

/// A spatial force (wrench): moment n about the frame origin and force f.
struct SpatialForce {
  Eigen::Vector3d n{Eigen::Vector3d::Zero()};
  Eigen::Vector3d f{Eigen::Vector3d::Zero()};

  SpatialForce() = default;
  SpatialForce(const Eigen::Vector3d& n_in, const Eigen::Vector3d& f_in) : n(n_in), f(f_in) {}
  static SpatialForce Zero() { return {}; }
  SpatialForce operator+(const SpatialForce& o) const { return {n + o.n, f + o.f}; }
  SpatialForce operator-(const SpatialForce& o) const { return {n - o.n, f - o.f}; }
  SpatialForce& operator+=(const SpatialForce& o) {
    n += o.n;
    f += o.f;
    return *this;
  }
  SpatialForce& operator-=(const SpatialForce& o) {
    n -= o.n;
    f -= o.f;
    return *this;
  }
  /// As a 6-vector [n; f].
  Eigen::Matrix<double, 6, 1> vector() const {
    Eigen::Matrix<double, 6, 1> x;
    x << n, f;
    return x;
  }
};

/// Power: the scalar product of a motion and a force expressed in the same frame.
inline double Dot(const SpatialMotion& m, const SpatialForce& F) {
  return m.w.dot(F.n) + m.v.dot(F.f);
}

/// Motion cross product m1 x m2 = [w1 x w2; w1 x v2 + v1 x w2].
inline SpatialMotion Cross(const SpatialMotion& m1, const SpatialMotion& m2) {
  return {m1.w.cross(m2.w), m1.w.cross(m2.v) + m1.v.cross(m2.w)};
}

/// Force cross product m x* F = [w x n + v x f; w x f].
inline SpatialForce CrossForce(const SpatialMotion& m, const SpatialForce& F) {
  return {m.w.cross(F.n) + m.v.cross(F.f), m.w.cross(F.f)};
}

/// A rigid transform (pose) X_AB: rotation R_AB and position p_AB of B's origin in A.
struct RigidTransform {
  Eigen::Matrix3d R{Eigen::Matrix3d::Identity()};
  Eigen::Vector3d p{Eigen::Vector3d::Zero()};

  RigidTransform() = default;
  RigidTransform(const Eigen::Matrix3d& R_in, const Eigen::Vector3d& p_in) : R(R_in), p(p_in) {}
  static RigidTransform Identity() { return {}; }

  /// X_AC = X_AB * X_BC.
  RigidTransform operator*(const RigidTransform& X_BC) const {
    return {R * X_BC.R, R * X_BC.p + p};
  }
  /// p_AQ = X_AB * p_BQ.
  Eigen::Vector3d operator*(const Eigen::Vector3d& p_BQ) const { return R * p_BQ + p; }
  RigidTransform inverse() const {
    const Eigen::Matrix3d Rt = R.transpose();
    return {Rt, -(Rt * p)};
  }

  /// A motion expressed in B (at Bo) re-expressed in A (at Ao).
  SpatialMotion ActOn(const SpatialMotion& m_B) const {
    const Eigen::Vector3d w = R * m_B.w;
    return {w, R * m_B.v + p.cross(w)};
  }
  /// A motion expressed in A (at Ao) re-expressed in B (at Bo).
  SpatialMotion InverseActOn(const SpatialMotion& m_A) const {
    return {R.transpose() * m_A.w, R.transpose() * (m_A.v - p.cross(m_A.w))};
  }
  /// A force expressed in B (about Bo) re-expressed in A (about Ao).
  SpatialForce ActOn(const SpatialForce& F_B) const {
    const Eigen::Vector3d f = R * F_B.f;
    return {R * F_B.n + p.cross(f), f};
  }
  /// A force expressed in A (about Ao) re-expressed in B (about Bo).
  SpatialForce InverseActOn(const SpatialForce& F_A) const {
    return {R.transpose() * (F_A.n - p.cross(F_A.f)), R.transpose() * F_A.f};
  }
};

/// Spatial inertia of a rigid body about the origin of the frame it is expressed in: mass m,
/// first moment h = m c (c: centre of mass) and rotational inertia Ibar about the origin.
struct SpatialInertia {
  double mass{0.0};
  Eigen::Vector3d h{Eigen::Vector3d::Zero()};
  Eigen::Matrix3d Ibar{Eigen::Matrix3d::Zero()};

  SpatialInertia() = default;
  SpatialInertia(double m, const Eigen::Vector3d& h_in, const Eigen::Matrix3d& Ibar_in)
      : mass(m), h(h_in), Ibar(Ibar_in) {}

  /// From mass, centre of mass c and rotational inertia I_c about the centre of mass.
  static SpatialInertia FromMassComInertia(double m, const Eigen::Vector3d& c,
                                           const Eigen::Matrix3d& I_c) {
    // Ibar = I_c + m ([c]x [c]x)^T = I_c + m (|c|^2 I - c c^T) (parallel axis theorem).
    return {m, m * c,
            I_c + m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose())};
  }
  static SpatialInertia Zero() { return {}; }

  Eigen::Vector3d com() const {
    return mass > 0.0 ? Eigen::Vector3d(h / mass) : Eigen::Vector3d::Zero();
  }
  /// Rotational inertia about the centre of mass.
  Eigen::Matrix3d InertiaAboutCom() const {
    if (mass <= 0.0) return Ibar;
    const Eigen::Vector3d c = h / mass;
    return Ibar - mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  }

  /// Momentum I * m: [Ibar w + h x v; m v - h x w].
  SpatialForce operator*(const SpatialMotion& m) const {
    return {Ibar * m.w + h.cross(m.v), mass * m.v - h.cross(m.w)};
  }
  SpatialInertia& operator+=(const SpatialInertia& o) {
    mass += o.mass;
    h += o.h;
    Ibar += o.Ibar;
    return *this;
  }
  SpatialInertia operator+(const SpatialInertia& o) const {
    SpatialInertia s = *this;
    s += o;
    return s;
  }

  /// The same inertia expressed in frame A, given X_AB (this inertia is expressed in B).
  SpatialInertia ExpressedIn(const RigidTransform& X_AB) const {
    const Eigen::Vector3d hR = X_AB.R * h;
    const Eigen::Vector3d& p = X_AB.p;
    Eigen::Matrix3d I = X_AB.R * Ibar * X_AB.R.transpose();
    // Parallel-axis shift of the origin from Bo to Ao (see docs/architecture.md).
    I -= hR * p.transpose() + p * hR.transpose() + mass * p * p.transpose();
    I.diagonal().array() += 2.0 * hR.dot(p) + mass * p.squaredNorm();
    return {mass, hR + mass * p, I};
  }

  /// The 6x6 matrix acting on [w; v].
  Eigen::Matrix<double, 6, 6> matrix() const {
    Eigen::Matrix<double, 6, 6> M;
    M.topLeftCorner<3, 3>() = Ibar;
    M.topRightCorner<3, 3>() = Skew(h);
    M.bottomLeftCorner<3, 3>() = -Skew(h);
    M.bottomRightCorner<3, 3>() = mass * Eigen::Matrix3d::Identity();
    return M;
  }
};

}  // namespace idto
