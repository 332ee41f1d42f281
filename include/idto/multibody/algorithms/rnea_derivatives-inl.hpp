#pragma once

/// @file
/// Definitions of the Scalar-templated RNEA derivatives (include to instantiate them with a
/// scalar other than double). Notation (docs/architecture.md): every spatial quantity is in the
/// world frame, at the world origin. For joint j with world motion subspace S_j, a tangent
/// perturbation of q_j along column s = S_j e displaces the subtree of j rigidly by s, and moves
/// the frame in which S_j is constant by t (the translational columns of floating and planar
/// joints, zero otherwise). Then, for every body k in the subtree of j:
///   dV_k = s x V_k + u,   dA_k = s x A_k + u x V_k + w,
///   u = V_j x s + t x vJ_j,
///   w = A_j x s + t x aJ_j + V_Fj x (t x vJ_j) + V_j x u,
/// with vJ_j = S_j v_j, aJ_j = S_j a_j and V_Fj = V_parent + T_j v_j. Along v_j: dV_k = s and
/// dA_k = s x V_k + u' with u' = (V_j + V_Fj) x s + t x vJ_j.

#include <vector>

#include "idto/multibody/algorithms/dynamics-inl.hpp"
#include "idto/multibody/algorithms/joint_kinematics.hpp"
#include "idto/multibody/algorithms/rnea_derivatives.hpp"

namespace idto {

namespace internal {

/// Whether column k of a joint's motion subspace is a translation of the joint's mixed frame
/// (origin at the body origin, axes of the joint frame): the columns whose perturbation moves
/// the frame in which S is constant.
inline bool IsMixedFrameTranslation(JointType type, int k) {
  return (type == JointType::kFloating && k >= 3) || (type == JointType::kPlanar && k < 2);
}

/// The columns of the world-frame motion subspace of moving body b (at the world origin), given
/// the world poses of its moving parent and of b.
template <typename Scalar>
inline void WorldMotionSubspace(const Model& model, BodyIndex b,
                                const RigidTransformTpl<Scalar>& X_Wp,
                                const RigidTransformTpl<Scalar>& X_WB,
                                SpatialMotionTpl<Scalar>* S) {
  const Vector3<Scalar>& p = X_WB.p;
  const JointType type = model.joint_type(b);
  if (type == JointType::kRevolute || type == JointType::kContinuous) {
    S[0].w.noalias() = X_WB.R * CastTo<Scalar>(model.joint_axis(b));
    S[0].v = p.cross(S[0].w);
    return;
  }
  if (type == JointType::kPrismatic) {
    S[0].w.setZero();
    S[0].v.noalias() = X_WB.R * CastTo<Scalar>(model.joint_axis(b));
    return;
  }
  Matrix3<Scalar> R_WJ;
  if (model.X_MJ_is_translation(b)) {
    R_WJ = X_Wp.R;
  } else {
    R_WJ.noalias() = X_Wp.R * CastTo<Scalar>(model.X_MJ(b).R);
  }
  if (type == JointType::kFloating) {
    for (int k = 0; k < 3; ++k) {
      S[k].w = R_WJ.col(k);
      S[k].v = p.cross(S[k].w);
      S[k + 3].w.setZero();
      S[k + 3].v = R_WJ.col(k);
    }
    return;
  }
  // Planar: x and y along e1 and e2, theta about the normal through the body origin.
  S[0].w.setZero();
  S[0].v.noalias() = R_WJ * CastTo<Scalar>(model.planar_e1(b));
  S[1].w.setZero();
  S[1].v.noalias() = R_WJ * CastTo<Scalar>(model.planar_e2(b));
  S[2].w.noalias() = R_WJ * CastTo<Scalar>(model.joint_axis(b));
  S[2].v = p.cross(S[2].w);
}

template <typename Scalar>
inline void StoreColumn(const SpatialMotionTpl<Scalar>& m, int k,
                        Eigen::Matrix<Scalar, 6, Eigen::Dynamic>* M) {
  M->col(k).template head<3>() = m.w;
  M->col(k).template tail<3>() = m.v;
}

template <typename Scalar>
inline SpatialMotionTpl<Scalar> LoadColumn(const Eigen::Matrix<Scalar, 6, Eigen::Dynamic>& M,
                                           int k) {
  return {M.col(k).template head<3>(), M.col(k).template tail<3>()};
}

/// Symmetric part of the angular block of B(I, V) = d(V x* I V)/dV - I [V x] for one body (the
/// full B is [[B_sym - [h_n]x, 0], [-2 [h_f]x, 0]] with h = I V its momentum).
template <typename Scalar>
inline Matrix3<Scalar> BodyBSym(const SpatialInertiaTpl<Scalar>& I,
                                const SpatialMotionTpl<Scalar>& V) {
  const Matrix3<Scalar> wI = Skew(V.w) * I.Ibar;
  Matrix3<Scalar> B = wI + wI.transpose();
  B.noalias() -= I.h * V.v.transpose();
  B.noalias() -= V.v * I.h.transpose();
  B.diagonal().array() += 2.0 * I.h.dot(V.v);
  return B;
}

/// Forward pass for moving body j: pose, world motion subspace, velocity, acceleration, body
/// force and the per-column derivative directions u, w, u' (data->dV_dq_, dA_dq_, dA_dv_).
template <typename Scalar>
inline void RneaDerivativesForwardBody(const Model& model, BodyIndex j, const Scalar* q,
                                       const Scalar* v, const Scalar* a, DataTpl<Scalar>* data) {
  using Motion = SpatialMotionTpl<Scalar>;
  const BodyIndex p = model.moving_parent(j);
  const int n = model.joint_nv(j);
  const int iv = model.velocity_start(j);
  const JointType type = model.joint_type(j);
  CalcJointPose(model, j, q + model.position_start(j), &data->X_pi_[j], &data->R_JB_[j]);
  const RigidTransformTpl<Scalar>& X_Wp = data->X_WB_[p];
  RigidTransformTpl<Scalar>& X_WB = data->X_WB_[j];
  X_WB = X_Wp * data->X_pi_[j];
  Motion S[6];
  WorldMotionSubspace(model, j, X_Wp, X_WB, S);
  Motion vJ, aJ, Tv;
  for (int k = 0; k < n; ++k) {
    vJ += S[k] * v[iv + k];
    aJ += S[k] * a[iv + k];
    if (IsMixedFrameTranslation(type, k)) Tv += S[k] * v[iv + k];
  }
  RneaDerivativeBodyTpl<Scalar>& body = data->deriv_body_[j];
  if (p == kWorldBody) {
    body.V = vJ;
    body.V_F = Tv;
    body.A = Motion(Vector3<Scalar>::Zero(), -CastTo<Scalar>(model.gravity())) + aJ;
  } else {
    const RneaDerivativeBodyTpl<Scalar>& parent = data->deriv_body_[p];
    body.V = parent.V + vJ;
    body.V_F = parent.V + Tv;
    body.A = parent.A + aJ;
  }
  body.A += Cross(body.V_F, vJ);
  body.vJ = vJ;
  body.Ic = CastTo<Scalar>(model.merged_inertia(j)).ExpressedIn(X_WB);
  body.h = body.Ic * body.V;
  body.F = body.Ic * body.A + CrossForce(body.V, body.h);
  body.B_sym = BodyBSym(body.Ic, body.V);
  body.ext_n.setZero();
  body.ext_f.setZero();
  body.ext_P.setZero();
  const Motion V_sum = body.V + body.V_F;
  for (int k = 0; k < n; ++k) {
    const Motion& s = S[k];
    StoreColumn(s, iv + k, &data->S_);
    Motion u = Cross(body.V, s), up = Cross(V_sum, s);
    Motion w = Cross(body.A, s);
    if (IsMixedFrameTranslation(type, k)) {
      const Motion t_vJ = Cross(s, vJ);
      u += t_vJ;
      up += t_vJ;
      w += Cross(s, aJ) + Cross(body.V_F, t_vJ);
    }
    w += Cross(body.V, u);
    StoreColumn(u, iv + k, &data->dV_dq_);
    StoreColumn(w, iv + k, &data->dA_dq_);
    StoreColumn(up, iv + k, &data->dA_dv_);
  }
}

/// Subtracts the external forces from the body forces (at the world origin) and records the
/// terms of their derivative (moments, forces and sum of [p]x [f]x per moving body).
template <typename Scalar>
inline void RneaDerivativesExternalForces(const Model& model, const BodyForcesTpl<Scalar>& F_ext,
                                          DataTpl<Scalar>* data) {
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const BodyIndex m = model.mobilized_body(b);
    if (m == kWorldBody) continue;
    const Vector3<Scalar> n = F_ext.col(b).template head<3>();
    const Vector3<Scalar> f = F_ext.col(b).template tail<3>();
    if ((n.array() == 0.0).all() && (f.array() == 0.0).all()) continue;
    const Vector3<Scalar> p = data->X_WB_[m] * CastTo<Scalar>(model.X_MB(b).p);
    RneaDerivativeBodyTpl<Scalar>& body = data->deriv_body_[m];
    body.F.n -= n + p.cross(f);
    body.F.f -= f;
    body.ext_n += n;
    body.ext_f += f;
    body.ext_P.noalias() += f * p.transpose();
    body.ext_P.diagonal().array() -= p.dot(f);
  }
}

template <typename Scalar>
using ForceColumns = Eigen::Matrix<Scalar, 6, 6>;

/// Backward step at moving body i (its composites complete): tau_i and the blocks of
/// dtau_dq_tangent, dtau_dv and M in the rows and columns of i and of its ancestors.
template <typename Scalar>
inline void RneaDerivativesBackwardBody(const Model& model, BodyIndex i, bool with_ext,
                                        DataTpl<Scalar>* data) {
  using Motion = SpatialMotionTpl<Scalar>;
  using Force = SpatialForceTpl<Scalar>;
  const RneaDerivativeBodyTpl<Scalar>& body = data->deriv_body_[i];
  const int n = model.joint_nv(i);
  const int iv = model.velocity_start(i);
  const JointType type = model.joint_type(i);
  MatrixX<Scalar>& dq = data->dtau_dq_tangent;
  MatrixX<Scalar>& dv = data->dtau_dv;
  MatrixX<Scalar>& M = data->M;
  // Columns of joint i: G (for dq), H (for dv), K = Ic S (for M and the descendant rows), and
  // the angular 3-vectors Y2 = (B^T S)_w and Y3 = (Phi^T S) of the descendant rows.
  ForceColumns<Scalar> G, H, K;
  Eigen::Matrix<Scalar, 3, 6> Y2, Y3;
  const Vector3<Scalar>& hn = body.h.n;
  const Vector3<Scalar>& hf = body.h.f;
  auto B_times = [&](const Vector3<Scalar>& x) {
    return Force(body.B_sym * x - hn.cross(x), -2.0 * hf.cross(x));
  };
  for (int c = 0; c < n; ++c) {
    const Motion s = LoadColumn(data->S_, iv + c);
    const Motion u = LoadColumn(data->dV_dq_, iv + c);
    const Motion w = LoadColumn(data->dA_dq_, iv + c);
    const Motion up = LoadColumn(data->dA_dv_, iv + c);
    Force g = CrossForce(s, body.F) + body.Ic * w + B_times(u.w);
    const Force h = body.Ic * up + B_times(s.w);
    const Force k = body.Ic * s;
    Y2.col(c) = body.B_sym * s.w + hn.cross(s.w) + 2.0 * hf.cross(s.v);
    if (with_ext) {
      g.n -= body.ext_n.cross(s.w) + body.ext_P * s.w;
      g.f -= body.ext_f.cross(s.w);
      Y3.col(c) = s.w.cross(body.ext_n) + body.ext_P.transpose() * s.w - body.ext_f.cross(s.v);
    }
    G.col(c) << g.n, g.f;
    H.col(c) << h.n, h.f;
    K.col(c) << k.n, k.f;
  }
  const auto S_i = data->S_.middleCols(iv, n);
  for (int r = 0; r < n; ++r) {
    data->tau(iv + r) =
        S_i.col(r).template head<3>().dot(body.F.n) + S_i.col(r).template tail<3>().dot(body.F.f);
  }
  dq.block(iv, iv, n, n).noalias() = S_i.transpose() * G.leftCols(n);
  dv.block(iv, iv, n, n).noalias() = S_i.transpose() * H.leftCols(n);
  M.block(iv, iv, n, n).noalias() = S_i.transpose() * K.leftCols(n);
  for (int c = 0; c < n; ++c) {
    if (!IsMixedFrameTranslation(type, c)) continue;
    for (int r = 0; r < n; ++r) {
      dq(iv + r, iv + c) +=
          Dot(Cross(LoadColumn(data->S_, iv + c), LoadColumn(data->S_, iv + r)), body.F);
    }
  }
  // Rows and columns of the ancestors j: small products with inner dimension 6 or 3 (Eigen
  // evaluates them coefficient-wise, vectorized, without GEMM's packing).
  const auto Gi = G.leftCols(n);
  const auto Hi = H.leftCols(n);
  const auto Ki = K.leftCols(n);
  for (BodyIndex j = model.moving_parent(i); j != kWorldBody; j = model.moving_parent(j)) {
    const int nj = model.joint_nv(j);
    const int jv = model.velocity_start(j);
    const auto S_j = data->S_.middleCols(jv, nj);
    dq.block(jv, iv, nj, n).noalias() = S_j.transpose() * Gi;
    dv.block(jv, iv, nj, n).noalias() = S_j.transpose() * Hi;
    M.block(jv, iv, nj, n).noalias() = S_j.transpose() * Ki;
    M.block(iv, jv, n, nj) = M.block(jv, iv, nj, n).transpose();
    auto dq_ij = dq.block(iv, jv, n, nj);
    dq_ij.noalias() = Ki.transpose() * data->dA_dq_.middleCols(jv, nj);
    dq_ij.noalias() += Y2.leftCols(n).transpose() * data->dV_dq_.middleCols(jv, nj).topRows(3);
    if (with_ext) dq_ij.noalias() -= Y3.leftCols(n).transpose() * S_j.topRows(3);
    auto dv_ij = dv.block(iv, jv, n, nj);
    dv_ij.noalias() = Ki.transpose() * data->dA_dv_.middleCols(jv, nj);
    dv_ij.noalias() += Y2.leftCols(n).transpose() * S_j.topRows(3);
  }
}

/// Adds the composites of moving body i to its moving parent.
template <typename Scalar>
inline void RneaDerivativesAccumulate(const Model& model, BodyIndex i, DataTpl<Scalar>* data) {
  const BodyIndex p = model.moving_parent(i);
  if (p == kWorldBody) return;
  const RneaDerivativeBodyTpl<Scalar>& c = data->deriv_body_[i];
  RneaDerivativeBodyTpl<Scalar>& parent = data->deriv_body_[p];
  parent.Ic += c.Ic;
  parent.B_sym += c.B_sym;
  parent.h += c.h;
  parent.F += c.F;
  parent.ext_n += c.ext_n;
  parent.ext_f += c.ext_f;
  parent.ext_P += c.ext_P;
}

/// dtau_dq (raw q coordinates) = dtau_dq_tangent * N+(q).
template <typename Scalar>
inline void RneaDerivativesToRawCoordinates(const Model& model, const Scalar* q,
                                            DataTpl<Scalar>* data) {
  const MatrixX<Scalar>& dq_t = data->dtau_dq_tangent;
  MatrixX<Scalar>& dq = data->dtau_dq;
  for (BodyIndex b : model.moving_bodies()) {
    const int iq = model.position_start(b), iv = model.velocity_start(b);
    if (model.joint_type(b) == JointType::kFloating) {
      const Eigen::Matrix<Scalar, 4, 3> E = QuaternionRateMatrix(q + iq);
      const Scalar n2 =
          q[iq] * q[iq] + q[iq + 1] * q[iq + 1] + q[iq + 2] * q[iq + 2] + q[iq + 3] * q[iq + 3];
      const Scalar scale = n2 > 0.0 ? Scalar(4.0 / n2) : Scalar(0);
      // Inner dimension 3: a coefficient-based product (GEMM's packing costs more here).
      dq.template middleCols<4>(iq).noalias() =
          dq_t.template middleCols<3>(iv).lazyProduct(scale * E.transpose());
      dq.template middleCols<3>(iq + 4) = dq_t.template middleCols<3>(iv + 3);
    } else {
      const int n = model.joint_nv(b);
      dq.middleCols(iq, n) = dq_t.middleCols(iv, n);
    }
  }
}

}  // namespace internal

namespace internal {

/// ComputeRneaDerivatives without the last step: data->dtau_dq (raw coordinates) is not
/// written (for callers that add to dtau_dq_tangent first, then call
/// RneaDerivativesToRawCoordinates once).
template <typename Scalar>
void ComputeRneaDerivativesTangent(const Model& model, const ConstVectorRef<Scalar>& q,
                                   const ConstVectorRef<Scalar>& v, const ConstVectorRef<Scalar>& a,
                                   const NonDeduced<BodyForcesTpl<Scalar>>* F_ext,
                                   DataTpl<Scalar>* data) {
  CheckData(model, "ComputeRneaDerivatives", data);
  CheckNq(model, "ComputeRneaDerivatives", "q", q.size());
  CheckNv(model, "ComputeRneaDerivatives", "v", v.size());
  CheckNv(model, "ComputeRneaDerivatives", "a", a.size());
  CheckBodyForces(model, "ComputeRneaDerivatives", F_ext);
  const std::vector<BodyIndex>& moving = model.moving_bodies();
  data->X_WB_[0] = RigidTransformTpl<Scalar>::Identity();
  for (BodyIndex b : moving)
    RneaDerivativesForwardBody(model, b, q.data(), v.data(), a.data(), data);
  if (F_ext != nullptr) RneaDerivativesExternalForces(model, *F_ext, data);
  // Entries between bodies on different branches are zero and never written.
  data->dtau_dq_tangent.setZero();
  data->dtau_dv.setZero();
  data->M.setZero();
  for (auto it = moving.rbegin(); it != moving.rend(); ++it) {
    RneaDerivativesBackwardBody(model, *it, F_ext != nullptr, data);
    RneaDerivativesAccumulate(model, *it, data);
  }
  const Eigen::VectorXd& d = model.damping();
  for (int i = 0; i < model.nv(); ++i) {
    data->tau(i) += d[i] * v[i];
    data->dtau_dv(i, i) += d[i];
  }
}

}  // namespace internal

template <typename Scalar>
void ComputeRneaDerivatives(const Model& model, const ConstVectorRef<Scalar>& q,
                            const ConstVectorRef<Scalar>& v, const ConstVectorRef<Scalar>& a,
                            const NonDeduced<BodyForcesTpl<Scalar>>* F_ext, DataTpl<Scalar>* data) {
  internal::ComputeRneaDerivativesTangent<Scalar>(model, q, v, a, F_ext, data);
  internal::RneaDerivativesToRawCoordinates(model, q.data(), data);
}

}  // namespace idto
