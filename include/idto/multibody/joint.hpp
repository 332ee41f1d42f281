#pragma once

/// @file
/// Joint and base types (design.md §3).

#include <string>

namespace idto {

/// The joint connecting a body to its parent.
///
/// Coordinates, in the joint frame J (fixed in the parent, at the joint origin):
///  - kRevolute / kContinuous: q = angle about `axis` (continuous is unbounded), nq = nv = 1.
///  - kPrismatic: q = translation along `axis`, nq = nv = 1.
///  - kFixed: nq = nv = 0; the body is welded to its parent (merged for dynamics).
///  - kPlanar: motion in the plane normal to `axis` (unit n): q = v = [x, y, theta], where x, y
///    are translations along e1 = J's x axis projected onto the plane (J's y axis when n is
///    parallel to x) and e2 = n x e1, and theta is the rotation about n; nq = nv = 3.
///    For n = +z this is (x, y, yaw); for n = -y it is (x, z, pitch) in the sagittal plane.
///  - kFloating: q = [qw, qx, qy, qz, x, y, z] (quaternion of the body in J, position of the body
///    origin in J), v = [w, v] with w the angular velocity and v the velocity of the body origin,
///    both expressed in J (the world for a base); nq = 7, nv = 6.
enum class JointType { kFixed, kRevolute, kContinuous, kPrismatic, kPlanar, kFloating };

/// How the root of a model is attached to the world.
enum class BaseType { kFixed, kFloating, kPlanar };

/// Number of position coordinates of a joint type.
constexpr int JointNq(JointType type) {
  switch (type) {
    case JointType::kFixed:
      return 0;
    case JointType::kRevolute:
    case JointType::kContinuous:
    case JointType::kPrismatic:
      return 1;
    case JointType::kPlanar:
      return 3;
    case JointType::kFloating:
      return 7;
  }
  return 0;
}

/// Number of velocity coordinates of a joint type.
constexpr int JointNv(JointType type) { return type == JointType::kFloating ? 6 : JointNq(type); }

/// "fixed", "revolute", "continuous", "prismatic", "planar" or "floating".
std::string JointTypeName(JointType type);

}  // namespace idto
