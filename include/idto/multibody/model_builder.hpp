#pragma once

/// @file
/// Building a Model in code (the URDF parser uses this too).

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/core/types.hpp"
#include "idto/geometry/shape.hpp"
#include "idto/multibody/joint.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// The joint that attaches a new body to its parent.
struct JointSpec {
  std::string name;  ///< unique within the model
  JointType type{JointType::kRevolute};
  Eigen::Isometry3d X_PJ{Eigen::Isometry3d::Identity()};  ///< joint frame J in the parent P
  Eigen::Vector3d axis{Eigen::Vector3d::UnitZ()};         ///< in J; normalized by the builder
  double damping{0.0};                                    ///< N·m·s/rad or N·s/m, every DoF
  /// Effort limit (N·m or N), every DoF of the joint; infinity = none.
  double effort_limit{std::numeric_limits<double>::infinity()};
  /// Velocity limit (rad/s or m/s), every DoF of the joint; infinity = none.
  double velocity_limit{std::numeric_limits<double>::infinity()};
  /// Position limits (rad or m) of revolute and prismatic joints; ±infinity = none.
  double lower_limit{-std::numeric_limits<double>::infinity()};
  double upper_limit{std::numeric_limits<double>::infinity()};
};

/// Accumulates bodies, joints, frames and geometry; `Build()` validates and returns an
/// immutable Model.
///
/// The body frame B of a new body coincides with its joint frame J at q = 0:
/// X_PB(q) = X_PJ · X_J(q). Bodies must be added after their parent; body indices are the order
/// of addition (1, 2, ...; 0 is the world), which is also the order of joints in q and v. The URDF
/// parser adds bodies in depth-first order. Bodies attached by kFixed joints keep their index,
/// name, frames and geometry, but are merged into their moving ancestor for dynamics.
class ModelBuilder {
 public:
  explicit ModelBuilder(std::string model_name = "model");

  /// Adds a body attached to `parent` by `joint`. Throws InvalidArgument (naming the body and
  /// the value) on a duplicate body or joint name, an unknown parent, a non-finite pose, a zero
  /// axis, negative damping, limits that are NaN, non-positive (effort, velocity) or inverted
  /// (lower > upper), a field the joint type does not use that is not at its default (finite
  /// position limits on a joint other than revolute or prismatic; damping, an effort or a
  /// velocity limit on a fixed joint: they would be dropped), or mass properties that are not
  /// physical (negative mass, inertia not symmetric positive semi-definite or violating the
  /// triangle inequality). The limits are set here, through `joint` (JointSpec::lower_limit,
  /// upper_limit, velocity_limit, effort_limit). A body may be a point mass (zero rotational
  /// inertia) or even massless, as long as the model's joint-space mass matrix is positive
  /// definite (checked by Build()).
  BodyIndex AddBody(const std::string& name, const BodyInertia& inertia, BodyIndex parent,
                    const JointSpec& joint);

  /// Adds a named frame F fixed in `body` at X_BF. Every body also has a frame of its own name.
  FrameIndex AddFrame(const std::string& name, BodyIndex body, const Eigen::Isometry3d& X_BF);

  /// Adds collision geometry to `body` (kWorldBody for the world). Names must be unique.
  GeometryIndex AddGeometry(const std::string& name, BodyIndex body, const Eigen::Isometry3d& X_BG,
                            const Shape& shape);

  /// Gravity in the world frame, default (0, 0, -9.81).
  void SetGravity(const Eigen::Vector3d& gravity);

  /// Model name (the URDF parser sets the robot name).
  void SetName(const std::string& name);

  /// Number of bodies so far, including the world.
  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  /// Index of a body added so far (throws InvalidArgument on an unknown name).
  BodyIndex GetBodyIndex(const std::string& name) const;
  bool HasBody(const std::string& name) const;

  /// Validates and returns the model; the builder stays usable. Every moving body must carry
  /// mass (itself, or the bodies welded to it or moving below it), and the joint-space mass
  /// matrix M(q) at the neutral configuration must be positive definite: point masses (a
  /// pendulum bob) and massless intermediate bodies are fine when the bodies they carry give
  /// every DoF inertia, a point mass on a free joint or on its own rotation axis is not. Throws
  /// InvalidArgument naming the body or joint otherwise.
  Model Build() const;

 private:
  struct BodyEntry {
    std::string name;
    BodyIndex parent{-1};
    BodyInertia inertia;
    JointSpec joint;
  };
  struct FrameEntry {
    std::string name;
    BodyIndex body{kWorldBody};
    Eigen::Isometry3d X_BF{Eigen::Isometry3d::Identity()};
  };

  void CheckNewName(const char* where, const std::string& kind, const std::string& name) const;
  // Parts of Build().
  void FillJointVectors(Model* model) const;
  void FillFramesAndGeometry(Model* model) const;

  std::string name_;
  std::vector<BodyEntry> bodies_;
  std::vector<FrameEntry> frames_;
  std::vector<GeometryInstance> geometries_;
  Eigen::Vector3d gravity_{0.0, 0.0, -9.81};
};

/// A copy of `model` whose body b has its mass and its rotational inertia about its centre of
/// mass multiplied by scale[b] (scale: num_bodies entries; scale[0], the world's, is not used;
/// the others finite and > 0, else InvalidArgument naming the entry). Joints, limits, damping,
/// frames, geometry, gravity and name are copied. For a plant with other masses than a
/// controller's model (idto-campaign's mass mismatch) and for a controller that plans with
/// other masses than the scene's (`mpc.model_mass_scale`).
Model ScaleBodyInertias(const Model& model, const std::vector<double>& scale);

}  // namespace idto
