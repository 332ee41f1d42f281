#pragma once

/// @file
/// Task measures of the bi-manual examples (examples/bimanual*, the IDTO paper's three bi-manual
/// tasks): two arms move, lift or balance a floating box. Registered in metrics.cpp.

#include "idto/config/config.hpp"
#include "idto/solver/trajectory_optimizer.hpp"
#include "run/metrics.hpp"

namespace idto::examples {

/// "bimanual": the box slid to a target pose on the table.
TaskResult BimanualMoveTask(const ExampleConfig& config, const Trajectory& solution);

/// "bimanual_lift": the box lifted off the table.
TaskResult BimanualLiftTask(const ExampleConfig& config, const Trajectory& solution);

/// "bimanual_balance": the box brought to, and held at, a pose on one of its edges.
TaskResult BimanualBalanceTask(const ExampleConfig& config, const Trajectory& solution);

}  // namespace idto::examples
