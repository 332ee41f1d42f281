#include "idto/multibody/algorithms/dynamics.hpp"

#include "../joint_kinematics.hpp"
#include "idto/core/errors.hpp"

namespace idto {

namespace {

// Recursive Newton-Euler in body coordinates. With a == nullptr the accelerations are zero
// (bias term). With F_ext != nullptr, world poses are accumulated to bring the external forces
// into body coordinates.
// With kinematics_done, the joint poses, body velocities and world poses of a preceding
// ForwardKinematics(q, v) are reused (q is not read).
void Rnea(const Model& model, const double* q, const double* v, const double* a,
          const BodyForces* F_ext, Data* data, bool kinematics_done = false) {
  const std::vector<BodyIndex>& moving = model.moving_bodies();
  const SpatialMotion a_world(Eigen::Vector3d::Zero(), -model.gravity());
  const bool with_world = F_ext != nullptr && !kinematics_done;
  data->X_WB_[0] = RigidTransform::Identity();
  for (BodyIndex b : moving) {
    const BodyIndex p = model.moving_parent(b);
    const int iv = model.velocity_start(b);
    RigidTransform& X_pi = data->X_pi_[b];
    Eigen::Matrix3d& R_JB = data->R_JB_[b];
    if (!kinematics_done) {
      internal::CalcJointPose(model, b, q + model.position_start(b), &X_pi, &R_JB);
    }
    const SpatialMotion vJ = internal::JointMotion(model, b, R_JB, v + iv);
    SpatialMotion& vi = data->vel_[b];
    SpatialMotion& ai = data->acc_[b];
    if (p == kWorldBody) {
      if (!kinematics_done) vi = vJ;
      ai = X_pi.InverseActOn(a_world);
    } else {
      if (!kinematics_done) vi = X_pi.InverseActOn(data->vel_[p]) + vJ;
      ai = X_pi.InverseActOn(data->acc_[p]) + Cross(vi, vJ);
    }
    if (a != nullptr) ai += internal::JointMotion(model, b, R_JB, a + iv);
    if (internal::JointHasBiasAcceleration(model.joint_type(b))) {
      ai += internal::JointBiasAcceleration(vJ);
    }
    const SpatialInertia& I = model.merged_inertia(b);
    data->force_[b] = I * ai + CrossForce(vi, I * vi);
    if (with_world) data->X_WB_[b] = data->X_WB_[p] * X_pi;
  }
  if (F_ext != nullptr) {
    for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
      const BodyIndex mb = model.mobilized_body(b);
      if (mb == kWorldBody) continue;
      const Eigen::Vector3d n_W = F_ext->col(b).head<3>();
      const Eigen::Vector3d f_W = F_ext->col(b).tail<3>();
      if (n_W.isZero(0.0) && f_W.isZero(0.0)) continue;
      const RigidTransform& X_WM = data->X_WB_[mb];
      // Shift the moment from Bo to Mo, then express in M.
      const Eigen::Vector3d p_MoBo_W = X_WM.R * model.X_MB(b).p;  // zero when b moves itself
      const Eigen::Vector3d n_Mo_W = n_W + p_MoBo_W.cross(f_W);
      data->force_[mb].n -= X_WM.R.transpose() * n_Mo_W;
      data->force_[mb].f -= X_WM.R.transpose() * f_W;
    }
  }
  double* tau = data->tau.data();
  for (auto it = moving.rbegin(); it != moving.rend(); ++it) {
    const BodyIndex b = *it;
    const int iv = model.velocity_start(b);
    internal::ProjectForce(model, b, data->R_JB_[b], data->force_[b], tau + iv);
    const BodyIndex p = model.moving_parent(b);
    if (p != kWorldBody) data->force_[p] += data->X_pi_[b].ActOn(data->force_[b]);
  }
  const Eigen::VectorXd& d = model.damping();
  for (int i = 0; i < model.nv(); ++i) tau[i] += d[i] * v[i];
}

}  // namespace

const Eigen::VectorXd& InverseDynamics(const Model& model,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       const Eigen::Ref<const Eigen::VectorXd>& v,
                                       const Eigen::Ref<const Eigen::VectorXd>& a, Data* data) {
  model.CheckConfiguration("InverseDynamics", "q", q);
  model.CheckVelocity("InverseDynamics", "v", v);
  model.CheckVelocity("InverseDynamics", "a", a);
  Rnea(model, q.data(), v.data(), a.data(), nullptr, data);
  return data->tau;
}

const Eigen::VectorXd& InverseDynamics(const Model& model,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       const Eigen::Ref<const Eigen::VectorXd>& v,
                                       const Eigen::Ref<const Eigen::VectorXd>& a,
                                       const BodyForces& F_ext, Data* data) {
  model.CheckConfiguration("InverseDynamics", "q", q);
  model.CheckVelocity("InverseDynamics", "v", v);
  model.CheckVelocity("InverseDynamics", "a", a);
  if (F_ext.cols() != model.num_bodies()) {
    CheckSize("InverseDynamics", "F_ext.cols()", F_ext.cols(), model.num_bodies(),
              "model.num_bodies()");
  }
  Rnea(model, q.data(), v.data(), a.data(), &F_ext, data);
  return data->tau;
}

const Eigen::VectorXd& InverseDynamicsAfterKinematics(const Model& model,
                                                      const Eigen::Ref<const Eigen::VectorXd>& v,
                                                      const Eigen::Ref<const Eigen::VectorXd>& a,
                                                      const BodyForces* F_ext, Data* data) {
  model.CheckVelocity("InverseDynamicsAfterKinematics", "v", v);
  model.CheckVelocity("InverseDynamicsAfterKinematics", "a", a);
  if (F_ext != nullptr && F_ext->cols() != model.num_bodies()) {
    CheckSize("InverseDynamicsAfterKinematics", "F_ext->cols()", F_ext->cols(), model.num_bodies(),
              "model.num_bodies()");
  }
  Rnea(model, nullptr, v.data(), a.data(), F_ext, data, /*kinematics_done=*/true);
  return data->tau;
}

const Eigen::VectorXd& BiasTerm(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                                const Eigen::Ref<const Eigen::VectorXd>& v, Data* data) {
  model.CheckConfiguration("BiasTerm", "q", q);
  model.CheckVelocity("BiasTerm", "v", v);
  Rnea(model, q.data(), v.data(), nullptr, nullptr, data);
  return data->tau;
}

namespace {

void Crba(const Model& model, const double* q, Data* data) {
  const std::vector<BodyIndex>& moving = model.moving_bodies();
  for (BodyIndex b : moving) {
    internal::CalcJointPose(model, b, q + model.position_start(b), &data->X_pi_[b],
                            &data->R_JB_[b]);
    data->composite_[b] = model.merged_inertia(b);
  }
  for (auto it = moving.rbegin(); it != moving.rend(); ++it) {
    const BodyIndex b = *it;
    const BodyIndex p = model.moving_parent(b);
    if (p != kWorldBody) data->composite_[p] += data->composite_[b].ExpressedIn(data->X_pi_[b]);
  }
  Eigen::MatrixXd& M = data->M;
  Eigen::Matrix<double, 6, 6>& F = data->F_;
  for (BodyIndex b : moving) {
    const int nb = model.joint_nv(b);
    const int ib = model.velocity_start(b);
    const SpatialInertia& Ic = data->composite_[b];
    SpatialForce Fk[6];
    for (int k = 0; k < nb; ++k) {
      Fk[k] = Ic * internal::JointMotionColumn(model, b, data->R_JB_[b], k);
      internal::ProjectForce(model, b, data->R_JB_[b], Fk[k], F.col(k).data());
      // Fill the lower triangle of the joint's block and mirror it: M stays exactly symmetric.
      for (int r = k; r < nb; ++r) {
        M(ib + r, ib + k) = F(r, k);
        M(ib + k, ib + r) = F(r, k);
      }
    }
    BodyIndex j = b;
    while (model.moving_parent(j) != kWorldBody) {
      const RigidTransform& X = data->X_pi_[j];
      for (int k = 0; k < nb; ++k) Fk[k] = X.ActOn(Fk[k]);
      j = model.moving_parent(j);
      const int nj = model.joint_nv(j);
      const int ij = model.velocity_start(j);
      for (int k = 0; k < nb; ++k) {
        internal::ProjectForce(model, j, data->R_JB_[j], Fk[k], F.col(k).data());
        for (int r = 0; r < nj; ++r) {
          M(ij + r, ib + k) = F(r, k);
          M(ib + k, ij + r) = F(r, k);
        }
      }
    }
  }
}

}  // namespace

const Eigen::MatrixXd& MassMatrix(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                                  Data* data) {
  model.CheckConfiguration("MassMatrix", "q", q);
  // Entries between bodies on different branches are zero and never written.
  data->M.setZero();
  Crba(model, q.data(), data);
  return data->M;
}

const Eigen::VectorXd& ForwardDynamics(const Model& model,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       const Eigen::Ref<const Eigen::VectorXd>& v,
                                       const Eigen::Ref<const Eigen::VectorXd>& tau, Data* data) {
  model.CheckConfiguration("ForwardDynamics", "q", q);
  model.CheckVelocity("ForwardDynamics", "v", v);
  model.CheckVelocity("ForwardDynamics", "tau", tau);
  Rnea(model, q.data(), v.data(), nullptr, nullptr, data);
  data->a = tau - data->tau;
  data->M.setZero();
  Crba(model, q.data(), data);
  data->llt_.compute(data->M);
  if (data->llt_.info() != Eigen::Success) {
    data->a.setConstant(std::numeric_limits<double>::quiet_NaN());
    return data->a;
  }
  data->llt_.solveInPlace(data->a);
  return data->a;
}

void GeneralizedForceFromBodyForces(const Model& model, const BodyForces& F, Data* data,
                                    Eigen::VectorXd* tau) {
  if (F.cols() != model.num_bodies()) {
    CheckSize("GeneralizedForceFromBodyForces", "F.cols()", F.cols(), model.num_bodies(),
              "model.num_bodies()");
  }
  if (tau->size() != model.nv()) tau->resize(model.nv());
  for (BodyIndex b : model.moving_bodies()) data->force_[b] = SpatialForce::Zero();
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const BodyIndex m = model.mobilized_body(b);
    if (m == kWorldBody) continue;
    const Eigen::Vector3d n_W = F.col(b).head<3>();
    const Eigen::Vector3d f_W = F.col(b).tail<3>();
    const RigidTransform& X_WM = data->pose(m);
    // Move the moment from Bo to Mo, then express in M.
    const Eigen::Vector3d n_Mo = n_W + (data->p_WB(b) - X_WM.p).cross(f_W);
    data->force_[m].n += X_WM.R.transpose() * n_Mo;
    data->force_[m].f += X_WM.R.transpose() * f_W;
  }
  const std::vector<BodyIndex>& moving = model.moving_bodies();
  for (auto it = moving.rbegin(); it != moving.rend(); ++it) {
    const BodyIndex b = *it;
    internal::ProjectForce(model, b, data->R_JB_[b], data->force_[b],
                           tau->data() + model.velocity_start(b));
    const BodyIndex p = model.moving_parent(b);
    if (p != kWorldBody) data->force_[p] += data->X_pi_[b].ActOn(data->force_[b]);
  }
}

}  // namespace idto
