#pragma once

/// @file
/// Quaternion and rotation helpers. Quaternions in q are stored [qw, qx, qy, qz] (design.md §3).
/// The helpers the kernels use are templates on the scalar type; exp/log stay double.

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/math/scalar.hpp"

namespace idto {

/// Rotation by `angle` about the unit vector `axis` (Rodrigues' formula).
template <typename Scalar>
inline Matrix3<Scalar> AxisAngleRotation(const NonDeduced<Eigen::Vector3d>& axis,
                                         const Scalar& angle) {
  using std::cos;
  using std::sin;
  const Scalar s = sin(angle);
  const Scalar c = cos(angle);
  const Scalar t = 1.0 - c;
  const double x = axis.x(), y = axis.y(), z = axis.z();
  Matrix3<Scalar> R;
  R << t * (x * x) + c, t * (x * y) - s * z, t * (x * z) + s * y,  //
      t * (x * y) + s * z, t * (y * y) + c, t * (y * z) - s * x,   //
      t * (x * z) - s * y, t * (y * z) + s * x, t * (z * z) + c;
  return R;
}

/// The quaternion stored at q[0..3] as [qw, qx, qy, qz] (not normalized).
inline Eigen::Quaterniond QuaternionFromWxyz(const double* q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}

/// Writes quaternion `Q` to q[0..3] as [qw, qx, qy, qz].
inline void QuaternionToWxyz(const Eigen::Quaterniond& Q, double* q) {
  q[0] = Q.w();
  q[1] = Q.x();
  q[2] = Q.y();
  q[3] = Q.z();
}

/// Rotation matrix of the normalized quaternion [qw, qx, qy, qz] at q (identity for a zero one).
/// Depends on q only through q / |q|.
template <typename Scalar>
inline Matrix3<Scalar> RotationFromWxyz(const Scalar* q) {
  const Scalar n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  if (!(n2 > 0.0)) return Matrix3<Scalar>::Identity();
  const Scalar s = 2.0 / n2;  // normalizes on the fly
  const Scalar &w = q[0], &x = q[1], &y = q[2], &z = q[3];
  Matrix3<Scalar> R;
  R << 1.0 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y),  //
      s * (x * y + w * z), 1.0 - s * (x * x + z * z), s * (y * z - w * x),   //
      s * (x * z - w * y), s * (y * z + w * x), 1.0 - s * (x * x + y * y);
  return R;
}

/// The 4 x 3 map G(q) with qdot = G(q) w for a quaternion q = [w, x, y, z] whose angular
/// velocity w is expressed in the parent (fixed) frame: qdot = 1/2 [0; w] (x) q. G(q)^T q = 0 and
/// G(q)^T G(q) = |q|^2 / 4 I.
template <typename Scalar>
inline Eigen::Matrix<Scalar, 4, 3> QuaternionRateMatrix(const Scalar* q) {
  const Scalar &w = q[0], &x = q[1], &y = q[2], &z = q[3];
  Eigen::Matrix<Scalar, 4, 3> G;
  G << -x, -y, -z,  //
      w, z, -y,     //
      -z, w, x,     //
      y, -x, w;
  return 0.5 * G;
}

/// exp of a rotation vector: the unit quaternion rotating by |theta| about theta/|theta|.
/// Accurate for small angles (Taylor series below 1e-4 rad).
inline Eigen::Quaterniond QuaternionExp(const Eigen::Vector3d& theta) {
  const double angle = theta.norm();
  const double half = 0.5 * angle;
  double c, k;  // k = sin(half) / angle
  if (angle < 1e-4) {
    const double a2 = angle * angle;
    c = 1.0 - a2 / 8.0;
    k = 0.5 - a2 / 48.0;
  } else {
    c = std::cos(half);
    k = std::sin(half) / angle;
  }
  return Eigen::Quaterniond(c, k * theta.x(), k * theta.y(), k * theta.z());
}

/// log of a unit quaternion: the rotation vector of the shortest rotation it represents
/// (Q and -Q give the same result; |result| <= pi).
inline Eigen::Vector3d QuaternionLog(const Eigen::Quaterniond& Q_in) {
  Eigen::Quaterniond Q = Q_in;
  if (Q.w() < 0.0) Q.coeffs() = -Q.coeffs();
  const Eigen::Vector3d u = Q.vec();
  const double s = u.norm();
  if (s < 1e-8) {
    // angle = 2 atan2(s, w) ~ 2 s / w (1 - s^2 / (3 w^2)).
    const double w = Q.w();
    return (2.0 / w) * (1.0 - s * s / (3.0 * w * w)) * u;
  }
  const double angle = 2.0 * std::atan2(s, Q.w());
  return (angle / s) * u;
}

}  // namespace idto
