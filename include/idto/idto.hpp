#pragma once

/// @file
/// Umbrella header: everything a user of idto needs.

#include "idto/version.hpp"

// core
#include "idto/core/errors.hpp"
#include "idto/core/types.hpp"
// math
#include "idto/math/penta_diagonal_matrix.hpp"
#include "idto/math/quaternion.hpp"
#include "idto/math/spatial.hpp"
// multibody
#include "idto/multibody/algorithms/discrete_velocity.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/algorithms/jacobians.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/multibody/algorithms/rnea_derivatives.hpp"
#include "idto/multibody/data.hpp"
#include "idto/multibody/joint.hpp"
#include "idto/multibody/model.hpp"
#include "idto/multibody/model_builder.hpp"
// geometry
#include "idto/geometry/shape.hpp"
#include "idto/geometry/signed_distance.hpp"
// parsers
#include "idto/parsers/urdf.hpp"
// contact
#include "idto/contact/contact_engine.hpp"
#include "idto/contact/contact_law.hpp"
#include "idto/contact/inverse_dynamics_with_contact.hpp"
// problem and solver
#include "idto/problem/derivative_method.hpp"
#include "idto/problem/problem_definition.hpp"
#include "idto/problem/trajectory_state.hpp"
#include "idto/problem/transcription.hpp"
#include "idto/solver/banded_kkt.hpp"
#include "idto/solver/solver_options.hpp"
#include "idto/solver/solver_summary.hpp"
#include "idto/solver/trajectory_optimizer.hpp"
// mpc
#include "idto/mpc/controller.hpp"
#include "idto/mpc/pd_controller.hpp"
#include "idto/mpc/position_filter.hpp"
#include "idto/mpc/realtime.hpp"
#include "idto/mpc/spline.hpp"
// sim
#include "idto/sim/mjcf.hpp"
#include "idto/sim/plant.hpp"
// closed loop
#include "idto/mpc/closed_loop.hpp"
// example configuration files (YAML): builds models, problems and solver options
#include "idto/config/config.hpp"
#include "idto/config/mpc_config.hpp"
// viewer (top of the stack): self-contained HTML animation pages
#include "idto/viz/html_animation.hpp"
