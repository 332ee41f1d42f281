#include "idto/multibody/algorithms/discrete_velocity.hpp"

#include "idto/math/quaternion.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"

namespace idto {

void CalcDiscreteVelocity(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                          const Eigen::Ref<const Eigen::VectorXd>& q_prev, double dt,
                          Eigen::VectorXd* v) {
  if (v->size() != model.nv()) v->resize(model.nv());
  for (BodyIndex b : model.moving_bodies()) {
    const int iq = model.position_start(b), iv = model.velocity_start(b);
    if (model.joint_type(b) == JointType::kFloating) {
      // N+ of a quaternion is 4 / |Q|^2 G(Q)^T (see CalcNplusMatrix); the rest is linear.
      const Eigen::Matrix<double, 4, 3> G = QuaternionRateMatrix(q.data() + iq);
      const double n2 = q.segment<4>(iq).squaredNorm();
      v->segment<3>(iv) =
          (4.0 / (n2 * dt)) * G.transpose() * (q.segment<4>(iq) - q_prev.segment<4>(iq));
      v->segment<3>(iv + 3) = (q.segment<3>(iq + 4) - q_prev.segment<3>(iq + 4)) / dt;
    } else {
      for (int k = 0; k < model.joint_nq(b); ++k) {
        (*v)(iv + k) = (q(iq + k) - q_prev(iq + k)) / dt;
      }
    }
  }
}

void CalcDiscreteVelocityPartials(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                                  const Eigen::Ref<const Eigen::VectorXd>& q_prev, double dt,
                                  const Eigen::Ref<const Eigen::VectorXd>& v,
                                  Eigen::MatrixXd* Nplus, Eigen::MatrixXd* dv_dq,
                                  Eigen::MatrixXd* dv_dq_prev) {
  CalcNplusMatrix(model, q, Nplus);
  *dv_dq = *Nplus / dt;
  *dv_dq_prev = -*dv_dq;
  for (JointIndex j : model.floating_joints()) {
    const int iq = model.position_start(j), iv = model.velocity_start(j);
    const Eigen::Vector4d Q = q.segment<4>(iq);
    const double n2 = Q.squaredNorm();
    // w = 4/|Q|^2 G(Q_prev)^T Q / dt (G(Q)^T Q = 0), so dw/dQ = 4/|Q|^2 G(Q_prev)^T / dt
    // - 2/|Q|^2 w Q^T.
    const Eigen::Matrix<double, 4, 3> G_prev = QuaternionRateMatrix(q_prev.data() + iq);
    const Eigen::Vector3d w = v.segment<3>(iv);
    dv_dq->block<3, 4>(iv, iq) =
        (4.0 / (n2 * dt)) * G_prev.transpose() - (2.0 / n2) * w * Q.transpose();
  }
}

}  // namespace idto
