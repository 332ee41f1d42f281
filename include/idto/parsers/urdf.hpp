#pragma once

/// @file
/// URDF -> Model through urdfdom (urdfdom stays out of public headers), and scenes made of
/// several URDF models merged into one Model.
///
/// Conventions:
///  - Every URDF link becomes a body, added in depth-first order from the root; the children of a
///    link follow the document order of their joints. This is the order of the joints in q and v.
///    The body frame of a link is the URDF link frame: JointSpec::X_PJ is the joint's <origin>,
///    the axis is normalized.
///  - Joint types: revolute, continuous (one unbounded angle), prismatic, fixed (the child is
///    merged into its parent for dynamics but keeps its body, frame and geometry), floating
///    (JointType::kFloating) and planar (JointType::kPlanar, <axis> is the plane normal).
///  - <dynamics damping> gives the joint damping; <limit effort> the effort limit (effort="0"
///    means none); <limit lower/upper> the position limits of revolute and prismatic joints (a
///    <limit> without lower and upper leaves the joint unbounded). Velocity limits, friction,
///    <mimic>, <safety_controller>, <calibration>, <transmission> and visuals are ignored.
///  - <inertial>: mass, centre of mass (<origin xyz>) and the inertia tensor given in the frame
///    rotated by <origin rpy>: I_BBcm_B = R I R^T. A link without <inertial> has no mass, which is
///    fine when it is welded to (or carries a welded child with) mass, or welded to the world.
///  - Collision: <sphere>, <box> (full sizes) and <cylinder> (along z, full `length`) become
///    Sphere, Box and Cylinder with X_BG = the collision <origin>; meshes are skipped. A
///    geometry is named after its <collision name="...">, or "<link>_collision_<i>" with i the
///    position of the <collision> element in its link (counting skipped meshes); repeated names
///    get "_1", "_2", ... appended. With UrdfOptions::box_inscribed_spheres, each box is
///    replaced by its inscribed spheres, named "<geometry>_sphere<i>".
///  - Every body, joint, frame and geometry name gets UrdfOptions::prefix prepended.
///  - The root link is attached to the world as UrdfOptions says, by a joint named
///    prefix + root link + "_root_joint" (for example "ball_root_joint"). A root link named
///    "world" (without mass) instead stands for the world itself: its child joints attach to the
///    world body (their <origin> composed with X_WB), its collision geometry goes to the world,
///    and UrdfOptions::base is not used; with a non-empty prefix a frame prefix + "world" marks
///    X_WB on the world body.
///
/// Errors are FileError naming the file (or `source_name`) and the element, e.g.
/// "arm.urdf: joint 'elbow': <axis xyz> is (0, 0, 0); expected a non-zero finite vector".
/// urdfdom's own messages (which it reports through console_bridge) are captured during the parse
/// and forwarded in the message rather than printed. Options that are not valid (a zero planar
/// normal, a non-finite X_WB, a null builder) throw InvalidArgument.
///
/// Thread safety: the functions may be called from several threads; the urdfdom part of a parse
/// is serialized (console_bridge's output handler is global).

#include <optional>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/core/types.hpp"
#include "idto/geometry/signed_distance.hpp"
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
  /// When set, every <box> collision is replaced by the spheres that
  /// InscribedSpheres(box, *box_inscribed_spheres) places inside it (sharp corners make the
  /// contact normal jump, which spoils finite differences: the paper's Remark on collision
  /// geometries). The spheres keep the box's link
  /// and pose, and are named "<geometry>_sphere<i>" (prefix included), i = 0, 1, ... in the
  /// order InscribedSpheres returns them (the centre sphere last). Invalid options
  /// (num_per_axis < 2 or > 100, radius_fraction outside (0, 0.5]) throw InvalidArgument.
  std::optional<InscribedSpheresOptions> box_inscribed_spheres;
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
/// prefix). Returns the index of the root body (kWorldBody for a "world" root). Errors as
/// ParseUrdfFile; the file is checked completely before the builder is touched, but a name
/// already used in the builder by another model is only found while adding, and the builder
/// then keeps the bodies added so far.
BodyIndex AddUrdfFile(const std::string& path, const UrdfOptions& options, ModelBuilder* builder);

/// As AddUrdfFile, from URDF text.
BodyIndex AddUrdfString(const std::string& urdf_xml, const UrdfOptions& options,
                        ModelBuilder* builder, const std::string& source_name = "<urdf string>");

}  // namespace idto
