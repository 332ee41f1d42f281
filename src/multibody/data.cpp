#include "idto/multibody/data.hpp"

namespace idto {

Data::Data(const Model& model)
    : tau(Eigen::VectorXd::Zero(model.nv())),
      M(Eigen::MatrixXd::Zero(model.nv(), model.nv())),
      a(Eigen::VectorXd::Zero(model.nv())),
      X_WB_(model.num_bodies(), RigidTransform::Identity()),
      w_WB_(model.num_bodies(), Eigen::Vector3d::Zero()),
      v_WBo_(model.num_bodies(), Eigen::Vector3d::Zero()),
      X_pi_(model.num_bodies(), RigidTransform::Identity()),
      R_JB_(model.num_bodies(), Eigen::Matrix3d::Identity()),
      vel_(model.num_bodies()),
      acc_(model.num_bodies()),
      force_(model.num_bodies()),
      composite_(model.num_bodies()),
      F_(Eigen::Matrix<double, 6, 6>::Zero()),
      llt_(model.nv()),
      scratch_v_(Eigen::VectorXd::Zero(model.nv())) {
  // Eigen's LLT(size) leaves its status uninitialized until compute(); copying or moving a Data
  // would read it. Factor the identity once so every member is defined.
  llt_.compute(Eigen::MatrixXd::Identity(model.nv(), model.nv()));
}

Eigen::Isometry3d Data::X_WB(BodyIndex b) const {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = X_WB_[b].R;
  X.translation() = X_WB_[b].p;
  return X;
}

Eigen::Matrix<double, 6, 1> Data::V_WB(BodyIndex b) const {
  Eigen::Matrix<double, 6, 1> V;
  V << w_WB_[b], v_WBo_[b];
  return V;
}

Eigen::Isometry3d Data::X_WF(const Model& model, FrameIndex f) const {
  return X_WB(model.frame_body(f)) * model.X_BF(f);
}

}  // namespace idto
