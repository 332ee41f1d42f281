#include "idto/mpc/pd_controller.hpp"

#include <string>

#include "idto/core/errors.hpp"

namespace idto::mpc {

PdController::PdController(const Model& model, const std::vector<int>& actuated,
                           const PdGains& gains)
    : actuated_(actuated), gains_(gains), nv_(model.nv()) {
  static constexpr const char* kWhere = "PdController";
  CheckSize(kWhere, "gains.Kp", gains.Kp.size(), model.nv(), "model.nv()");
  CheckSize(kWhere, "gains.Kd", gains.Kd.size(), model.nv(), "model.nv()");
  CheckNonNegative(kWhere, "gains.Kp", gains.Kp);
  CheckNonNegative(kWhere, "gains.Kd", gains.Kd);
  for (size_t k = 0; k < actuated.size(); ++k) {
    const int i = actuated[k];
    if (i < 0 || i >= model.nv()) {
      ThrowInvalidArgument(kWhere, "actuated[" + std::to_string(k) + "]", std::to_string(i),
                           "a velocity index in [0, " + std::to_string(model.nv()) + ")");
    }
    // The joint owning velocity i must be a 1-DoF joint: its position index follows.
    const JointIndex j = model.GetJointIndex(model.velocity_name(i));
    if (model.joint_nv(j) != 1) {
      ThrowInvalidArgument(kWhere, "actuated[" + std::to_string(k) + "]",
                           std::to_string(i) + " (joint \"" + model.joint_name(j) + "\", " +
                               JointTypeName(model.joint_type(j)) + ")",
                           "a DoF of a revolute, continuous or prismatic joint");
    }
    position_index_.push_back(model.position_start(j));
  }
}

void PdController::Compute(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                           const Eigen::VectorXd& q_d, const Eigen::VectorXd& v_d,
                           const Eigen::VectorXd& u_ff, Eigen::VectorXd* u) const {
  if (u->size() != nv_) u->resize(nv_);
  u->setZero();
  for (size_t k = 0; k < actuated_.size(); ++k) {
    const int i = actuated_[k];
    const int j = position_index_[k];
    (*u)(i) = u_ff(i) + gains_.Kp(i) * (q_d(j) - q(j)) + gains_.Kd(i) * (v_d(i) - v(i));
  }
}

}  // namespace idto::mpc
