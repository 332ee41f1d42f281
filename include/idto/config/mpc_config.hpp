#pragma once

/// @file
/// The `mpc:` section of an example configuration (see docs/config.md): controller rate,
/// iterations per step, PD+ gains, relative nominal coordinates, the plant and its options,
/// disturbances, and the closed-loop duration.

#include <string>

#include "idto/mpc/closed_loop.hpp"
#include "idto/mpc/controller.hpp"
#include "idto/sim/plant.hpp"

namespace idto {

struct ExampleConfig;

/// Everything `idto-run NAME --mpc` needs beyond the open-loop problem.
struct MpcConfig {
  mpc::MpcOptions controller;          ///< rate, iterations, gains, relative positions
  mpc::ClosedLoopOptions closed_loop;  ///< duration, plant step, latency, disturbances
  std::string plant{"mujoco"};         ///< "mujoco" (when built with it) or "builtin"
  sim::BuiltinPlantOptions builtin;    ///< builtin plant: contact law (stiff), time step
  sim::MujocoPlantOptions mujoco;      ///< MuJoCo plant: friction, time step
  int initial_iterations{50};          ///< iterations of the cold-start solve before t = 0
};

/// The `mpc:` section of `config`: config.mpc, read by LoadExampleConfig with the rest of the
/// file, or the defaults below (for config.model and the scene's contact) when the file has no
/// `mpc` section. Keys (all optional):
///   control_rate (Hz, default 100), iterations_per_step (integer >= 1, default 1),
///   duration (s, 5; at least one plant step), initial_iterations (integer >= 0, 50),
///   plant (mujoco|builtin; default mujoco when available), plant_time_step (s, 1e-3),
///   latency (solve_time|control_period|a delay in s),
///   latency_jitter (s >= 0, default 0: each re-plan's latency plus uniform [0, jitter]),
///   sensor_noise: {position (rad or m), velocity_relative, velocity_floor (rad/s or m/s)}
///     (mpc::SensorNoise; default none), seed (integer >= 0, default 0: the noise and jitter),
///   kp, kd: a number for every DoF, a list of nv, or {default: x, joint: value or list},
///   relative: [joint names, or {joint: [coordinate indices within the joint]}] whose position
///     coordinates keep their nominal offsets from the measured state,
///   relative_goal: {joint: goal or [goals]}: where those coordinates' targets stop, one goal
///     per coordinate of the joint listed in `relative` (mpc::MpcOptions::relative_goals),
///   orientation_lead: {floating joint: angle in rad > 0}: the joint's nominal orientation is
///     the measured one turned towards the problem's nominal by at most that angle
///     (mpc::MpcOptions::orientation_leads),
///   builtin_contact: {stiffness, smoothing, dissipation_velocity, friction_coefficient,
///                     stiction_velocity},
///   mujoco_friction (default: the scene's friction coefficient),
///   mujoco_torsional_friction, mujoco_rolling_friction (m, default 0: MuJoCo's torsional and
///     rolling friction on every pair, condim 4 / 6; sim::MujocoPlantOptions),
///   mujoco_cone: elliptic (default) | pyramidal (sim::MujocoPlantOptions::friction_cone),
///   disturbances: [{body, start, duration, force: [fx, fy, fz]}],
///   problem, contact, solver: the controller's own problem, contact law parameters and solver
///     options (ExampleConfig::mpc_problem and ExampleConfig::mpc_solver).
/// Errors (thrown by LoadExampleConfig) are FileError naming the file, the key path
/// "mpc.<key>", the line in the file, the value and what was expected. The plant's pair
/// filters come from the scene's contact options.
MpcConfig ParseMpcConfig(const ExampleConfig& config);

}  // namespace idto
