#pragma once

/// @file
/// Definitions of the Scalar-templated kinematics (include to instantiate them with a scalar
/// other than double).

#include "idto/math/quaternion.hpp"
#include "idto/multibody/algorithms/joint_kinematics.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"

namespace idto {

namespace internal {

/// World poses of every body; velocities too when v != nullptr.
template <typename Scalar>
void Kinematics(const Model& model, const Scalar* q, const Scalar* v, DataTpl<Scalar>* data) {
  data->X_WB_[0] = RigidTransformTpl<Scalar>::Identity();
  data->w_WB_[0].setZero();
  data->v_WBo_[0].setZero();
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const BodyIndex mb = model.mobilized_body(b);
    if (mb != b) {
      // Welded: rigidly attached to its moving body.
      const RigidTransformTpl<Scalar>& X_WM = data->X_WB_[mb];
      data->X_WB_[b] = X_WM * CastTo<Scalar>(model.X_MB(b));
      if (v != nullptr) {
        data->w_WB_[b] = data->w_WB_[mb];
        data->v_WBo_[b] = data->v_WBo_[mb] + data->w_WB_[mb].cross(data->X_WB_[b].p - X_WM.p);
      }
      continue;
    }
    RigidTransformTpl<Scalar>& X_pi = data->X_pi_[b];
    CalcJointPose(model, b, q + model.position_start(b), &X_pi, &data->R_JB_[b]);
    const BodyIndex p = model.moving_parent(b);
    const RigidTransformTpl<Scalar>& X_Wp = data->X_WB_[p];
    RigidTransformTpl<Scalar>& X_Wi = data->X_WB_[b];
    X_Wi = X_Wp * X_pi;
    if (v != nullptr) {
      // Body-coordinate velocity, then world-aligned angular velocity and origin velocity.
      const SpatialMotionTpl<Scalar> vJ =
          JointMotion(model, b, data->R_JB_[b], v + model.velocity_start(b));
      SpatialMotionTpl<Scalar>& vi = data->vel_[b];
      if (p == kWorldBody) {
        vi = vJ;
      } else {
        vi = X_pi.InverseActOn(data->vel_[p]) + vJ;
      }
      data->w_WB_[b] = X_Wi.R * vi.w;
      data->v_WBo_[b] = X_Wi.R * vi.v;
    }
  }
}

}  // namespace internal

template <typename Scalar>
void ForwardKinematics(const Model& model, const ConstVectorRef<Scalar>& q, DataTpl<Scalar>* data) {
  internal::CheckData(model, "ForwardKinematics", data);
  internal::CheckNq(model, "ForwardKinematics", "q", q.size());
  internal::Kinematics<Scalar>(model, q.data(), nullptr, data);
}

template <typename Scalar>
void ForwardKinematics(const Model& model, const ConstVectorRef<Scalar>& q,
                       const ConstVectorRef<Scalar>& v, DataTpl<Scalar>* data) {
  internal::CheckData(model, "ForwardKinematics", data);
  internal::CheckNq(model, "ForwardKinematics", "q", q.size());
  internal::CheckNv(model, "ForwardKinematics", "v", v.size());
  internal::Kinematics<Scalar>(model, q.data(), v.data(), data);
}

template <typename Scalar>
void CalcNMatrix(const Model& model, const ConstVectorRef<Scalar>& q, MatrixX<Scalar>* N) {
  internal::CheckNq(model, "CalcNMatrix", "q", q.size());
  N->setZero(model.nq(), model.nv());
  for (BodyIndex b : model.moving_bodies()) {
    const int iq = model.position_start(b), iv = model.velocity_start(b);
    if (model.joint_type(b) == JointType::kFloating) {
      N->template block<4, 3>(iq, iv) = QuaternionRateMatrix(q.data() + iq);
      N->template block<3, 3>(iq + 4, iv + 3).setIdentity();
    } else {
      for (int k = 0; k < model.joint_nv(b); ++k) (*N)(iq + k, iv + k) = Scalar(1);
    }
  }
}

template <typename Scalar>
void CalcNplusMatrix(const Model& model, const ConstVectorRef<Scalar>& q, MatrixX<Scalar>* Nplus) {
  internal::CheckNq(model, "CalcNplusMatrix", "q", q.size());
  Nplus->setZero(model.nv(), model.nq());
  for (BodyIndex b : model.moving_bodies()) {
    const int iq = model.position_start(b), iv = model.velocity_start(b);
    if (model.joint_type(b) == JointType::kFloating) {
      // E^T E = |q|^2 / 4 I, so the pseudo-inverse of E is (4 / |q|^2) E^T.
      const Eigen::Matrix<Scalar, 4, 3> E = QuaternionRateMatrix(q.data() + iq);
      const Scalar n2 = q.template segment<4>(iq).squaredNorm();
      const Scalar scale = n2 > 0.0 ? Scalar(4.0 / n2) : Scalar(0);
      Nplus->template block<3, 4>(iv, iq) = scale * E.transpose();
      Nplus->template block<3, 3>(iv + 3, iq + 4).setIdentity();
    } else {
      for (int k = 0; k < model.joint_nv(b); ++k) (*Nplus)(iv + k, iq + k) = Scalar(1);
    }
  }
}

}  // namespace idto
