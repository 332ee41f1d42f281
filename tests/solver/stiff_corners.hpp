#pragma once

// The corners of the parameter space that tests/solver/extremes/extremes_test.cpp solves and
// tests/solver/heavy/stiff_corner_statistics_test.cpp solves again from perturbed guesses: the
// ball-and-finger model's problem at a corner, and an example's problem with its contact
// parameters replaced.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "idto/idto.hpp"
#include "support/test_models.hpp"

namespace idto::test {

/// A corner of the ball-and-finger problem (test::BallAndFinger): contact parameters, time step
/// and horizon, weights, the ball's initial height, speed and orientation, and the solver's
/// method and iteration limit.
struct Corner {
  std::string name;
  double stiffness{500}, smoothing{0.01}, stiction{0.1};
  double dt{0.05};
  int N{20};
  double weight_scale{1.0};
  double ball_height{0.049};  // deep penetration when well below 0.05
  double ball_speed{0.0};
  double quaternion_w{1.0};  // near -1 / 0 for sign-flip corners
  ConstraintMethod method{ConstraintMethod::kPenalty};
  DerivativeMethod derivatives{DerivativeMethod::kAnalytic};
  int iterations{30};
};

/// The corner's problem on `model` (test::BallAndFinger()): push the ball 0.2 m along x to rest
/// on the ground (z = 0.05) from c's initial state.
inline ProblemDefinition CornerProblem(const Model& model, const Corner& c) {
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, c.dt, c.N);
  const double qw = c.quaternion_w, qx = std::sqrt(std::max(0.0, 1.0 - qw * qw));
  p.q_init << qw, qx, 0, 0, 0.0, 0.0, c.ball_height, 0.5, -1.2;
  p.v_init.setZero();
  p.v_init(3) = c.ball_speed;
  p.Qq.setConstant(1.0 * c.weight_scale);
  p.Qv.setConstant(0.1 * c.weight_scale);
  p.R.setConstant(0.1 * c.weight_scale);
  p.R.head<6>().setConstant(100.0 * c.weight_scale);
  p.Qfq.setConstant(10.0 * c.weight_scale);
  p.Qfv.setConstant(1.0 * c.weight_scale);
  Eigen::VectorXd target = p.q_init;
  target(4) = 0.2;
  target(6) = 0.05;
  p.SetConstantNominal(target, Eigen::VectorXd::Zero(model.nv()));
  p.contact.parameters.stiffness = c.stiffness;
  p.contact.parameters.smoothing = c.smoothing;
  p.contact.parameters.stiction_velocity = c.stiction;
  return p;
}

/// The corner's solver options with `iterations` and `trial_derivatives`.
inline SolverOptions CornerOptions(const Corner& c, int iterations, bool trial_derivatives) {
  SolverOptions o;
  o.max_iterations = iterations;
  o.trial_derivatives = trial_derivatives;
  o.constraint_method = c.method;
  o.derivative_method = c.derivatives;
  return o;
}

/// Example `name` (examples/NAME/NAME.yaml) with its contact stiffness, stiction velocity,
/// smoothing and time step replaced.
inline ExampleConfig ExampleAtCorner(const std::string& name, double stiffness, double stiction,
                                     double smoothing, double dt) {
  const std::vector<std::string> dirs{IDTO_SOURCE_DIR};
  ExampleConfig config = LoadExampleConfig(FindExampleConfig(name, dirs), dirs);
  ProblemDefinition& p = config.problem;
  p.contact.parameters.stiffness = stiffness;
  p.contact.parameters.stiction_velocity = stiction;
  p.contact.parameters.smoothing = smoothing;
  p.time_step = dt;
  return config;
}

}  // namespace idto::test
