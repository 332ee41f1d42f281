#include <cmath>

#include "idto/core/errors.hpp"
#include "idto/math/quaternion.hpp"
#include "idto/multibody/algorithms/kinematics-inl.hpp"

namespace idto {

template void ForwardKinematics<double>(const Model&, const ConstVectorRef<double>&,
                                        DataTpl<double>*);
template void ForwardKinematics<double>(const Model&, const ConstVectorRef<double>&,
                                        const ConstVectorRef<double>&, DataTpl<double>*);
template void CalcNMatrix<double>(const Model&, const ConstVectorRef<double>&, MatrixX<double>*);
template void CalcNplusMatrix<double>(const Model&, const ConstVectorRef<double>&,
                                      MatrixX<double>*);

void ForwardKinematics(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q, Data* data) {
  ForwardKinematics<double>(model, q, data);
}

void ForwardKinematics(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                       const Eigen::Ref<const Eigen::VectorXd>& v, Data* data) {
  ForwardKinematics<double>(model, q, v, data);
}

void CalcNMatrix(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                 Eigen::MatrixXd* N) {
  CalcNMatrix<double>(model, q, N);
}

void CalcNplusMatrix(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                     Eigen::MatrixXd* Nplus) {
  CalcNplusMatrix<double>(model, q, Nplus);
}

void Integrate(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
               const Eigen::Ref<const Eigen::VectorXd>& v, double dt, Eigen::VectorXd* q_next) {
  model.CheckConfiguration("Integrate", "q", q);
  model.CheckVelocity("Integrate", "v", v);
  CheckFinite("Integrate", "dt", dt);
  // Read everything needed from q before writing, so q_next may alias q.
  if (q_next->size() != model.nq()) q_next->resize(model.nq());
  for (BodyIndex b : model.moving_bodies()) {
    const int iq = model.position_start(b), iv = model.velocity_start(b);
    if (model.joint_type(b) == JointType::kFloating) {
      const Eigen::Quaterniond Q = QuaternionFromWxyz(q.data() + iq).normalized();
      const Eigen::Quaterniond dQ = QuaternionExp(dt * v.segment<3>(iv));
      // The angular velocity is expressed in the joint frame: left multiplication.
      const Eigen::Quaterniond Qn = (dQ * Q).normalized();
      const Eigen::Vector3d p = q.segment<3>(iq + 4) + dt * v.segment<3>(iv + 3);
      QuaternionToWxyz(Qn, q_next->data() + iq);
      q_next->segment<3>(iq + 4) = p;
    } else {
      const int n = model.joint_nq(b);
      for (int k = 0; k < n; ++k) (*q_next)(iq + k) = q(iq + k) + dt * v(iv + k);
    }
  }
}

void Difference(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q1,
                const Eigen::Ref<const Eigen::VectorXd>& q0, Eigen::VectorXd* v) {
  model.CheckConfiguration("Difference", "q1", q1);
  model.CheckConfiguration("Difference", "q0", q0);
  if (v->size() != model.nv()) v->resize(model.nv());
  for (BodyIndex b : model.moving_bodies()) {
    const int iq = model.position_start(b), iv = model.velocity_start(b);
    if (model.joint_type(b) == JointType::kFloating) {
      const Eigen::Quaterniond Q0 = QuaternionFromWxyz(q0.data() + iq).normalized();
      const Eigen::Quaterniond Q1 = QuaternionFromWxyz(q1.data() + iq).normalized();
      v->segment<3>(iv) = QuaternionLog(Q1 * Q0.conjugate());
      v->segment<3>(iv + 3) = q1.segment<3>(iq + 4) - q0.segment<3>(iq + 4);
    } else {
      const int n = model.joint_nq(b);
      for (int k = 0; k < n; ++k) (*v)(iv + k) = q1(iq + k) - q0(iq + k);
    }
  }
}

void NormalizeQuaternions(const Model& model, Eigen::VectorXd* q) {
  model.CheckConfiguration("NormalizeQuaternions", "q", *q);
  for (JointIndex j : model.floating_joints()) {
    auto Q = q->segment<4>(model.position_start(j));
    const double n = Q.norm();
    if (n > 0.0 && std::isfinite(n)) {
      Q /= n;
    } else {
      Q << 1.0, 0.0, 0.0, 0.0;
    }
  }
}

}  // namespace idto
