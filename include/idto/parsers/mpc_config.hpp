#pragma once

/// @file
/// The `mpc:` section of an example configuration (see docs/config.md): controller rate,
/// iterations per step, PD+ gains, relative nominal coordinates, the plant and its options,
/// disturbances, and the closed-loop duration.

#include <string>

#include "idto/mpc/closed_loop.hpp"
#include "idto/mpc/controller.hpp"
#include "idto/parsers/config.hpp"
#include "idto/sim/plant.hpp"

namespace idto {

/// Everything `idto-run NAME --mpc` needs beyond the open-loop problem.
struct MpcConfig {
  mpc::MpcOptions controller;          ///< rate, iterations, gains, relative positions
  mpc::ClosedLoopOptions closed_loop;  ///< duration, plant step, latency, disturbances
  std::string plant{"mujoco"};         ///< "mujoco" (when built with it) or "builtin"
  sim::BuiltinPlantOptions builtin;    ///< builtin plant: contact law (stiff), time step
  sim::MujocoPlantOptions mujoco;      ///< MuJoCo plant: friction, time step
  int initial_iterations{50};          ///< iterations of the cold-start solve before t = 0
};

/// Parses config.mpc (YAML text). Keys (all optional):
///   control_rate (Hz, default 100), iterations_per_step (1), duration (s, 5),
///   initial_iterations (50), plant (mujoco|builtin; default mujoco when available),
///   plant_time_step (s, 1e-3), latency (solve_time|control_period|a delay in s),
///   kp, kd: a number for every actuated DoF, a list of nv, or {default: x, joint: value},
///   relative: [joint names, or {joint: [coordinate indices within the joint]}] whose position
///     coordinates keep their nominal offsets from the measured state,
///   orientation_lead: {floating joint: angle in rad > 0}: the joint's nominal orientation is
///     the measured one turned towards the problem's nominal by at most that angle
///     (mpc::MpcOptions::orientation_leads),
///   builtin_contact: {stiffness, smoothing, dissipation_velocity, friction_coefficient,
///                     stiction_velocity},
///   mujoco_friction (default: the scene's friction coefficient),
///   mujoco_torsional_friction, mujoco_rolling_friction (m, default 0: MuJoCo's torsional and
///     rolling friction on every pair, condim 4 / 6; sim::MujocoPlantOptions),
///   disturbances: [{body, start, duration, force: [fx, fy, fz]}],
///   problem: overrides of the open-loop `problem` keys for the controller (parsed by
///     LoadExampleConfig into ExampleConfig::mpc_problem).
/// Errors are FileError naming config.source_file, the key path "mpc.<key>", the value and what
/// was expected. The plant's pair filters come from the scene's contact options.
MpcConfig ParseMpcConfig(const ExampleConfig& config);

}  // namespace idto
