#pragma once

/// @file
/// Forward kinematics and configuration-space maps (quaternion joints).
///
/// ForwardKinematics, CalcNMatrix and CalcNplusMatrix are templates on the scalar type, defined
/// in kinematics-inl.hpp; the double instantiation is compiled once in the library (extern
/// template below). The non-template double overloads are the stable entry points; the templates
/// deduce Scalar from the DataTpl<Scalar>* (or output matrix) argument only.

#include <Eigen/Core>

#include "idto/math/scalar.hpp"
#include "idto/multibody/data.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// Body poses for configuration q (nq). Velocities in data are left unchanged.
void ForwardKinematics(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q, Data* data);

/// Body poses and spatial velocities for q (nq) and v (nv).
void ForwardKinematics(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                       const Eigen::Ref<const Eigen::VectorXd>& v, Data* data);

/// N(q) (nq x nv): qdot = N(q) v. Identity except for floating joints, whose quaternion block is
/// 0.5 * [-w^T; w*I - [w]x]-style (the map from the angular velocity in J to the quaternion rate).
void CalcNMatrix(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                 Eigen::MatrixXd* N);

/// N+(q) (nv x nq), the left pseudo-inverse of N(q): N+(q) N(q) = I for unit quaternions.
void CalcNplusMatrix(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                     Eigen::MatrixXd* Nplus);

/// Scalar-templated ForwardKinematics(q): body poses (q: nq).
template <typename Scalar>
void ForwardKinematics(const Model& model, const ConstVectorRef<Scalar>& q, DataTpl<Scalar>* data);

/// Scalar-templated ForwardKinematics(q, v): body poses and velocities (q: nq, v: nv).
template <typename Scalar>
void ForwardKinematics(const Model& model, const ConstVectorRef<Scalar>& q,
                       const ConstVectorRef<Scalar>& v, DataTpl<Scalar>* data);

/// Scalar-templated N(q) (nq x nv, resized).
template <typename Scalar>
void CalcNMatrix(const Model& model, const ConstVectorRef<Scalar>& q, MatrixX<Scalar>* N);

/// Scalar-templated N+(q) (nv x nq, resized).
template <typename Scalar>
void CalcNplusMatrix(const Model& model, const ConstVectorRef<Scalar>& q, MatrixX<Scalar>* Nplus);

extern template void ForwardKinematics<double>(const Model&, const ConstVectorRef<double>&,
                                               DataTpl<double>*);
extern template void ForwardKinematics<double>(const Model&, const ConstVectorRef<double>&,
                                               const ConstVectorRef<double>&, DataTpl<double>*);
extern template void CalcNMatrix<double>(const Model&, const ConstVectorRef<double>&,
                                         MatrixX<double>*);
extern template void CalcNplusMatrix<double>(const Model&, const ConstVectorRef<double>&,
                                             MatrixX<double>*);

/// q_next = q "+" v * dt: exact exponential integration on quaternions (result normalized).
/// q: nq, v: nv, q_next: nq (may alias q).
void Integrate(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
               const Eigen::Ref<const Eigen::VectorXd>& v, double dt, Eigen::VectorXd* q_next);

/// v (nv) such that Integrate(q0, v, 1) = q1 (the shortest rotation for quaternions).
void Difference(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q1,
                const Eigen::Ref<const Eigen::VectorXd>& q0, Eigen::VectorXd* v);

/// Normalizes every quaternion in q (nq) in place.
void NormalizeQuaternions(const Model& model, Eigen::VectorXd* q);

}  // namespace idto
