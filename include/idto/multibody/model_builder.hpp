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
  double effort_limit{std::numeric_limits<double>::infinity()};
  double lower_limit{-std::numeric_limits<double>::infinity()};  ///< 1-DoF joints only
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
  /// axis, negative damping, or mass properties that are not physical (negative mass, inertia
  /// not symmetric positive semi-definite or violating the triangle inequality). A moving body
  /// must have positive mass unless a welded descendant gives it mass (checked by Build()).
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

  /// Validates (every moving body, after merging welded descendants, has positive mass and a
  /// positive-definite rotational inertia) and returns the model. The builder stays usable.
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

  std::string name_;
  std::vector<BodyEntry> bodies_;
  std::vector<FrameEntry> frames_;
  std::vector<GeometryInstance> geometries_;
  Eigen::Vector3d gravity_{0.0, 0.0, -9.81};
};

}  // namespace idto
