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

/// The world-frame motion subspace (at the world origin) of a moving body b whose joint has one
/// degree of freedom (revolute, continuous or prismatic), given its world pose.
template <typename Scalar>
IDTO_ALWAYS_INLINE SpatialMotionTpl<Scalar> OneDofWorldMotionColumn(
    const Model& model, BodyIndex b, const RigidTransformTpl<Scalar>& X_WB) {
  const Vector3<Scalar> axis_W = X_WB.R * CastTo<Scalar>(model.joint_axis(b));
  if (model.joint_type(b) == JointType::kPrismatic) return {Vector3<Scalar>::Zero(), axis_W};
  return {axis_W, X_WB.p.cross(axis_W)};
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
  if (model.joint_nv(b) == 1) {
    S[0] = OneDofWorldMotionColumn(model, b, X_WB);
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
/// full B is [[B_sym - [h_n]x, 0], [-2 [h_f]x, 0]] with h = I V its momentum), written entry by
/// entry into *B (a returned temporary copied with 16-byte moves after 8-byte stores stalls on
/// store forwarding).
template <typename Scalar>
inline void BodyBSym(const SpatialInertiaTpl<Scalar>& I, const SpatialMotionTpl<Scalar>& V,
                     Matrix3<Scalar>* B) {
  Matrix3<Scalar> wI;  // [w]x Ibar, by columns
  for (int k = 0; k < 3; ++k) wI.col(k) = V.w.cross(I.Ibar.col(k));
  const Scalar hv2 = 2.0 * I.h.dot(V.v);
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r <= c; ++r) {
      Scalar b = wI(r, c) + wI(c, r) - I.h(r) * V.v(c) - V.v(r) * I.h(c);
      if (r == c) b += hv2;
      (*B)(r, c) = b;
      (*B)(c, r) = b;
    }
  }
}

/// Forward pass for moving body j: pose, world motion subspace, velocity, acceleration, body
/// force and the per-column derivative directions u, w, u' (data->dV_dq_, dA_dq_, dA_dv_).
/// kOneDof: j's joint has one degree of freedom (no mixed-frame column); the motion subspace is
/// then one local column the compiler keeps in registers.
template <bool kOneDof, typename Scalar>
inline void RneaDerivativesForwardBodyImpl(const Model& model, BodyIndex j, const Scalar* q,
                                           const Scalar* v, const Scalar* a,
                                           DataTpl<Scalar>* data) {
  using Motion = SpatialMotionTpl<Scalar>;
  const BodyIndex p = model.moving_parent(j);
  const int n = kOneDof ? 1 : model.joint_nv(j);
  const int iv = model.velocity_start(j);
  const JointType type = model.joint_type(j);
  CalcJointPose(model, j, q + model.position_start(j), &data->X_pi_[j], &data->R_JB_[j]);
  const RigidTransformTpl<Scalar>& X_Wp = data->X_WB_[p];
  RigidTransformTpl<Scalar>& X_WB = data->X_WB_[j];
  X_WB = X_Wp * data->X_pi_[j];
  Motion S[kOneDof ? 1 : 6];
  if constexpr (kOneDof) {
    S[0] = OneDofWorldMotionColumn(model, j, X_WB);
  } else {
    WorldMotionSubspace(model, j, X_Wp, X_WB, S);
  }
  Motion vJ, aJ, Tv;
  for (int k = 0; k < n; ++k) {
    vJ += S[k] * v[iv + k];
    aJ += S[k] * a[iv + k];
    if (!kOneDof && IsMixedFrameTranslation(type, k)) Tv += S[k] * v[iv + k];
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
  BodyBSym(body.Ic, body.V, &body.B_sym);
  body.ext_n.setZero();
  body.ext_f.setZero();
  body.ext_P.setZero();
  const Motion V_sum = body.V + body.V_F;
  for (int k = 0; k < n; ++k) {
    const Motion& s = S[k];
    StoreColumn(s, iv + k, &data->S_);
    Motion u = Cross(body.V, s), up = Cross(V_sum, s);
    Motion w = Cross(body.A, s);
    if (!kOneDof && IsMixedFrameTranslation(type, k)) {
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

template <typename Scalar>
inline void RneaDerivativesForwardBody(const Model& model, BodyIndex j, const Scalar* q,
                                       const Scalar* v, const Scalar* a, DataTpl<Scalar>* data) {
  if (model.joint_nv(j) == 1) {
    RneaDerivativesForwardBodyImpl<true>(model, j, q, v, a, data);
  } else {
    RneaDerivativesForwardBodyImpl<false>(model, j, q, v, a, data);
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

/// What the backward step needs of one column s of joint i (with u, w, u' its derivative
/// directions): g (for dtau_dq), h (for dtau_dv), k = Ic s (for M and the descendant rows), and
/// the angular 3-vectors y2 = (B^T s)_w and y3 = (Phi^T s) (external forces) of the descendant
/// rows.
template <typename Scalar>
struct RneaColumnTermsTpl {
  Vector6<Scalar> g, h, k;  // spatial forces as [n; f]
  Vector3<Scalar> y2, y3;
};

/// B x for an angular 3-vector x (the linear columns of B are zero; see BodyBSym).
template <typename Scalar>
IDTO_ALWAYS_INLINE SpatialForceTpl<Scalar> BodyBTimes(const RneaDerivativeBodyTpl<Scalar>& body,
                                                      const Vector3<Scalar>& x) {
  return {body.B_sym * x - body.h.n.cross(x), -2.0 * body.h.f.cross(x)};
}

template <typename Scalar>
IDTO_ALWAYS_INLINE RneaColumnTermsTpl<Scalar> RneaColumnTerms(
    const RneaDerivativeBodyTpl<Scalar>& body, const SpatialMotionTpl<Scalar>& s,
    const SpatialMotionTpl<Scalar>& u, const SpatialMotionTpl<Scalar>& w,
    const SpatialMotionTpl<Scalar>& up, bool with_ext) {
  const Vector3<Scalar>& hn = body.h.n;
  const Vector3<Scalar>& hf = body.h.f;
  RneaColumnTermsTpl<Scalar> t;
  SpatialForceTpl<Scalar> g = CrossForce(s, body.F) + body.Ic * w + BodyBTimes(body, u.w);
  const SpatialForceTpl<Scalar> h = body.Ic * up + BodyBTimes(body, s.w);
  const SpatialForceTpl<Scalar> k = body.Ic * s;
  t.y2 = body.B_sym * s.w + hn.cross(s.w) + 2.0 * hf.cross(s.v);
  if (with_ext) {
    g.n -= body.ext_n.cross(s.w) + body.ext_P * s.w;
    g.f -= body.ext_f.cross(s.w);
    t.y3 = s.w.cross(body.ext_n) + body.ext_P.transpose() * s.w - body.ext_f.cross(s.v);
  }
  t.g << g.n, g.f;
  t.h << h.n, h.f;
  t.k << k.n, k.f;
  return t;
}

/// The backward step's outputs for a moving body i with one degree of freedom (no mixed-frame
/// column), given the terms t of its column: tau_i, the diagonal entries, then the ancestors'
/// rows and columns column by column, as dot products of fixed size 6 and 3. Most joints have
/// one degree of freedom; these are the general case's block products without their per-block
/// setup, on values held in registers.
template <typename Scalar>
inline void RneaDerivativesOneColumn(const Model& model, BodyIndex i,
                                     const RneaColumnTermsTpl<Scalar>& t, bool with_ext,
                                     DataTpl<Scalar>* data) {
  const int iv = model.velocity_start(i);
  MatrixX<Scalar>& dq = data->dtau_dq_tangent;
  MatrixX<Scalar>& dv = data->dtau_dv;
  MatrixX<Scalar>& M = data->M;
  const auto s_i = data->S_.col(iv);
  const SpatialForceTpl<Scalar>& F = data->deriv_body_[i].F;
  data->tau(iv) = s_i.template head<3>().dot(F.n) + s_i.template tail<3>().dot(F.f);
  dq(iv, iv) = s_i.dot(t.g);
  dv(iv, iv) = s_i.dot(t.h);
  M(iv, iv) = s_i.dot(t.k);
  for (BodyIndex j = model.moving_parent(i); j != kWorldBody; j = model.moving_parent(j)) {
    const int end = model.velocity_start(j) + model.joint_nv(j);
    for (int c = model.velocity_start(j); c < end; ++c) {
      const auto s = data->S_.col(c);
      dq(c, iv) = s.dot(t.g);
      dv(c, iv) = s.dot(t.h);
      const Scalar m = s.dot(t.k);
      M(c, iv) = m;
      M(iv, c) = m;
      const auto sw = s.template head<3>();
      Scalar dq_ic =
          t.k.dot(data->dA_dq_.col(c)) + t.y2.dot(data->dV_dq_.col(c).template head<3>());
      if (with_ext) dq_ic -= t.y3.dot(sw);
      dq(iv, c) = dq_ic;
      dv(iv, c) = t.k.dot(data->dA_dv_.col(c)) + t.y2.dot(sw);
    }
  }
}

/// Backward step at moving body i (its composites complete): tau_i and the blocks of
/// dtau_dq_tangent, dtau_dv and M in the rows and columns of i and of its ancestors.
template <typename Scalar>
inline void RneaDerivativesBackwardBody(const Model& model, BodyIndex i, bool with_ext,
                                        DataTpl<Scalar>* data) {
  const RneaDerivativeBodyTpl<Scalar>& body = data->deriv_body_[i];
  const int n = model.joint_nv(i);
  const int iv = model.velocity_start(i);
  const JointType type = model.joint_type(i);
  MatrixX<Scalar>& dq = data->dtau_dq_tangent;
  MatrixX<Scalar>& dv = data->dtau_dv;
  MatrixX<Scalar>& M = data->M;
  if (n == 1) {
    const RneaColumnTermsTpl<Scalar> t =
        RneaColumnTerms(body, LoadColumn(data->S_, iv), LoadColumn(data->dV_dq_, iv),
                        LoadColumn(data->dA_dq_, iv), LoadColumn(data->dA_dv_, iv), with_ext);
    RneaDerivativesOneColumn(model, i, t, with_ext, data);
    return;
  }
  // Columns of joint i (RneaColumnTermsTpl): G (for dq), H (for dv), K = Ic S, Y2 and Y3.
  ForceColumns<Scalar> G, H, K;
  Eigen::Matrix<Scalar, 3, 6> Y2, Y3;
  for (int c = 0; c < n; ++c) {
    const RneaColumnTermsTpl<Scalar> t = RneaColumnTerms(
        body, LoadColumn(data->S_, iv + c), LoadColumn(data->dV_dq_, iv + c),
        LoadColumn(data->dA_dq_, iv + c), LoadColumn(data->dA_dv_, iv + c), with_ext);
    G.col(c) = t.g;
    H.col(c) = t.h;
    K.col(c) = t.k;
    Y2.col(c) = t.y2;
    if (with_ext) Y3.col(c) = t.y3;
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
  // Columns of joints without a quaternion are copied in runs of consecutive columns (whole
  // columns of a column-major matrix: one contiguous copy per run).
  int run_q = 0, run_v = 0, run_n = 0;
  auto flush = [&]() {
    if (run_n > 0) dq.middleCols(run_q, run_n) = dq_t.middleCols(run_v, run_n);
    run_n = 0;
  };
  for (BodyIndex b : model.moving_bodies()) {
    const int iq = model.position_start(b), iv = model.velocity_start(b);
    if (model.joint_type(b) == JointType::kFloating) {
      const Eigen::Matrix<Scalar, 4, 3> E = QuaternionRateMatrix(q + iq);
      const Scalar n2 =
          q[iq] * q[iq] + q[iq + 1] * q[iq + 1] + q[iq + 2] * q[iq + 2] + q[iq + 3] * q[iq + 3];
      const Scalar scale = n2 > 0.0 ? Scalar(4.0 / n2) : Scalar(0);
      // Inner dimension 3: each quaternion column as a sum of three scaled whole columns
      // (vectorized down the rows; GEMM's packing costs more at this size).
      for (int k = 0; k < 4; ++k) {
        dq.col(iq + k) = dq_t.col(iv) * (scale * E(k, 0)) + dq_t.col(iv + 1) * (scale * E(k, 1)) +
                         dq_t.col(iv + 2) * (scale * E(k, 2));
      }
      dq.template middleCols<3>(iq + 4) = dq_t.template middleCols<3>(iv + 3);
      continue;
    }
    const int n = model.joint_nv(b);
    if (run_n > 0 && iq == run_q + run_n && iv == run_v + run_n) {
      run_n += n;
    } else {
      flush();
      run_q = iq;
      run_v = iv;
      run_n = n;
    }
  }
  flush();
}

/// After ComputeRneaDerivatives(Tangent): the rest of what ForwardKinematics(q, v) leaves in
/// *data for a contact evaluation, from the pass's world-frame quantities: the poses of welded
/// bodies (the moving ones are already there) and every body's world angular velocity and origin
/// velocity (data->w_WB_, data->v_WBo_). Mathematically what ForwardKinematics computes, with
/// its own round-off (velocities from the world-frame twists, not from body coordinates).
template <typename Scalar>
void CompleteKinematicsAfterRneaDerivatives(const Model& model, DataTpl<Scalar>* data) {
  data->w_WB_[0].setZero();
  data->v_WBo_[0].setZero();
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const BodyIndex m = model.mobilized_body(b);
    if (m == kWorldBody) {
      // Welded to the world (kept as Kinematics keeps it: its pose from the world's).
      data->X_WB_[b] = data->X_WB_[0] * CastTo<Scalar>(model.X_MB(b));
      data->w_WB_[b].setZero();
      data->v_WBo_[b].setZero();
      continue;
    }
    if (m != b) data->X_WB_[b] = data->X_WB_[m] * CastTo<Scalar>(model.X_MB(b));
    // V = (w, v_O) at the world origin: the body origin moves at v_O + w x p.
    const SpatialMotionTpl<Scalar>& V = data->deriv_body_[m].V;
    data->w_WB_[b] = V.w;
    data->v_WBo_[b] = V.v + V.w.cross(data->X_WB_[b].p);
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
