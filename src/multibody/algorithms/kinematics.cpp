#include "idto/multibody/algorithms/kinematics.hpp"

#include <cmath>

#include "../joint_kinematics.hpp"
#include "idto/core/errors.hpp"
#include "idto/math/quaternion.hpp"

namespace idto {

namespace {

// World poses of every body; velocities too when v != nullptr.
void Kinematics(const Model& model, const double* q, const double* v, Data* data) {
  data->X_WB_[0] = RigidTransform::Identity();
  data->w_WB_[0].setZero();
  data->v_WBo_[0].setZero();
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const BodyIndex mb = model.mobilized_body(b);
    if (mb != b) {
      // Welded: rigidly attached to its moving body.
      const RigidTransform& X_WM = data->X_WB_[mb];
      data->X_WB_[b] = X_WM * model.X_MB(b);
      if (v != nullptr) {
        data->w_WB_[b] = data->w_WB_[mb];
        data->v_WBo_[b] = data->v_WBo_[mb] + data->w_WB_[mb].cross(data->X_WB_[b].p - X_WM.p);
      }
      continue;
    }
    RigidTransform& X_pi = data->X_pi_[b];
    internal::CalcJointPose(model, b, q + model.position_start(b), &X_pi, &data->R_JB_[b]);
    const BodyIndex p = model.moving_parent(b);
    const RigidTransform& X_Wp = data->X_WB_[p];
    RigidTransform& X_Wi = data->X_WB_[b];
    X_Wi = X_Wp * X_pi;
    if (v != nullptr) {
      // Body-coordinate velocity, then world-aligned angular velocity and origin velocity.
      const SpatialMotion vJ =
          internal::JointMotion(model, b, data->R_JB_[b], v + model.velocity_start(b));
      SpatialMotion& vi = data->vel_[b];
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

}  // namespace

void ForwardKinematics(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q, Data* data) {
  model.CheckConfiguration("ForwardKinematics", "q", q);
  Kinematics(model, q.data(), nullptr, data);
}

void ForwardKinematics(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                       const Eigen::Ref<const Eigen::VectorXd>& v, Data* data) {
  model.CheckConfiguration("ForwardKinematics", "q", q);
  model.CheckVelocity("ForwardKinematics", "v", v);
  Kinematics(model, q.data(), v.data(), data);
}

void CalcNMatrix(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                 Eigen::MatrixXd* N) {
  model.CheckConfiguration("CalcNMatrix", "q", q);
  N->setZero(model.nq(), model.nv());
  for (BodyIndex b : model.moving_bodies()) {
    const int iq = model.position_start(b), iv = model.velocity_start(b);
    if (model.joint_type(b) == JointType::kFloating) {
      N->block<4, 3>(iq, iv) = QuaternionRateMatrix(q.data() + iq);
      N->block<3, 3>(iq + 4, iv + 3).setIdentity();
    } else {
      for (int k = 0; k < model.joint_nv(b); ++k) (*N)(iq + k, iv + k) = 1.0;
    }
  }
}

void CalcNplusMatrix(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                     Eigen::MatrixXd* Nplus) {
  model.CheckConfiguration("CalcNplusMatrix", "q", q);
  Nplus->setZero(model.nv(), model.nq());
  for (BodyIndex b : model.moving_bodies()) {
    const int iq = model.position_start(b), iv = model.velocity_start(b);
    if (model.joint_type(b) == JointType::kFloating) {
      // E^T E = |q|^2 / 4 I, so the pseudo-inverse of E is (4 / |q|^2) E^T.
      const Eigen::Matrix<double, 4, 3> E = QuaternionRateMatrix(q.data() + iq);
      const double n2 = q.segment<4>(iq).squaredNorm();
      Nplus->block<3, 4>(iv, iq) = (n2 > 0.0 ? 4.0 / n2 : 0.0) * E.transpose();
      Nplus->block<3, 3>(iv + 3, iq + 4).setIdentity();
    } else {
      for (int k = 0; k < model.joint_nv(b); ++k) (*Nplus)(iv + k, iq + k) = 1.0;
    }
  }
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
