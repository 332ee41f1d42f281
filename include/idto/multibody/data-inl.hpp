#pragma once

/// @file
/// Definitions of DataTpl (include to instantiate DataTpl with a scalar other than double).

#include <type_traits>

#include "idto/multibody/data.hpp"

namespace idto {

template <typename Scalar>
DataTpl<Scalar>::DataTpl(const Model& model)
    : tau(VectorX<Scalar>::Zero(model.nv())),
      M(MatrixX<Scalar>::Zero(model.nv(), model.nv())),
      a(VectorX<Scalar>::Zero(model.nv())),
      dtau_dq(MatrixX<Scalar>::Zero(model.nv(), model.nq())),
      dtau_dq_tangent(MatrixX<Scalar>::Zero(model.nv(), model.nv())),
      dtau_dv(MatrixX<Scalar>::Zero(model.nv(), model.nv())),
      X_WB_(model.num_bodies(), RigidTransformTpl<Scalar>::Identity()),
      w_WB_(model.num_bodies(), Vector3<Scalar>::Zero()),
      v_WBo_(model.num_bodies(), Vector3<Scalar>::Zero()),
      X_pi_(model.num_bodies(), RigidTransformTpl<Scalar>::Identity()),
      R_JB_(model.num_bodies(), Matrix3<Scalar>::Identity()),
      vel_(model.num_bodies()),
      acc_(model.num_bodies()),
      force_(model.num_bodies()),
      composite_(model.num_bodies()),
      F_(Matrix6<Scalar>::Zero()),
      llt_(model.nv()),
      scratch_v_(VectorX<Scalar>::Zero(model.nv())),
      deriv_body_(model.num_bodies()),
      S_(Eigen::Matrix<Scalar, 6, Eigen::Dynamic>::Zero(6, model.nv())),
      dV_dq_(Eigen::Matrix<Scalar, 6, Eigen::Dynamic>::Zero(6, model.nv())),
      dA_dq_(Eigen::Matrix<Scalar, 6, Eigen::Dynamic>::Zero(6, model.nv())),
      dA_dv_(Eigen::Matrix<Scalar, 6, Eigen::Dynamic>::Zero(6, model.nv())) {
  model_tag_ = model.tag();
  // Eigen's LLT(size) leaves its status uninitialized until compute(); copying or moving a Data
  // would read it. Factor the identity once so every member is defined.
  llt_.compute(MatrixX<Scalar>::Identity(model.nv(), model.nv()));
}

template <typename Scalar>
typename DataTpl<Scalar>::Isometry3 DataTpl<Scalar>::X_WB(BodyIndex b) const {
  Isometry3 X = Isometry3::Identity();
  X.linear() = X_WB_[b].R;
  X.translation() = X_WB_[b].p;
  return X;
}

template <typename Scalar>
Vector6<Scalar> DataTpl<Scalar>::V_WB(BodyIndex b) const {
  Vector6<Scalar> V;
  V << w_WB_[b], v_WBo_[b];
  return V;
}

template <typename Scalar>
typename DataTpl<Scalar>::Isometry3 DataTpl<Scalar>::X_WF(const Model& model, FrameIndex f) const {
  return X_WB(model.frame_body(f)) * model.X_BF(f).template cast<Scalar>();
}

}  // namespace idto
