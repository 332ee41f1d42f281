#pragma once

/// @file
/// Collision shapes, each described in its own frame G (design.md §5b). This header is a leaf
/// (Eigen only) so that multibody::Model can hold collision geometry.

#include <string>
#include <variant>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/core/types.hpp"

namespace idto {

/// A sphere of `radius` centred at the frame origin.
struct Sphere {
  double radius{0.0};
};

/// A capsule: the set of points within `radius` of the segment from (0,0,-length/2) to
/// (0,0,length/2). `length` is the length of the segment (not counting the caps).
struct Capsule {
  double radius{0.0};
  double length{0.0};
};

/// A solid cylinder of `radius` along z, centred, from z = -length/2 to z = length/2.
struct Cylinder {
  double radius{0.0};
  double length{0.0};
};

/// A box with full side lengths `size`, centred at the frame origin.
struct Box {
  Eigen::Vector3d size{Eigen::Vector3d::Zero()};
};

/// The half-space z <= 0 of its frame; outward normal +z.
struct HalfSpace {};

/// Any of the shapes above.
using Shape = std::variant<Sphere, Capsule, Cylinder, Box, HalfSpace>;

/// "sphere", "capsule", "cylinder", "box" or "half_space".
std::string ShapeName(const Shape& shape);

/// A shape attached to a body of a Model (or to the world, body 0).
struct GeometryInstance {
  std::string name;                                       ///< unique within the model
  BodyIndex body{kWorldBody};                             ///< the body the shape moves with
  Eigen::Isometry3d X_BG{Eigen::Isometry3d::Identity()};  ///< pose of the shape frame in B
  Shape shape{Sphere{}};
};

}  // namespace idto
