#pragma once

/// @file
/// Inverse dynamics (RNEA), mass matrix (CRBA), bias term, forward dynamics.

#include <Eigen/Core>

#include "idto/multibody/data.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// Spatial forces on bodies: column b = [torque; force] applied to body b at its origin Bo,
/// expressed in the world (6 x num_bodies; column 0, the world, is ignored).
using BodyForces = Eigen::Matrix<double, 6, Eigen::Dynamic>;

/// tau = M(q) a + C(q, v) v - tau_g(q) + D v (joint damping), no contact. Returns data->tau.
/// q: nq, v: nv, a: nv.
const Eigen::VectorXd& InverseDynamics(const Model& model,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       const Eigen::Ref<const Eigen::VectorXd>& v,
                                       const Eigen::Ref<const Eigen::VectorXd>& a, Data* data);

/// As above minus the generalized force of external spatial forces `F_ext` (6 x num_bodies):
/// tau = M a + C v - tau_g + D v - sum_b J_b^T F_ext_b.
const Eigen::VectorXd& InverseDynamics(const Model& model,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       const Eigen::Ref<const Eigen::VectorXd>& v,
                                       const Eigen::Ref<const Eigen::VectorXd>& a,
                                       const BodyForces& F_ext, Data* data);

/// As InverseDynamics(q, v, a[, F_ext]) for the q and v of the preceding
/// ForwardKinematics(q, v, data) call, whose joint poses, velocities and world poses it reuses
/// (about 40% of the work). F_ext may be null. The caller guarantees that data holds
/// ForwardKinematics(q, v) for this v. Returns data->tau.
const Eigen::VectorXd& InverseDynamicsAfterKinematics(const Model& model,
                                                      const Eigen::Ref<const Eigen::VectorXd>& v,
                                                      const Eigen::Ref<const Eigen::VectorXd>& a,
                                                      const BodyForces* F_ext, Data* data);

/// Bias term C(q, v) v - tau_g(q) + D v = InverseDynamics(q, v, 0). Returns data->tau.
const Eigen::VectorXd& BiasTerm(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                                const Eigen::Ref<const Eigen::VectorXd>& v, Data* data);

/// Mass matrix M(q) (nv x nv, symmetric, both triangles filled) by CRBA. Returns data->M.
const Eigen::MatrixXd& MassMatrix(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                                  Data* data);

/// Accelerations a (nv) solving M(q) a + C v - tau_g + D v = tau (CRBA + Cholesky of M).
/// Returns data->a; all NaN if M is not positive definite (never for a model that Build()
/// accepted, barring non-finite input).
const Eigen::VectorXd& ForwardDynamics(const Model& model,
                                       const Eigen::Ref<const Eigen::VectorXd>& q,
                                       const Eigen::Ref<const Eigen::VectorXd>& v,
                                       const Eigen::Ref<const Eigen::VectorXd>& tau, Data* data);

/// tau = sum_b J_b^T F_b: the generalized force of spatial forces F (6 x num_bodies, at each
/// body origin, world frame). `data` must hold ForwardKinematics(q). tau (nv) is resized.
void GeneralizedForceFromBodyForces(const Model& model, const BodyForces& F, Data* data,
                                    Eigen::VectorXd* tau);

}  // namespace idto
