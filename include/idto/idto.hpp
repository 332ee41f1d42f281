#pragma once

/// @file
/// Umbrella header: everything a user of idto needs.

#include "idto/version.hpp"

// core
#include "idto/core/errors.hpp"
#include "idto/core/parallel.hpp"
#include "idto/core/types.hpp"
// math
#include "idto/math/quaternion.hpp"
#include "idto/math/spatial.hpp"
// multibody
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/algorithms/jacobians.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/multibody/data.hpp"
#include "idto/multibody/joint.hpp"
#include "idto/multibody/model.hpp"
#include "idto/multibody/model_builder.hpp"
// geometry
#include "idto/geometry/shape.hpp"
// contact
#include "idto/contact/contact_law.hpp"
// parsers
#include "idto/parsers/urdf.hpp"
// sim
#include "idto/sim/mjcf.hpp"
