#pragma once

/// @file
/// Closed-loop task measures (`idto-run NAME --mpc`): what the robot did in the plant over the
/// whole run, judged against the MPC targets of docs/mpc.md (spinner >= 3 rad in 5 s, quadruped
/// >= 0.3 m/s over 10 s without falling, ball turned 180 degrees within 20 s, box lifted >= 5 cm
/// and held). Examples without a closed-loop measure get the open-loop one (metrics.hpp) on the
/// log resampled at the planner's time step.

#include <vector>

#include <Eigen/Core>

#include "idto/config/config.hpp"
#include "idto/mpc/closed_loop.hpp"
#include "run/metrics.hpp"

namespace idto::examples {

/// Evaluates the closed-loop run `log` of `config` (its `mpc` problem when it has one). A plant
/// failure (log.failure) is never a success.
TaskResult EvaluateClosedLoopTask(const ExampleConfig& config, const mpc::ClosedLoopLog& log);

/// The log at times 0, dt, 2 dt, ... (the first log entry at or after each), as a Trajectory
/// (q, v, and u as tau).
Trajectory ResampleClosedLoop(const mpc::ClosedLoopLog& log, double dt);

}  // namespace idto::examples
