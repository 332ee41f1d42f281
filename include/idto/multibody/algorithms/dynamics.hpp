#pragma once

/// @file
/// Inverse dynamics (RNEA), mass matrix (CRBA), bias term, forward dynamics.
///
/// InverseDynamics, InverseDynamicsAfterKinematics, BiasTerm and MassMatrix are also templates
/// on the scalar type (defined in dynamics-inl.hpp; the double instantiation is compiled once in
/// the library, extern template below). The non-template double overloads are the stable entry
/// points; the templates deduce Scalar from the DataTpl<Scalar>* argument only.

#include <Eigen/Core>

#include "idto/math/scalar.hpp"
#include "idto/multibody/data.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// Spatial forces on bodies: column b = [torque; force] applied to body b at its origin Bo,
/// expressed in the world (6 x num_bodies; column 0, the world, is ignored).
template <typename Scalar>
using BodyForcesTpl = Eigen::Matrix<Scalar, 6, Eigen::Dynamic>;
using BodyForces = BodyForcesTpl<double>;

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

// ---- Scalar-templated kernels (same contracts as the double functions above). ----

/// InverseDynamics(q, v, a[, F_ext]) for any scalar; F_ext (6 x num_bodies) may be null.
template <typename Scalar>
const VectorX<Scalar>& InverseDynamics(const Model& model, const ConstVectorRef<Scalar>& q,
                                       const ConstVectorRef<Scalar>& v,
                                       const ConstVectorRef<Scalar>& a,
                                       const NonDeduced<BodyForcesTpl<Scalar>>* F_ext,
                                       DataTpl<Scalar>* data);

/// InverseDynamicsAfterKinematics for any scalar.
template <typename Scalar>
const VectorX<Scalar>& InverseDynamicsAfterKinematics(
    const Model& model, const ConstVectorRef<Scalar>& v, const ConstVectorRef<Scalar>& a,
    const NonDeduced<BodyForcesTpl<Scalar>>* F_ext, DataTpl<Scalar>* data);

/// BiasTerm for any scalar.
template <typename Scalar>
const VectorX<Scalar>& BiasTerm(const Model& model, const ConstVectorRef<Scalar>& q,
                                const ConstVectorRef<Scalar>& v, DataTpl<Scalar>* data);

/// MassMatrix for any scalar.
template <typename Scalar>
const MatrixX<Scalar>& MassMatrix(const Model& model, const ConstVectorRef<Scalar>& q,
                                  DataTpl<Scalar>* data);

extern template const VectorX<double>& InverseDynamics<double>(
    const Model&, const ConstVectorRef<double>&, const ConstVectorRef<double>&,
    const ConstVectorRef<double>&, const BodyForcesTpl<double>*, DataTpl<double>*);
extern template const VectorX<double>& InverseDynamicsAfterKinematics<double>(
    const Model&, const ConstVectorRef<double>&, const ConstVectorRef<double>&,
    const BodyForcesTpl<double>*, DataTpl<double>*);
extern template const VectorX<double>& BiasTerm<double>(const Model&, const ConstVectorRef<double>&,
                                                        const ConstVectorRef<double>&,
                                                        DataTpl<double>*);
extern template const MatrixX<double>& MassMatrix<double>(const Model&,
                                                          const ConstVectorRef<double>&,
                                                          DataTpl<double>*);

}  // namespace idto
