#pragma once

/// @file
/// Definitions of the Scalar-templated RNEA and CRBA (include to instantiate them with a scalar
/// other than double).

#include <vector>

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/algorithms/joint_kinematics.hpp"

namespace idto {

namespace internal {

/// Adds -F_ext to the body-coordinate forces of the moving bodies, with the world poses in
/// data->X_WB_ (moments shifted from each body origin to its moving body's origin).
template <typename Scalar>
void SubtractExternalForces(const Model& model, const BodyForcesTpl<Scalar>& F_ext,
                            DataTpl<Scalar>* data) {
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const BodyIndex mb = model.mobilized_body(b);
    if (mb == kWorldBody) continue;
    const Vector3<Scalar> n_W = F_ext.col(b).template head<3>();
    const Vector3<Scalar> f_W = F_ext.col(b).template tail<3>();
    if ((n_W.array() == 0.0).all() && (f_W.array() == 0.0).all()) continue;
    const RigidTransformTpl<Scalar>& X_WM = data->X_WB_[mb];
    // Shift the moment from Bo to Mo, then express in M.
    const Vector3<Scalar> p_MoBo_W = X_WM.R * CastTo<Scalar>(model.X_MB(b).p);  // 0 if b moves
    const Vector3<Scalar> n_Mo_W = n_W + p_MoBo_W.cross(f_W);
    data->force_[mb].n -= X_WM.R.transpose() * n_Mo_W;
    data->force_[mb].f -= X_WM.R.transpose() * f_W;
  }
}

/// Recursive Newton-Euler in body coordinates. With a == nullptr the accelerations are zero
/// (bias term). With F_ext != nullptr, world poses are accumulated to bring the external forces
/// into body coordinates. With kinematics_done, the joint poses, body velocities and world poses
/// of a preceding ForwardKinematics(q, v) are reused (q is not read).
template <typename Scalar>
void Rnea(const Model& model, const Scalar* q, const Scalar* v, const Scalar* a,
          const BodyForcesTpl<Scalar>* F_ext, DataTpl<Scalar>* data, bool kinematics_done = false) {
  const std::vector<BodyIndex>& moving = model.moving_bodies();
  const SpatialMotionTpl<Scalar> a_world(Vector3<Scalar>::Zero(), -CastTo<Scalar>(model.gravity()));
  const bool with_world = F_ext != nullptr && !kinematics_done;
  data->X_WB_[0] = RigidTransformTpl<Scalar>::Identity();
  for (BodyIndex b : moving) {
    const BodyIndex p = model.moving_parent(b);
    const int iv = model.velocity_start(b);
    RigidTransformTpl<Scalar>& X_pi = data->X_pi_[b];
    Matrix3<Scalar>& R_JB = data->R_JB_[b];
    if (!kinematics_done) CalcJointPose(model, b, q + model.position_start(b), &X_pi, &R_JB);
    const SpatialMotionTpl<Scalar> vJ = JointMotion(model, b, R_JB, v + iv);
    SpatialMotionTpl<Scalar>& vi = data->vel_[b];
    SpatialMotionTpl<Scalar>& ai = data->acc_[b];
    if (p == kWorldBody) {
      if (!kinematics_done) vi = vJ;
      ai = X_pi.InverseActOn(a_world);
    } else {
      if (!kinematics_done) vi = X_pi.InverseActOn(data->vel_[p]) + vJ;
      ai = X_pi.InverseActOn(data->acc_[p]) + Cross(vi, vJ);
    }
    if (a != nullptr) ai += JointMotion(model, b, R_JB, a + iv);
    if (JointHasBiasAcceleration(model.joint_type(b))) ai += JointBiasAcceleration(vJ);
    const auto& I = CastTo<Scalar>(model.merged_inertia(b));
    data->force_[b] = I * ai + CrossForce(vi, I * vi);
    if (with_world) data->X_WB_[b] = data->X_WB_[p] * X_pi;
  }
  if (F_ext != nullptr) SubtractExternalForces(model, *F_ext, data);
  Scalar* tau = data->tau.data();
  for (auto it = moving.rbegin(); it != moving.rend(); ++it) {
    const BodyIndex b = *it;
    ProjectForce(model, b, data->R_JB_[b], data->force_[b], tau + model.velocity_start(b));
    const BodyIndex p = model.moving_parent(b);
    if (p != kWorldBody) data->force_[p] += data->X_pi_[b].ActOn(data->force_[b]);
  }
  const Eigen::VectorXd& d = model.damping();
  for (int i = 0; i < model.nv(); ++i) tau[i] += d[i] * v[i];
}

/// CRBA: writes the entries of data->M on the tree's branches (the caller zeroes M first).
template <typename Scalar>
void Crba(const Model& model, const Scalar* q, DataTpl<Scalar>* data) {
  const std::vector<BodyIndex>& moving = model.moving_bodies();
  for (BodyIndex b : moving) {
    CalcJointPose(model, b, q + model.position_start(b), &data->X_pi_[b], &data->R_JB_[b]);
    data->composite_[b] = CastTo<Scalar>(model.merged_inertia(b));
  }
  for (auto it = moving.rbegin(); it != moving.rend(); ++it) {
    const BodyIndex b = *it;
    const BodyIndex p = model.moving_parent(b);
    if (p != kWorldBody) data->composite_[p] += data->composite_[b].ExpressedIn(data->X_pi_[b]);
  }
  MatrixX<Scalar>& M = data->M;
  Matrix6<Scalar>& F = data->F_;
  for (BodyIndex b : moving) {
    const int nb = model.joint_nv(b);
    const int ib = model.velocity_start(b);
    const SpatialInertiaTpl<Scalar>& Ic = data->composite_[b];
    SpatialForceTpl<Scalar> Fk[6];
    for (int k = 0; k < nb; ++k) {
      Fk[k] = Ic * JointMotionColumn(model, b, data->R_JB_[b], k);
      ProjectForce(model, b, data->R_JB_[b], Fk[k], F.col(k).data());
      // Fill the lower triangle of the joint's block and mirror it: M stays exactly symmetric.
      for (int r = k; r < nb; ++r) {
        M(ib + r, ib + k) = F(r, k);
        M(ib + k, ib + r) = F(r, k);
      }
    }
    BodyIndex j = b;
    while (model.moving_parent(j) != kWorldBody) {
      const RigidTransformTpl<Scalar>& X = data->X_pi_[j];
      for (int k = 0; k < nb; ++k) Fk[k] = X.ActOn(Fk[k]);
      j = model.moving_parent(j);
      const int nj = model.joint_nv(j);
      const int ij = model.velocity_start(j);
      for (int k = 0; k < nb; ++k) {
        ProjectForce(model, j, data->R_JB_[j], Fk[k], F.col(k).data());
        for (int r = 0; r < nj; ++r) {
          M(ij + r, ib + k) = F(r, k);
          M(ib + k, ij + r) = F(r, k);
        }
      }
    }
  }
}

template <typename Scalar>
void CheckBodyForces(const Model& model, const char* where, const BodyForcesTpl<Scalar>* F_ext) {
  if (F_ext != nullptr && F_ext->cols() != model.num_bodies()) {
    CheckSize(where, "F_ext.cols()", F_ext->cols(), model.num_bodies(), "model.num_bodies()");
  }
}

}  // namespace internal

template <typename Scalar>
const VectorX<Scalar>& InverseDynamics(const Model& model, const ConstVectorRef<Scalar>& q,
                                       const ConstVectorRef<Scalar>& v,
                                       const ConstVectorRef<Scalar>& a,
                                       const NonDeduced<BodyForcesTpl<Scalar>>* F_ext,
                                       DataTpl<Scalar>* data) {
  internal::CheckData(model, "InverseDynamics", data);
  internal::CheckNq(model, "InverseDynamics", "q", q.size());
  internal::CheckNv(model, "InverseDynamics", "v", v.size());
  internal::CheckNv(model, "InverseDynamics", "a", a.size());
  internal::CheckBodyForces(model, "InverseDynamics", F_ext);
  internal::Rnea<Scalar>(model, q.data(), v.data(), a.data(), F_ext, data);
  return data->tau;
}

template <typename Scalar>
const VectorX<Scalar>& InverseDynamicsAfterKinematics(
    const Model& model, const ConstVectorRef<Scalar>& v, const ConstVectorRef<Scalar>& a,
    const NonDeduced<BodyForcesTpl<Scalar>>* F_ext, DataTpl<Scalar>* data) {
  internal::CheckData(model, "InverseDynamicsAfterKinematics", data);
  internal::CheckNv(model, "InverseDynamicsAfterKinematics", "v", v.size());
  internal::CheckNv(model, "InverseDynamicsAfterKinematics", "a", a.size());
  if (F_ext != nullptr && F_ext->cols() != model.num_bodies()) {
    CheckSize("InverseDynamicsAfterKinematics", "F_ext->cols()", F_ext->cols(), model.num_bodies(),
              "model.num_bodies()");
  }
  internal::Rnea<Scalar>(model, nullptr, v.data(), a.data(), F_ext, data,
                         /*kinematics_done=*/true);
  return data->tau;
}

template <typename Scalar>
const VectorX<Scalar>& BiasTerm(const Model& model, const ConstVectorRef<Scalar>& q,
                                const ConstVectorRef<Scalar>& v, DataTpl<Scalar>* data) {
  internal::CheckData(model, "BiasTerm", data);
  internal::CheckNq(model, "BiasTerm", "q", q.size());
  internal::CheckNv(model, "BiasTerm", "v", v.size());
  internal::Rnea<Scalar>(model, q.data(), v.data(), nullptr, nullptr, data);
  return data->tau;
}

template <typename Scalar>
const MatrixX<Scalar>& MassMatrix(const Model& model, const ConstVectorRef<Scalar>& q,
                                  DataTpl<Scalar>* data) {
  internal::CheckData(model, "MassMatrix", data);
  internal::CheckNq(model, "MassMatrix", "q", q.size());
  // Entries between bodies on different branches are zero and never written.
  data->M.setZero();
  internal::Crba<Scalar>(model, q.data(), data);
  return data->M;
}

}  // namespace idto
