#pragma once

// Per-joint kinematics shared by the algorithms (internal header, not installed).
//
// Body coordinates: the motion subspace S of a joint maps its velocity coordinates to the
// spatial velocity of the body relative to its moving parent, expressed in the body frame.

#include <Eigen/Core>

#include "idto/math/quaternion.hpp"
#include "idto/math/spatial.hpp"
#include "idto/multibody/model.hpp"

namespace idto::internal {

/// X_pi: pose of moving body b in its moving parent; R_JB: rotation of B in J (floating and
/// planar joints only). qj points at the joint's first position coordinate.
inline void CalcJointPose(const Model& model, BodyIndex b, const double* qj, RigidTransform* X_pi,
                          Eigen::Matrix3d* R_JB) {
  const RigidTransform& X_MJ = model.X_MJ(b);
  switch (model.joint_type(b)) {
    case JointType::kRevolute:
    case JointType::kContinuous: {
      const Eigen::Matrix3d R = AxisAngleRotation(model.joint_axis(b), qj[0]);
      X_pi->R.noalias() = model.X_MJ_is_translation(b) ? R : Eigen::Matrix3d(X_MJ.R * R);
      X_pi->p = X_MJ.p;
      return;
    }
    case JointType::kPrismatic:
      X_pi->R = X_MJ.R;
      X_pi->p = X_MJ.p + X_MJ.R * (qj[0] * model.joint_axis(b));
      return;
    case JointType::kFloating: {
      *R_JB = RotationFromWxyz(qj);
      const Eigen::Vector3d p_JB(qj[4], qj[5], qj[6]);
      X_pi->R.noalias() = X_MJ.R * (*R_JB);
      X_pi->p = X_MJ.p + X_MJ.R * p_JB;
      return;
    }
    case JointType::kPlanar: {
      *R_JB = AxisAngleRotation(model.joint_axis(b), qj[2]);
      const Eigen::Vector3d p_JB = qj[0] * model.planar_e1(b) + qj[1] * model.planar_e2(b);
      X_pi->R.noalias() = X_MJ.R * (*R_JB);
      X_pi->p = X_MJ.p + X_MJ.R * p_JB;
      return;
    }
    case JointType::kFixed:
      break;
  }
}

/// S * x for the joint of moving body b (x: the joint's nv entries), in body coordinates.
inline SpatialMotion JointMotion(const Model& model, BodyIndex b, const Eigen::Matrix3d& R_JB,
                                 const double* x) {
  switch (model.joint_type(b)) {
    case JointType::kRevolute:
    case JointType::kContinuous:
      return {x[0] * model.joint_axis(b), Eigen::Vector3d::Zero()};
    case JointType::kPrismatic:
      return {Eigen::Vector3d::Zero(), x[0] * model.joint_axis(b)};
    case JointType::kFloating:
      return {R_JB.transpose() * Eigen::Vector3d(x[0], x[1], x[2]),
              R_JB.transpose() * Eigen::Vector3d(x[3], x[4], x[5])};
    case JointType::kPlanar:
      return {x[2] * model.joint_axis(b),
              R_JB.transpose() * (x[0] * model.planar_e1(b) + x[1] * model.planar_e2(b))};
    case JointType::kFixed:
      break;
  }
  return {};
}

/// Column k of S for the joint of moving body b, in body coordinates.
inline SpatialMotion JointMotionColumn(const Model& model, BodyIndex b, const Eigen::Matrix3d& R_JB,
                                       int k) {
  double x[6] = {0, 0, 0, 0, 0, 0};
  x[k] = 1.0;
  return JointMotion(model, b, R_JB, x);
}

/// The velocity-product term S̊ q̇ (apparent derivative of S in body coordinates), given the
/// joint's relative velocity vJ = S q̇ in body coordinates. Zero for 1-DoF joints.
inline bool JointHasBiasAcceleration(JointType type) {
  return type == JointType::kFloating || type == JointType::kPlanar;
}
inline SpatialMotion JointBiasAcceleration(const SpatialMotion& vJ) {
  return {Eigen::Vector3d::Zero(), -vJ.w.cross(vJ.v)};
}

/// out = S^T F for the joint of moving body b (out: the joint's nv entries).
inline void ProjectForce(const Model& model, BodyIndex b, const Eigen::Matrix3d& R_JB,
                         const SpatialForce& F, double* out) {
  switch (model.joint_type(b)) {
    case JointType::kRevolute:
    case JointType::kContinuous:
      out[0] = model.joint_axis(b).dot(F.n);
      return;
    case JointType::kPrismatic:
      out[0] = model.joint_axis(b).dot(F.f);
      return;
    case JointType::kFloating: {
      const Eigen::Vector3d n = R_JB * F.n;
      const Eigen::Vector3d f = R_JB * F.f;
      out[0] = n.x();
      out[1] = n.y();
      out[2] = n.z();
      out[3] = f.x();
      out[4] = f.y();
      out[5] = f.z();
      return;
    }
    case JointType::kPlanar: {
      const Eigen::Vector3d f = R_JB * F.f;
      out[0] = model.planar_e1(b).dot(f);
      out[1] = model.planar_e2(b).dot(f);
      out[2] = model.joint_axis(b).dot(F.n);
      return;
    }
    case JointType::kFixed:
      break;
  }
}

}  // namespace idto::internal
