#include <limits>

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/dynamics-inl.hpp"

namespace idto {

template const VectorX<double>& InverseDynamics<double>(const Model&, const ConstVectorRef<double>&,
                                                        const ConstVectorRef<double>&,
                                                        const ConstVectorRef<double>&,
                                                        const BodyForcesTpl<double>*,
                                                        DataTpl<double>*);
template const VectorX<double>& InverseDynamicsAfterKinematics<double>(
    const Model&, const ConstVectorRef<double>&, const ConstVectorRef<double>&,
    const BodyForcesTpl<double>*, DataTpl<double>*);
template const VectorX<double>& BiasTerm<double>(const Model&, const ConstVectorRef<double>&,
                                                 const ConstVectorRef<double>&, DataTpl<double>*);
template const MatrixX<double>& MassMatrix<double>(const Model&, const ConstVectorRef<double>&,
                                                   DataTpl<double>*);

const Eigen::VectorXd& InverseDynamics(const Model& model,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       const Eigen::Ref<const Eigen::VectorXd>& v,
                                       const Eigen::Ref<const Eigen::VectorXd>& a, Data* data) {
  return InverseDynamics<double>(model, q, v, a, nullptr, data);
}

const Eigen::VectorXd& InverseDynamics(const Model& model,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       const Eigen::Ref<const Eigen::VectorXd>& v,
                                       const Eigen::Ref<const Eigen::VectorXd>& a,
                                       const BodyForces& F_ext, Data* data) {
  return InverseDynamics<double>(model, q, v, a, &F_ext, data);
}

const Eigen::VectorXd& InverseDynamicsAfterKinematics(const Model& model,
                                                      const Eigen::Ref<const Eigen::VectorXd>& v,
                                                      const Eigen::Ref<const Eigen::VectorXd>& a,
                                                      const BodyForces* F_ext, Data* data) {
  return InverseDynamicsAfterKinematics<double>(model, v, a, F_ext, data);
}

const Eigen::VectorXd& BiasTerm(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                                const Eigen::Ref<const Eigen::VectorXd>& v, Data* data) {
  return BiasTerm<double>(model, q, v, data);
}

const Eigen::MatrixXd& MassMatrix(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                                  Data* data) {
  return MassMatrix<double>(model, q, data);
}

const Eigen::VectorXd& ForwardDynamics(const Model& model,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       const Eigen::Ref<const Eigen::VectorXd>& v,
                                       const Eigen::Ref<const Eigen::VectorXd>& tau, Data* data) {
  internal::CheckData(model, "ForwardDynamics", data);
  model.CheckConfiguration("ForwardDynamics", "q", q);
  model.CheckVelocity("ForwardDynamics", "v", v);
  model.CheckVelocity("ForwardDynamics", "tau", tau);
  internal::Rnea<double>(model, q.data(), v.data(), nullptr, nullptr, data);
  data->a = tau - data->tau;
  data->M.setZero();
  internal::Crba<double>(model, q.data(), data);
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
  internal::CheckData(model, "GeneralizedForceFromBodyForces", data);
  if (tau == nullptr) {
    ThrowInvalidArgument("GeneralizedForceFromBodyForces", "tau", "null", "an output vector");
  }
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
