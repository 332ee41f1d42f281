#include "idto/mpc/position_filter.hpp"

#include <cmath>

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"

namespace idto::mpc {

PositionFilter::PositionFilter(const Model& model, double time_constant)
    : model_(model), time_constant_(time_constant), v_step_(Eigen::VectorXd::Zero(model.nv())) {
  CheckPositive("PositionFilter", "time_constant", time_constant);
}

void PositionFilter::Reset(const Eigen::VectorXd& q) {
  model_.CheckConfiguration("PositionFilter::Reset", "q", q);
  CheckFinite("PositionFilter::Reset", "q", q);
  q_est_ = q;
}

void PositionFilter::Update(double dt, const Eigen::VectorXd& q_hat, const Eigen::VectorXd& v_hat,
                            Eigen::VectorXd* q) {
  static constexpr const char* kWhere = "PositionFilter::Update";
  CheckPositive(kWhere, "dt", dt);
  model_.CheckConfiguration(kWhere, "q_hat", q_hat);
  model_.CheckVelocity(kWhere, "v_hat", v_hat);
  if (q_est_.size() == 0) {
    ThrowInvalidArgument(kWhere, "this", "a filter without an estimate", "Reset(q) first");
  }
  if (v_hat.allFinite()) Integrate(model_, q_est_, v_hat, dt, &q_est_);
  if (q_hat.allFinite()) {
    // The correction: a fraction alpha of the tangent difference, applied on the manifold.
    Difference(model_, q_hat, q_est_, &v_step_);
    Integrate(model_, q_est_, v_step_, 1.0 - std::exp(-dt / time_constant_), &q_est_);
  }
  *q = q_est_;
}

}  // namespace idto::mpc
