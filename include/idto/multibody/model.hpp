#pragma once

/// @file
/// The immutable multibody Model (design.md §4).

#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/core/types.hpp"
#include "idto/geometry/shape.hpp"
#include "idto/math/spatial.hpp"
#include "idto/multibody/joint.hpp"

namespace idto {

/// Mass properties of a body, in the body frame B.
struct BodyInertia {
  double mass{0.0};                                   ///< kg
  Eigen::Vector3d p_BBcm{Eigen::Vector3d::Zero()};    ///< centre of mass in B, m
  Eigen::Matrix3d I_BBcm_B{Eigen::Matrix3d::Zero()};  ///< rotational inertia about the centre
                                                      ///< of mass, expressed in B, kg m^2
};

class ModelBuilder;

/// A tree of rigid bodies connected by joints, with frames and collision geometry. Built by
/// ModelBuilder or a parser; immutable and copyable; share it by const reference across threads
/// and give each thread its own Data.
///
/// Body 0 is the world. Joint b (b >= 1) connects body b to parent(b) and carries the name given
/// at construction. Joint coordinates are stacked in body order (the depth-first order of the
/// tree for parsed models) into q (size nq) and v (size nv). Bodies welded by kFixed joints keep
/// their index, name, frame and geometry but are merged into their moving ancestor
/// (mobilized_body()) for dynamics.
class Model {
 public:
  /// An empty model (only the world); use ModelBuilder to make a real one.
  Model();

  /// A tag shared by this Model and its copies and distinct for every Model constructed: a Data
  /// records the tag of the model it was made for, and the algorithms check it.
  std::uint64_t tag() const { return tag_; }

  /// Number of generalized positions.
  int nq() const { return nq_; }
  /// Number of generalized velocities.
  int nv() const { return nv_; }
  /// Number of bodies including the world and bodies welded by fixed joints.
  int num_bodies() const { return static_cast<int>(body_name_.size()); }
  /// Number of joints (= num_bodies() - 1; joint b moves body b).
  int num_joints() const { return num_bodies() - 1; }
  /// Number of named frames (one per body, plus frames added to bodies).
  int num_frames() const { return static_cast<int>(frame_name_.size()); }
  /// Number of bodies that move relative to their parent (non-fixed joints), world excluded.
  int num_moving_bodies() const { return static_cast<int>(moving_bodies_.size()); }
  const std::string& name() const { return name_; }

  /// Body index by name; throws InvalidArgument naming the unknown body.
  BodyIndex GetBodyIndex(const std::string& name) const;
  bool HasBody(const std::string& name) const { return body_index_.count(name) > 0; }
  /// Joint index (= index of the body it moves) by joint name; throws on unknown names.
  JointIndex GetJointIndex(const std::string& name) const;
  bool HasJoint(const std::string& name) const { return joint_index_.count(name) > 0; }
  /// First index of the joint's coordinates in q / v; throws on unknown names.
  int GetPositionStart(const std::string& joint_name) const;
  int GetVelocityStart(const std::string& joint_name) const;
  /// Frame index by name (bodies are frames too); throws on unknown names.
  FrameIndex GetFrameIndex(const std::string& name) const;
  bool HasFrame(const std::string& name) const { return frame_index_.count(name) > 0; }

  const std::string& body_name(BodyIndex b) const { return body_name_[b]; }
  /// The body b is attached to (-1 for the world).
  BodyIndex parent(BodyIndex b) const { return parent_[b]; }
  /// The moving body whose dynamics carries b (b itself unless b is welded; 0 for bodies welded
  /// to the world).
  BodyIndex mobilized_body(BodyIndex b) const { return mobilized_[b]; }
  /// Pose of body b in the frame of mobilized_body(b) (identity for moving bodies).
  const RigidTransform& X_MB(BodyIndex b) const { return X_MB_[b]; }
  /// Mass of body b alone (as given to the builder).
  double body_mass(BodyIndex b) const { return body_inertia_[b].mass; }
  /// Mass properties of body b alone, as given to the builder.
  const BodyInertia& body_inertia(BodyIndex b) const { return body_inertia_[b]; }
  /// Spatial inertia of moving body b in its frame, including every body welded to it (zero for
  /// welded bodies and the world).
  const SpatialInertia& merged_inertia(BodyIndex b) const { return inertia_[b]; }
  /// Total mass of the model.
  double total_mass() const;

  const std::string& joint_name(JointIndex j) const { return joint_name_[j]; }
  JointType joint_type(JointIndex j) const { return joint_type_[j]; }
  int position_start(JointIndex j) const { return q_start_[j]; }
  int velocity_start(JointIndex j) const { return v_start_[j]; }
  int joint_nq(JointIndex j) const { return JointNq(joint_type_[j]); }
  int joint_nv(JointIndex j) const { return JointNv(joint_type_[j]); }
  /// Pose of joint j's frame J in the frame of parent(j) (which may be welded), X_PJ.
  const Eigen::Isometry3d& joint_frame_in_parent(JointIndex j) const { return X_PJ_[j]; }
  /// Unit axis of joint j in J (revolute/continuous/prismatic: the axis; planar: the normal).
  const Eigen::Vector3d& joint_axis(JointIndex j) const { return axis_[j]; }
  /// Viscous damping of joint j (every DoF of the joint).
  double joint_damping(JointIndex j) const { return joint_damping_[j]; }
  /// Name of the joint owning velocity coordinate i.
  const std::string& velocity_name(int i) const;
  /// Name of the joint owning position coordinate i.
  const std::string& position_name(int i) const;

  const std::string& frame_name(FrameIndex f) const { return frame_name_[f]; }
  BodyIndex frame_body(FrameIndex f) const { return frame_body_[f]; }
  /// Pose of frame f in its body.
  const Eigen::Isometry3d& X_BF(FrameIndex f) const { return X_BF_[f]; }

  /// Gravity in the world frame.
  const Eigen::Vector3d& gravity() const { return gravity_; }
  /// Joint damping per velocity coordinate (nv).
  const Eigen::VectorXd& damping() const { return damping_; }
  /// Joint limits, as given to ModelBuilder (JointSpec) or read from a URDF <limit>.
  /// Lower position limits per position coordinate (nq): the lower limit of revolute and
  /// prismatic joints, -infinity for every other coordinate and where none is given.
  const Eigen::VectorXd& position_lower_limits() const { return lower_limits_; }
  /// Upper position limits per position coordinate (nq; +infinity where none).
  const Eigen::VectorXd& position_upper_limits() const { return upper_limits_; }
  /// Velocity limits per velocity coordinate (nv; |v_i| <= limit; infinity where none). A joint's
  /// limit applies to each of its DoFs.
  const Eigen::VectorXd& velocity_limits() const { return velocity_limits_; }
  /// Effort limits per velocity coordinate (nv; |tau_i| <= limit; infinity where none).
  const Eigen::VectorXd& effort_limits() const { return effort_limits_; }
  /// Older names of position_lower_limits() and position_upper_limits().
  const Eigen::VectorXd& lower_position_limits() const { return lower_limits_; }
  const Eigen::VectorXd& upper_position_limits() const { return upper_limits_; }
  /// True for the velocity coordinates of floating and planar joints attached to the world
  /// (nv); the default unactuated DoFs of a problem.
  const std::vector<bool>& is_base_velocity() const { return is_base_velocity_; }
  /// True when the model has a floating joint (its q holds quaternions).
  bool has_quaternions() const { return !floating_joints_.empty(); }
  /// Joints of type kFloating, in order.
  const std::vector<JointIndex>& floating_joints() const { return floating_joints_; }

  /// Collision geometry, in the order added.
  const std::vector<GeometryInstance>& geometries() const { return geometries_; }
  GeometryIndex GetGeometryIndex(const std::string& name) const;

  /// q with every joint at zero (clamped into its limits) and identity quaternions.
  Eigen::VectorXd NeutralConfiguration() const;

  /// Throws InvalidArgument naming `where` and the argument unless q has nq entries (and
  /// likewise for v, nv). Used by the algorithms' public entry points.
  void CheckConfiguration(const char* where, const char* argument,
                          const Eigen::Ref<const Eigen::VectorXd>& q) const;
  void CheckVelocity(const char* where, const char* argument,
                     const Eigen::Ref<const Eigen::VectorXd>& v) const;

  // ---- Topology of the moving bodies, used by the algorithms (stable but low-level). ----
  /// Moving bodies (non-fixed joints) in increasing index order: parents before children.
  const std::vector<BodyIndex>& moving_bodies() const { return moving_bodies_; }
  /// For a moving body: its moving parent (0 = world).
  BodyIndex moving_parent(BodyIndex b) const { return moving_parent_[b]; }
  /// For a moving body: pose of its joint frame J in the frame of moving_parent(b).
  const RigidTransform& X_MJ(BodyIndex b) const { return X_MJ_[b]; }
  /// Whether X_MJ(b).R is the identity (skips a 3x3 product in the hot loops).
  bool X_MJ_is_translation(BodyIndex b) const { return X_MJ_translation_only_[b]; }
  /// Planar joints: in-plane unit directions e1, e2 (in J) of the x and y coordinates.
  const Eigen::Vector3d& planar_e1(BodyIndex b) const { return planar_e1_[b]; }
  const Eigen::Vector3d& planar_e2(BodyIndex b) const { return planar_e2_[b]; }

 private:
  friend class ModelBuilder;

  std::string name_{"model"};
  int nq_{0};
  int nv_{0};

  // Per body (index 0 = world).
  std::vector<std::string> body_name_;
  std::vector<BodyIndex> parent_;
  std::vector<BodyIndex> mobilized_;
  std::uint64_t tag_{0};
  std::vector<RigidTransform> X_MB_;
  std::vector<BodyInertia> body_inertia_;
  std::vector<SpatialInertia> inertia_;
  // Per joint (index = body index; entry 0 unused).
  std::vector<std::string> joint_name_;
  std::vector<JointType> joint_type_;
  std::vector<int> q_start_;
  std::vector<int> v_start_;
  std::vector<Eigen::Isometry3d> X_PJ_;
  std::vector<Eigen::Vector3d> axis_;
  std::vector<double> joint_damping_;
  std::vector<JointIndex> velocity_owner_;
  std::vector<JointIndex> position_owner_;
  // Moving-body topology.
  std::vector<BodyIndex> moving_bodies_;
  std::vector<BodyIndex> moving_parent_;
  std::vector<RigidTransform> X_MJ_;
  std::vector<bool> X_MJ_translation_only_;
  std::vector<Eigen::Vector3d> planar_e1_;
  std::vector<Eigen::Vector3d> planar_e2_;
  std::vector<JointIndex> floating_joints_;
  // Frames.
  std::vector<std::string> frame_name_;
  std::vector<BodyIndex> frame_body_;
  std::vector<Eigen::Isometry3d> X_BF_;
  // Whole-model vectors.
  Eigen::Vector3d gravity_{0.0, 0.0, -9.81};
  Eigen::VectorXd damping_;
  Eigen::VectorXd effort_limits_;
  Eigen::VectorXd velocity_limits_;
  Eigen::VectorXd lower_limits_;
  Eigen::VectorXd upper_limits_;
  std::vector<bool> is_base_velocity_;
  std::vector<GeometryInstance> geometries_;
  // Name look-ups.
  std::unordered_map<std::string, BodyIndex> body_index_;
  std::unordered_map<std::string, JointIndex> joint_index_;
  std::unordered_map<std::string, FrameIndex> frame_index_;
  std::unordered_map<std::string, GeometryIndex> geometry_index_;
};

}  // namespace idto
