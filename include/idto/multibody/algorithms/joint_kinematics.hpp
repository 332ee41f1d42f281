#pragma once

/// @file
/// Per-joint kinematics shared by the templated algorithms (internal: namespace
/// idto::internal, not a stable API).
///
/// Body coordinates: the motion subspace S of a joint maps its velocity coordinates to the
/// spatial velocity of the body relative to its moving parent, expressed in the body frame.

#include <Eigen/Core>

#include "idto/core/errors.hpp"
#include "idto/math/quaternion.hpp"
#include "idto/math/scalar.hpp"
#include "idto/math/spatial.hpp"
#include "idto/multibody/model.hpp"

namespace idto::internal {

/// Throws InvalidArgument naming `where` and `argument` unless size == model.nq() (any scalar).
inline void CheckNq(const Model& model, const char* where, const char* argument,
                    Eigen::Index size) {
  if (size != model.nq()) CheckSize(where, argument, size, model.nq(), "model.nq()");
}

/// Throws InvalidArgument naming `where` and `argument` unless size == model.nv() (any scalar).
inline void CheckNv(const Model& model, const char* where, const char* argument,
                    Eigen::Index size) {
  if (size != model.nv()) CheckSize(where, argument, size, model.nv(), "model.nv()");
}

/// X_pi: pose of moving body b in its moving parent; R_JB: rotation of B in J (floating and
/// planar joints only). qj points at the joint's first position coordinate.
template <typename Scalar>
inline void CalcJointPose(const Model& model, BodyIndex b, const Scalar* qj,
                          RigidTransformTpl<Scalar>* X_pi, Matrix3<Scalar>* R_JB) {
  const auto& X_MJ = CastTo<Scalar>(model.X_MJ(b));
  switch (model.joint_type(b)) {
    case JointType::kRevolute:
    case JointType::kContinuous: {
      const Matrix3<Scalar> R = AxisAngleRotation(model.joint_axis(b), qj[0]);
      if (model.X_MJ_is_translation(b)) {
        X_pi->R = R;
      } else {
        X_pi->R.noalias() = X_MJ.R * R;
      }
      X_pi->p = X_MJ.p;
      return;
    }
    case JointType::kPrismatic:
      X_pi->R = X_MJ.R;
      X_pi->p = X_MJ.p + X_MJ.R * (qj[0] * CastTo<Scalar>(model.joint_axis(b)));
      return;
    case JointType::kFloating: {
      *R_JB = RotationFromWxyz(qj);
      const Vector3<Scalar> p_JB(qj[4], qj[5], qj[6]);
      X_pi->R.noalias() = X_MJ.R * (*R_JB);
      X_pi->p = X_MJ.p + X_MJ.R * p_JB;
      return;
    }
    case JointType::kPlanar: {
      *R_JB = AxisAngleRotation(model.joint_axis(b), qj[2]);
      const Vector3<Scalar> p_JB =
          qj[0] * CastTo<Scalar>(model.planar_e1(b)) + qj[1] * CastTo<Scalar>(model.planar_e2(b));
      X_pi->R.noalias() = X_MJ.R * (*R_JB);
      X_pi->p = X_MJ.p + X_MJ.R * p_JB;
      return;
    }
    case JointType::kFixed:
      break;
  }
}

/// S * x for the joint of moving body b (x: the joint's nv entries), in body coordinates.
template <typename Scalar>
inline SpatialMotionTpl<Scalar> JointMotion(const Model& model, BodyIndex b,
                                            const Matrix3<Scalar>& R_JB, const Scalar* x) {
  switch (model.joint_type(b)) {
    case JointType::kRevolute:
    case JointType::kContinuous:
      return {x[0] * CastTo<Scalar>(model.joint_axis(b)), Vector3<Scalar>::Zero()};
    case JointType::kPrismatic:
      return {Vector3<Scalar>::Zero(), x[0] * CastTo<Scalar>(model.joint_axis(b))};
    case JointType::kFloating:
      return {R_JB.transpose() * Vector3<Scalar>(x[0], x[1], x[2]),
              R_JB.transpose() * Vector3<Scalar>(x[3], x[4], x[5])};
    case JointType::kPlanar:
      return {x[2] * CastTo<Scalar>(model.joint_axis(b)),
              R_JB.transpose() * (x[0] * CastTo<Scalar>(model.planar_e1(b)) +
                                  x[1] * CastTo<Scalar>(model.planar_e2(b)))};
    case JointType::kFixed:
      break;
  }
  return {};
}

/// Column k of S for the joint of moving body b, in body coordinates.
template <typename Scalar>
inline SpatialMotionTpl<Scalar> JointMotionColumn(const Model& model, BodyIndex b,
                                                  const Matrix3<Scalar>& R_JB, int k) {
  Scalar x[6] = {Scalar(0), Scalar(0), Scalar(0), Scalar(0), Scalar(0), Scalar(0)};
  x[k] = Scalar(1);
  return JointMotion(model, b, R_JB, x);
}

/// The velocity-product term S̊ q̇ (apparent derivative of S in body coordinates), given the
/// joint's relative velocity vJ = S q̇ in body coordinates. Zero for 1-DoF joints.
inline bool JointHasBiasAcceleration(JointType type) {
  return type == JointType::kFloating || type == JointType::kPlanar;
}
template <typename Scalar>
inline SpatialMotionTpl<Scalar> JointBiasAcceleration(const SpatialMotionTpl<Scalar>& vJ) {
  return {Vector3<Scalar>::Zero(), -vJ.w.cross(vJ.v)};
}

/// out = S^T F for the joint of moving body b (out: the joint's nv entries).
template <typename Scalar>
inline void ProjectForce(const Model& model, BodyIndex b, const Matrix3<Scalar>& R_JB,
                         const SpatialForceTpl<Scalar>& F, Scalar* out) {
  switch (model.joint_type(b)) {
    case JointType::kRevolute:
    case JointType::kContinuous:
      out[0] = CastTo<Scalar>(model.joint_axis(b)).dot(F.n);
      return;
    case JointType::kPrismatic:
      out[0] = CastTo<Scalar>(model.joint_axis(b)).dot(F.f);
      return;
    case JointType::kFloating: {
      const Vector3<Scalar> n = R_JB * F.n;
      const Vector3<Scalar> f = R_JB * F.f;
      out[0] = n.x();
      out[1] = n.y();
      out[2] = n.z();
      out[3] = f.x();
      out[4] = f.y();
      out[5] = f.z();
      return;
    }
    case JointType::kPlanar: {
      const Vector3<Scalar> f = R_JB * F.f;
      out[0] = CastTo<Scalar>(model.planar_e1(b)).dot(f);
      out[1] = CastTo<Scalar>(model.planar_e2(b)).dot(f);
      out[2] = CastTo<Scalar>(model.joint_axis(b)).dot(F.n);
      return;
    }
    case JointType::kFixed:
      break;
  }
}

}  // namespace idto::internal
