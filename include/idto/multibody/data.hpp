#pragma once

/// @file
/// Per-thread workspace for the multibody algorithms (design.md §4), templated on the scalar
/// type of the kernels: `Data` is `DataTpl<double>` (compiled once in src/multibody/data.cpp);
/// tests instantiate DataTpl with an automatic-differentiation scalar (include data-inl.hpp).

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/core/errors.hpp"
#include "idto/core/types.hpp"
#include "idto/math/scalar.hpp"
#include "idto/math/spatial.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

namespace internal {

/// Per moving body, world-frame quantities of ComputeRneaDerivatives (spatial vectors at the
/// world origin, expressed in the world). Composite entries sum over the body's subtree.
template <typename Scalar>
struct RneaDerivativeBodyTpl {
  SpatialMotionTpl<Scalar> V;    ///< spatial velocity of the body
  SpatialMotionTpl<Scalar> A;    ///< spatial acceleration (gravity as a base acceleration)
  SpatialMotionTpl<Scalar> V_F;  ///< velocity of the joint's "mixed" frame (parent + T v)
  SpatialMotionTpl<Scalar> vJ;   ///< joint velocity S v
  SpatialInertiaTpl<Scalar> Ic;  ///< composite inertia
  Matrix3<Scalar> B_sym;         ///< composite symmetric part of the angular block of B
  SpatialForceTpl<Scalar> h;     ///< composite momentum I V
  SpatialForceTpl<Scalar> F;     ///< composite force (inertial minus external)
  Vector3<Scalar> ext_n;         ///< composite external moments (about each body origin)
  Vector3<Scalar> ext_f;         ///< composite external forces
  Matrix3<Scalar> ext_P;         ///< composite sum of [p]x [f]x over the external forces
};

}  // namespace internal

/// Everything an algorithm writes, preallocated for one Model by the constructor; no algorithm
/// allocates afterwards. One Data per thread; a Data must only be used with the Model (or a copy
/// of it) it was made for.
template <typename Scalar>
class DataTpl {
 public:
  using Isometry3 = Eigen::Transform<Scalar, 3, Eigen::Isometry>;

  explicit DataTpl(const Model& model);

  /// The tag of the model this Data was made for (Model::tag()).
  std::uint64_t model_tag() const { return model_tag_; }

  /// Pose of body b in the world (after ForwardKinematics), any body including welded ones.
  Isometry3 X_WB(BodyIndex b) const;
  /// Rotation and origin of body b in the world.
  const Matrix3<Scalar>& R_WB(BodyIndex b) const { return X_WB_[b].R; }
  const Vector3<Scalar>& p_WB(BodyIndex b) const { return X_WB_[b].p; }
  /// Pose of body b in the world as a RigidTransform.
  const RigidTransformTpl<Scalar>& pose(BodyIndex b) const { return X_WB_[b]; }
  /// Spatial velocity of body b: [angular velocity; velocity of the body origin Bo], both
  /// expressed in the world (after ForwardKinematics with v).
  Vector6<Scalar> V_WB(BodyIndex b) const;
  /// Angular velocity of body b and velocity of its origin, expressed in the world.
  const Vector3<Scalar>& w_WB(BodyIndex b) const { return w_WB_[b]; }
  const Vector3<Scalar>& v_WBo(BodyIndex b) const { return v_WBo_[b]; }
  /// Pose of frame f in the world (after ForwardKinematics).
  Isometry3 X_WF(const Model& model, FrameIndex f) const;

  /// Generalized forces of the last InverseDynamics / BiasTerm / ComputeRneaDerivatives call
  /// (nv).
  VectorX<Scalar> tau;
  /// Mass matrix of the last MassMatrix or ComputeRneaDerivatives call (nv x nv, both triangles
  /// filled).
  MatrixX<Scalar> M;
  /// Accelerations of the last ForwardDynamics call (nv).
  VectorX<Scalar> a;
  /// ComputeRneaDerivatives: d tau / d q in the raw coordinates of q (nv x nq; quaternion
  /// columns included), = dtau_dq_tangent * N+(q).
  MatrixX<Scalar> dtau_dq;
  /// ComputeRneaDerivatives: d tau / d q in the tangent space (nv x nv): column k is the
  /// derivative along q(eps) with dq/deps = N(q) e_k (for a floating joint: a rotation about the
  /// joint frame's axes, applied on the left, and a translation along them).
  MatrixX<Scalar> dtau_dq_tangent;
  /// ComputeRneaDerivatives: d tau / d v (nv x nv).
  MatrixX<Scalar> dtau_dv;

  // ---- Implementation buffers (public for the algorithms; not part of the stable API). ----
  /// World poses of all bodies (ForwardKinematics).
  std::vector<RigidTransformTpl<Scalar>> X_WB_;
  /// World angular velocity and origin velocity of all bodies (ForwardKinematics with v).
  std::vector<Vector3<Scalar>> w_WB_;
  std::vector<Vector3<Scalar>> v_WBo_;
  /// Moving bodies: pose in the moving parent, X_{parent,i}(q).
  std::vector<RigidTransformTpl<Scalar>> X_pi_;
  /// Moving bodies: rotation of the body in its joint frame (floating and planar joints).
  std::vector<Matrix3<Scalar>> R_JB_;
  /// Moving bodies: spatial velocity, acceleration and force in body coordinates.
  std::vector<SpatialMotionTpl<Scalar>> vel_;
  std::vector<SpatialMotionTpl<Scalar>> acc_;
  std::vector<SpatialForceTpl<Scalar>> force_;
  /// Moving bodies: composite inertia (CRBA) or articulated inertia (ABA).
  std::vector<SpatialInertiaTpl<Scalar>> composite_;
  /// CRBA scratch: force columns (6 x 6).
  Matrix6<Scalar> F_;
  /// Forward dynamics: Cholesky factor of M.
  Eigen::LLT<MatrixX<Scalar>> llt_;
  /// Scratch vector (nv).
  VectorX<Scalar> scratch_v_;
  /// ComputeRneaDerivatives: per moving body world-frame quantities.
  std::vector<internal::RneaDerivativeBodyTpl<Scalar>> deriv_body_;
  /// ComputeRneaDerivatives, 6 x nv each, column per velocity coordinate (world frame, at the
  /// world origin): motion subspace S, dV/dq (u), dA/dq (w) and dA/dv (u') of the joint.
  Eigen::Matrix<Scalar, 6, Eigen::Dynamic> S_;
  Eigen::Matrix<Scalar, 6, Eigen::Dynamic> dV_dq_;
  Eigen::Matrix<Scalar, 6, Eigen::Dynamic> dA_dq_;
  Eigen::Matrix<Scalar, 6, Eigen::Dynamic> dA_dv_;

 private:
  std::uint64_t model_tag_{0};
};

namespace internal {

/// Throws InvalidArgument naming `where` unless `data` is not null and was made for `model` or a
/// copy of it (its buffers are sized for that model; another model's would be overrun).
template <typename Scalar>
inline void CheckData(const Model& model, const char* where, const DataTpl<Scalar>* data) {
  if (data == nullptr) {
    ThrowInvalidArgument(where, "data", "null", "a Data made for this model: DataTpl(model)");
  }
  if (data->model_tag() != model.tag()) {
    ThrowInvalidArgument(where, "data",
                         "made for another model (model tag " + std::to_string(data->model_tag()) +
                             ", this one's " + std::to_string(model.tag()) + ")",
                         "a Data made for this model or a copy of it: DataTpl(model)");
  }
}

}  // namespace internal

using Data = DataTpl<double>;

extern template class DataTpl<double>;

}  // namespace idto
