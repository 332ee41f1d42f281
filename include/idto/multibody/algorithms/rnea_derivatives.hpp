#pragma once

/// @file
/// Analytic derivatives of inverse dynamics (RNEA): d tau / d q, d tau / d v and
/// M = d tau / d a in one forward and one backward pass over the tree (world-frame recursions in
/// the spirit of Carpentier & Mansard, RSS 2018, derived for idto's joint conventions; see
/// docs/architecture.md "Templated kernels and derivative conventions").
///
/// tau(q, v, a) = M(q) a + C(q, v) v - tau_g(q) + D v - sum_b J_b(q)^T F_ext_b, with the external
/// spatial forces F_ext (6 x num_bodies: [moment about the body origin Bo; force], world frame)
/// held fixed: the force vectors do not change with q, their points of application (the body
/// origins) move with the bodies.
///
/// Coordinates of d tau / d q:
///  - data->dtau_dq (nv x nq) is the derivative in the raw coordinates of q, quaternion entries
///    included: d tau = dtau_dq * dq for any dq in R^nq. tau depends on a quaternion only through
///    its direction, so the columns of a quaternion satisfy dtau_dq.cols(quaternion) * q_quat = 0.
///    This is what a chain rule through q (e.g. through v = N+(q) (q_next - q) / dt) needs.
///  - data->dtau_dq_tangent (nv x nv) is the derivative along the tangent directions
///    dq = N(q) dx (dx in R^nv; for a floating joint dx = [rotation about the joint frame's axes,
///    applied on the left; translation of the body origin in the joint frame]). The two are
///    related by dtau_dq = dtau_dq_tangent * N+(q) and dtau_dq_tangent = dtau_dq * N(q) (for a
///    unit quaternion, or any non-zero one since N+(q) N(q) = I).

#include <Eigen/Core>

#include "idto/math/scalar.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/data.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// Computes, at (q, v, a) with external forces F_ext (6 x num_bodies, or null for none):
/// data->tau (= InverseDynamics(q, v, a, F_ext)), data->dtau_dq (nv x nq),
/// data->dtau_dq_tangent (nv x nv), data->dtau_dv (nv x nv, joint damping included) and
/// data->M (nv x nv, = d tau / d a). Allocation-free. Leaves data->X_WB_ holding the poses of the
/// moving bodies (welded bodies are not updated). q: nq, v: nv, a: nv.
void ComputeRneaDerivatives(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                            const Eigen::Ref<const Eigen::VectorXd>& v,
                            const Eigen::Ref<const Eigen::VectorXd>& a, const BodyForces* F_ext,
                            Data* data);

/// As above without external forces.
void ComputeRneaDerivatives(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                            const Eigen::Ref<const Eigen::VectorXd>& v,
                            const Eigen::Ref<const Eigen::VectorXd>& a, Data* data);

/// As ComputeRneaDerivatives, with d tau / d q in the tangent space only: data->tau,
/// data->dtau_dq_tangent (nv x nv), data->dtau_dv (nv x nv) and data->M (nv x nv);
/// data->dtau_dq is not written. These are the outputs the solver's derivatives use (and the
/// ones Pinocchio's computeRNEADerivatives computes). F_ext: 6 x num_bodies or null.
void ComputeRneaDerivativesTangent(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                                   const Eigen::Ref<const Eigen::VectorXd>& v,
                                   const Eigen::Ref<const Eigen::VectorXd>& a,
                                   const BodyForces* F_ext, Data* data);

/// Scalar-templated ComputeRneaDerivatives (defined in rnea_derivatives-inl.hpp).
template <typename Scalar>
void ComputeRneaDerivatives(const Model& model, const ConstVectorRef<Scalar>& q,
                            const ConstVectorRef<Scalar>& v, const ConstVectorRef<Scalar>& a,
                            const NonDeduced<BodyForcesTpl<Scalar>>* F_ext, DataTpl<Scalar>* data);

extern template void ComputeRneaDerivatives<double>(const Model&, const ConstVectorRef<double>&,
                                                    const ConstVectorRef<double>&,
                                                    const ConstVectorRef<double>&,
                                                    const BodyForcesTpl<double>*, DataTpl<double>*);

}  // namespace idto
