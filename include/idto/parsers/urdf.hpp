#pragma once

/// @file
/// URDF -> Model through urdfdom (urdfdom stays out of public headers), and scenes made of
/// several URDF models merged into one Model.
///
/// What is read, what is refused and why: docs/urdf.md. In short:
///  - Every URDF link becomes a body, added in depth-first order from the root; the children of a
///    link follow the document order of their joints. This is the order of the joints in q and v.
///    The body frame of a link is the URDF link frame: JointSpec::X_PJ is the joint's <origin>,
///    the axis is normalized.
///  - Joint types: revolute, continuous (one unbounded angle), prismatic, fixed (the child is
///    merged into its parent for dynamics but keeps its body, frame and geometry), floating
///    (JointType::kFloating) and planar (JointType::kPlanar, <axis> is the plane normal).
///  - <dynamics damping> gives the joint damping. <limit lower upper velocity effort> gives the
///    joint limits (Model::position_lower_limits(), position_upper_limits(), velocity_limits(),
///    effort_limits()); an absent <limit> or attribute means no limit (a revolute joint without
///    <limit> is unbounded, with unlimited effort), and velocity="0" or effort="0" mean none.
///    On a fixed joint, <axis>, <limit> and <dynamics> are checked and have no effect.
///  - <inertial>: mass, centre of mass (<origin xyz>) and the inertia tensor given in the frame
///    rotated by <origin rpy>: I_BBcm_B = R I R^T. A link without <inertial> has no mass. Point
///    masses (zero rotational inertia) and massless links are accepted when the model's
///    joint-space mass matrix is positive definite (ModelBuilder::Build()).
///  - Collision: <sphere>, <box> (full sizes), <cylinder> and <capsule> / <drake:capsule> (both
///    along z, full `length` between the cap centres for the capsule) become Sphere, Box,
///    Cylinder and Capsule with X_BG = the collision <origin>. A geometry is named after its
///    <collision name="...">, or "<link>_collision_<i>" with i the position of the <collision>
///    element in its link; repeated names get "_1", "_2", ... appended, with a UrdfWarning.
///    With UrdfOptions::box_inscribed_spheres, each box is replaced by its inscribed spheres,
///    named "<geometry>_sphere<i>".
///  - Nothing is silently dropped: an element idto cannot represent (a <mesh> or unknown shape,
///    an unknown element, <mimic>) is a FileError naming the file, the link or joint and the
///    element. So are an unknown attribute, text or a child element in an element that holds
///    values (<origin ryp="...">, <axis xzy="...">, <limit lowr="...">, <origin>0 0 1</origin>:
///    the value would silently take its default), several <mass> or <inertia> in one
///    <inertial>, and a second top-level element besides <robot>. An unknown attribute of
///    <robot>, <link>, <joint>, <inertial>, <collision>, <visual> or <geometry> gives a
///    UrdfWarning. Visual geometry is read and checked but not kept; an unsupported visual
///    element (a visual <mesh>) is an error too unless UrdfOptions::unsupported_visuals_as_warnings
///    is set. Elements ignored by design (<transmission>, <gazebo>, <safety_controller>,
///    <calibration>, <dynamics friction>, <drake:proximity_properties>, mass on a link welded to
///    the world) give a UrdfWarning.
///  - Every body, joint, frame and geometry name gets UrdfOptions::prefix prepended.
///  - The root link is attached to the world as UrdfOptions says, by a joint named
///    prefix + root link + "_root_joint" (for example "ball_root_joint"). A root link named
///    "world" instead stands for the world itself: its child joints attach to the world body
///    (their <origin> composed with X_WB), its collision geometry goes to the world, and
///    UrdfOptions::base must be kFixed (a floating or planar base could not apply: FileError);
///    with a non-empty prefix a frame prefix + "world" marks X_WB on the world body. Joints may
///    name a parent link "world" that the file does not declare (the implicit world of many
///    URDFs); mass on a world link is ignored with a warning.
///
/// Errors are FileError naming the file (or `source_name`), the element, and the value found,
/// e.g. "arm.urdf: joint 'elbow': <axis xyz> is (0, 0, 0); expected a non-zero finite vector" or
/// "arm.urdf: link 'foot': <mass value> is \"1O\"; expected a number". Elements nested deeper than
/// kMaxUrdfDepth are refused before parsing. Options that are not valid (a zero planar normal, a
/// planar normal without a planar base, a non-finite X_WB, a null builder) throw
/// InvalidArgument.
///
/// Thread safety: the functions may be called from several threads.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/core/types.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "idto/multibody/joint.hpp"
#include "idto/multibody/model.hpp"
#include "idto/multibody/model_builder.hpp"

namespace idto {

/// Elements may be nested at most this deep in a URDF document (a URDF needs about 5).
constexpr int kMaxUrdfDepth = 256;

/// Something in a URDF that idto did not use: ignored by design, or an unsupported visual-only
/// element downgraded by UrdfOptions::unsupported_visuals_as_warnings.
struct UrdfWarning {
  std::string file;     ///< the file (or source name)
  std::string element;  ///< e.g. "link 'foot'" or "joint 'knee'"
  std::string message;  ///< what was found and what idto does with it
  /// "file: element: message".
  std::string ToString() const { return file + ": " + element + ": " + message; }
};

/// How a URDF model is attached to the world.
struct UrdfOptions {
  /// kFixed welds the root link to the world at X_WB; kFloating gives it a floating joint
  /// (q = [qw qx qy qz x y z], design.md §3) whose frame J is X_WB; kPlanar a planar joint in the
  /// plane through X_WB normal to `planar_normal` (expressed in X_WB's frame).
  BaseType base{BaseType::kFixed};
  /// Pose of the root's joint frame in the world (for a fixed base: the pose of the root link).
  Eigen::Isometry3d X_WB{Eigen::Isometry3d::Identity()};
  /// Normal of the plane of a planar base (default z: coordinates x, y, yaw). Another value
  /// with a base that is not kPlanar is an InvalidArgument (it would not be used).
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
  /// By default a visual element idto cannot read (a <visual> <mesh>, an unknown shape or an
  /// unknown element inside <visual>) is an error like any other. When set, such visual-only
  /// elements give a UrdfWarning (naming file, link and element) instead; the warnings are
  /// collected in the `warnings` argument of the parse functions, which must then be given
  /// (InvalidArgument otherwise). Collision and inertial elements are never downgraded.
  bool unsupported_visuals_as_warnings{false};
};

/// Parses a URDF file into a Model. Throws FileError naming the file, the element (link or
/// joint) and the value found on a missing file, malformed or too deeply nested XML, a number
/// that does not parse, an unknown joint type, an unsupported element (see above), a negative or
/// non-finite mass, an inertia that is not physical, a singular joint-space mass matrix, a zero
/// joint axis, inverted limits, duplicate names, and a model with no root or several roots.
/// Warnings (see UrdfWarning) are appended to `warnings` when it is not null.
Model ParseUrdfFile(const std::string& path, const UrdfOptions& options = {},
                    std::vector<UrdfWarning>* warnings = nullptr);

/// As ParseUrdfFile, from URDF text; `source_name` stands for the file name in error messages.
Model ParseUrdfString(const std::string& urdf_xml, const UrdfOptions& options = {},
                      const std::string& source_name = "<urdf string>",
                      std::vector<UrdfWarning>* warnings = nullptr);

/// Adds the model of a URDF file to `builder` (scenes: call once per model, each with its own
/// prefix). Returns the index of the root body (kWorldBody for a "world" root). Errors as
/// ParseUrdfFile; the file is checked completely before the builder is touched, but a name
/// already used in the builder by another model is only found while adding, and the builder
/// then keeps the bodies added so far.
/// Warnings are appended to `warnings` when it is not null.
BodyIndex AddUrdfFile(const std::string& path, const UrdfOptions& options, ModelBuilder* builder,
                      std::vector<UrdfWarning>* warnings = nullptr);

/// As AddUrdfFile, from URDF text.
BodyIndex AddUrdfString(const std::string& urdf_xml, const UrdfOptions& options,
                        ModelBuilder* builder, const std::string& source_name = "<urdf string>",
                        std::vector<UrdfWarning>* warnings = nullptr);

}  // namespace idto
