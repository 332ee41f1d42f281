#pragma once

/// @file
/// Per-thread workspace for the multibody algorithms (design.md §4).

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/core/types.hpp"
#include "idto/math/spatial.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// Everything an algorithm writes, preallocated for one Model by the constructor; no algorithm
/// allocates afterwards. One Data per thread; a Data must only be used with the Model (or a copy
/// of it) it was made for.
class Data {
 public:
  explicit Data(const Model& model);

  /// Pose of body b in the world (after ForwardKinematics), any body including welded ones.
  Eigen::Isometry3d X_WB(BodyIndex b) const;
  /// Rotation and origin of body b in the world.
  const Eigen::Matrix3d& R_WB(BodyIndex b) const { return X_WB_[b].R; }
  const Eigen::Vector3d& p_WB(BodyIndex b) const { return X_WB_[b].p; }
  /// Pose of body b in the world as a RigidTransform.
  const RigidTransform& pose(BodyIndex b) const { return X_WB_[b]; }
  /// Spatial velocity of body b: [angular velocity; velocity of the body origin Bo], both
  /// expressed in the world (after ForwardKinematics with v).
  Eigen::Matrix<double, 6, 1> V_WB(BodyIndex b) const;
  /// Angular velocity of body b and velocity of its origin, expressed in the world.
  const Eigen::Vector3d& w_WB(BodyIndex b) const { return w_WB_[b]; }
  const Eigen::Vector3d& v_WBo(BodyIndex b) const { return v_WBo_[b]; }
  /// Pose of frame f in the world (after ForwardKinematics).
  Eigen::Isometry3d X_WF(const Model& model, FrameIndex f) const;

  /// Generalized forces of the last InverseDynamics / BiasTerm call (nv).
  Eigen::VectorXd tau;
  /// Mass matrix of the last MassMatrix call (nv x nv, both triangles filled).
  Eigen::MatrixXd M;
  /// Accelerations of the last ForwardDynamics call (nv).
  Eigen::VectorXd a;

  // ---- Implementation buffers (public for the algorithms; not part of the stable API). ----
  /// World poses of all bodies (ForwardKinematics).
  std::vector<RigidTransform> X_WB_;
  /// World angular velocity and origin velocity of all bodies (ForwardKinematics with v).
  std::vector<Eigen::Vector3d> w_WB_;
  std::vector<Eigen::Vector3d> v_WBo_;
  /// Moving bodies: pose in the moving parent, X_{parent,i}(q).
  std::vector<RigidTransform> X_pi_;
  /// Moving bodies: rotation of the body in its joint frame (floating and planar joints).
  std::vector<Eigen::Matrix3d> R_JB_;
  /// Moving bodies: spatial velocity, acceleration and force in body coordinates.
  std::vector<SpatialMotion> vel_;
  std::vector<SpatialMotion> acc_;
  std::vector<SpatialForce> force_;
  /// Moving bodies: composite inertia (CRBA) or articulated inertia (ABA).
  std::vector<SpatialInertia> composite_;
  /// CRBA scratch: force columns (6 x 6).
  Eigen::Matrix<double, 6, 6> F_;
  /// Forward dynamics: Cholesky factor of M.
  Eigen::LLT<Eigen::MatrixXd> llt_;
  /// Scratch vector (nv).
  Eigen::VectorXd scratch_v_;
};

}  // namespace idto
