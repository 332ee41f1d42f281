#pragma once

/// @file
/// URDF -> Model through urdfdom (urdfdom stays out of public headers), and scenes made of
/// several URDF models merged into one Model.

#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/core/types.hpp"
#include "idto/multibody/joint.hpp"
#include "idto/multibody/model.hpp"
#include "idto/multibody/model_builder.hpp"

namespace idto {

/// How a URDF model is attached to the world.
struct UrdfOptions {
  /// kFixed welds the root link to the world at X_WB; kFloating gives it a floating joint
  /// (q = [qw qx qy qz x y z], design.md §3) whose frame J is X_WB; kPlanar a planar joint in the
  /// plane through X_WB normal to `planar_normal` (expressed in X_WB's frame).
  BaseType base{BaseType::kFixed};
  /// Pose of the root's joint frame in the world (for a fixed base: the pose of the root link).
  Eigen::Isometry3d X_WB{Eigen::Isometry3d::Identity()};
  /// Normal of the plane of a planar base (default z: coordinates x, y, yaw).
  Eigen::Vector3d planar_normal{Eigen::Vector3d::UnitZ()};
  /// Prepended to every body, joint, frame and geometry name of this model (scenes use it to
  /// keep names unique, e.g. "left_" and "right_").
  std::string prefix;
  /// Name of the model (used by ParseUrdf*; default: the URDF's robot name).
  std::string model_name;
};

/// Parses a URDF file into a Model. Throws FileError naming the file and the element (link or
/// joint) on a missing file, malformed XML, an unknown joint type, zero or negative mass or a
/// non-positive-definite inertia on a moving body, a zero joint axis, duplicate names, and a
/// model with no root or several roots.
Model ParseUrdfFile(const std::string& path, const UrdfOptions& options = {});

/// As ParseUrdfFile, from URDF text; `source_name` stands for the file name in error messages.
Model ParseUrdfString(const std::string& urdf_xml, const UrdfOptions& options = {},
                      const std::string& source_name = "<urdf string>");

/// Adds the model of a URDF file to `builder` (scenes: call once per model, each with its own
/// prefix). Returns the index of the root body. Errors as ParseUrdfFile.
BodyIndex AddUrdfFile(const std::string& path, const UrdfOptions& options, ModelBuilder* builder);

/// As AddUrdfFile, from URDF text.
BodyIndex AddUrdfString(const std::string& urdf_xml, const UrdfOptions& options,
                        ModelBuilder* builder, const std::string& source_name = "<urdf string>");

}  // namespace idto
