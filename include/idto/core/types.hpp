#pragma once

/// @file
/// Basic index types shared by all modules.

namespace idto {

/// Index of a body in a Model. Body 0 is the world.
using BodyIndex = int;
/// Index of a joint in a Model (joint i connects body i to its parent).
using JointIndex = int;
/// Index of a frame in a Model (every body has a frame with its own name; fixed links add more).
using FrameIndex = int;
/// Index of a collision geometry in a Model.
using GeometryIndex = int;

/// The world body.
inline constexpr BodyIndex kWorldBody = 0;

}  // namespace idto
