#pragma once

/// @file
/// Task measures of the spinner and hopper examples (registered by name in metrics.cpp). The
/// criteria are documented in examples/spinner/README.md and examples/hopper/README.md.

#include "idto/config/config.hpp"
#include "idto/solver/trajectory_optimizer.hpp"
#include "run/metrics.hpp"

namespace idto::examples {

/// Spinner: the spinner (the single unactuated revolute DoF) must gain at least 1.5 rad over the
/// horizon (the nominal asks for 2 rad) while its generalized force stays below 1e-3 N m at every
/// step, i.e. the finger turns it through contact alone.
TaskResult SpinnerTask(const ExampleConfig& config, const Trajectory& solution);

/// Hopper: the planar base must move at least 0.5 m forward (along the plane's first axis; the
/// nominal asks for 1 m), the hopper must be airborne for at least two steps (every foot sphere
/// above the ground and the ground's normal force below 10% of the weight), the base's
/// generalized forces must stay below 1e-2 N (N m) and the final pitch within 0.3 rad of the
/// initial one (it lands upright).
TaskResult HopperTask(const ExampleConfig& config, const Trajectory& solution);

}  // namespace idto::examples
