#include "idto/multibody/algorithms/jacobians.hpp"

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/joint_kinematics.hpp"

namespace idto {

namespace {

void CheckBody(const Model& model, const char* where, BodyIndex b) {
  if (b < 0 || b >= model.num_bodies()) {
    ThrowInvalidArgument(where, "b", std::to_string(b),
                         "a body index in [0, " + std::to_string(model.num_bodies()) + ")");
  }
}

// Calls fn(column, w_W, v_WMo, p_WMo) for every DoF that moves body b: the world-aligned
// angular velocity and origin velocity of the moving body M carrying that DoF, per unit rate.
template <typename Fn>
void ForEachSupportingDof(const Model& model, const Data& data, BodyIndex b, const Fn& fn) {
  for (BodyIndex m = model.mobilized_body(b); m != kWorldBody; m = model.moving_parent(m)) {
    const Eigen::Matrix3d& R_WM = data.X_WB_[m].R;
    const int iv = model.velocity_start(m);
    for (int k = 0; k < model.joint_nv(m); ++k) {
      const SpatialMotion s = internal::JointMotionColumn(model, m, data.R_JB_[m], k);
      fn(iv + k, Eigen::Vector3d(R_WM * s.w), Eigen::Vector3d(R_WM * s.v), data.X_WB_[m].p);
    }
  }
}

}  // namespace

void CalcPointJacobian(const Model& model, const Data& data, BodyIndex b,
                       const Eigen::Vector3d& p_BC, Eigen::Matrix3Xd* J) {
  internal::CheckData(model, "CalcPointJacobian", &data);
  CheckBody(model, "CalcPointJacobian", b);
  J->setZero(3, model.nv());
  const Eigen::Vector3d p_WC = data.X_WB_[b] * p_BC;
  ForEachSupportingDof(
      model, data, b,
      [&](int col, const Eigen::Vector3d& w, const Eigen::Vector3d& v,
          const Eigen::Vector3d& p_WMo) { J->col(col) = v + w.cross(p_WC - p_WMo); });
}

void CalcFrameJacobian(const Model& model, const Data& data, BodyIndex b,
                       const Eigen::Isometry3d& X_BF, Eigen::Matrix<double, 6, Eigen::Dynamic>* J) {
  internal::CheckData(model, "CalcFrameJacobian", &data);
  CheckBody(model, "CalcFrameJacobian", b);
  J->setZero(6, model.nv());
  const Eigen::Vector3d p_WF = data.X_WB_[b] * Eigen::Vector3d(X_BF.translation());
  ForEachSupportingDof(model, data, b,
                       [&](int col, const Eigen::Vector3d& w, const Eigen::Vector3d& v,
                           const Eigen::Vector3d& p_WMo) {
                         J->col(col).head<3>() = w;
                         J->col(col).tail<3>() = v + w.cross(p_WF - p_WMo);
                       });
}

}  // namespace idto
