#pragma once

/// @file
/// Task measures of the quadruped (flat and hills) and Allegro hand examples (registered by name
/// in metrics.cpp). The criteria are documented in examples/quadruped/README.md,
/// examples/quadruped_hills/README.md and examples/allegro/README.md.

#include "idto/config/config.hpp"
#include "idto/solver/trajectory_optimizer.hpp"
#include "run/metrics.hpp"

namespace idto::examples {

/// Quadruped (flat ground or hills): the floating base must move forward, along the horizontal
/// direction from q_init to the last nominal configuration, by at least 20% of the nominal
/// distance, stay upright (tilt of the body's z axis below 0.3 rad at every step) and end at no
/// less than 2/3 of its initial height; and the legs, through contact, must be what moves it:
/// the base's unactuated generalized forces alone, acting on the robot with its joints locked
/// and free, would move it by at most 10% of the nominal distance and turn it by at most 0.1 rad
/// ("phantom" motion, see PhantomMotion in the .cpp).
TaskResult QuadrupedTask(const ExampleConfig& config, const Trajectory& solution);

/// Allegro hand and ball: the ball's final orientation must be within 0.1 rad of the last
/// nominal orientation and its centre within 2 cm of its initial position at every step (a
/// third of its radius: it stays in the hand); and the hand must be what turns it: the ball's
/// unactuated generalized forces alone would turn the free ball by at most 25% of the target
/// rotation and move it by at most 1 cm.
TaskResult AllegroTask(const ExampleConfig& config, const Trajectory& solution);

}  // namespace idto::examples
