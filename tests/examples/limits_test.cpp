// Joint limits as penalties (ProblemDefinition::limits, YAML problem.limits): the quadruped and
// Allegro variants (examples/quadruped_limits, examples/allegro_limits) end with every joint
// within its limits, where the plans without limits go past them; the gradient with active
// limit terms matches a central difference of the cost; bad limit input is refused.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "examples/example_test_support.hpp"
#include "idto/idto.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

using test::LoadExample;

struct Excess {
  double position{0.0}, velocity{0.0}, effort{0.0};  // effort relative to the limit
};

// How far `solution` goes past the limits of `limits` (the model's where not given).
Excess MeasureExcess(const Model& model, const LimitPenalties& l, const Trajectory& solution) {
  const Eigen::VectorXd& lo = l.q_lower.size() ? l.q_lower : model.position_lower_limits();
  const Eigen::VectorXd& hi = l.q_upper.size() ? l.q_upper : model.position_upper_limits();
  const Eigen::VectorXd& v_max = l.v_max.size() ? l.v_max : model.velocity_limits();
  const Eigen::VectorXd& tau_max = l.tau_max.size() ? l.tau_max : model.effort_limits();
  Excess e;
  for (const Eigen::VectorXd& q : solution.q) {
    for (int i = 0; i < q.size(); ++i)
      e.position = std::max({e.position, q(i) - hi(i), lo(i) - q(i)});
  }
  for (const Eigen::VectorXd& v : solution.v) {
    for (int i = 0; i < v.size(); ++i) e.velocity = std::max(e.velocity, std::abs(v(i)) - v_max(i));
  }
  for (size_t k = 0; k + 1 < solution.q.size(); ++k) {
    for (int i = 0; i < model.nv(); ++i) {
      if (!std::isfinite(tau_max(i))) continue;
      e.effort = std::max(e.effort, (std::abs(solution.tau[k](i)) - tau_max(i)) / tau_max(i));
    }
  }
  return e;
}

Trajectory Solve(const ExampleConfig& config, const ProblemDefinition& problem) {
  SolverOptions o = config.solver;
  o.num_threads = 2;
  TrajectoryOptimizer optimizer(config.model, problem, o);
  Trajectory solution;
  optimizer.Solve(MakeInitialGuess(config), &solution);
  return solution;
}

// Tolerances of the variants' task_success: 0.01 rad, 0.1 rad/s, 2% of the effort limit.
void ExpectWithinLimits(const Excess& e) {
  EXPECT_LE(e.position, 0.01);
  EXPECT_LE(e.velocity, 0.1);
  EXPECT_LE(e.effort, 0.02);
}

TEST(JointLimits, QuadrupedVariantKeepsTheKneeEffortCap) {
  const ExampleConfig config = LoadExample("quadruped_limits");
  ASSERT_TRUE(config.problem.limits.any());
  ProblemDefinition without = config.problem;
  without.limits.position_weight = without.limits.velocity_weight = 0.0;
  without.limits.effort_weight = 0.0;
  const Excess free = MeasureExcess(config.model, config.problem.limits, Solve(config, without));
  EXPECT_GT(free.effort, 0.2);  // the front knees ask 6.3 N m of a 4.5 N m motor
  const Excess limited =
      MeasureExcess(config.model, config.problem.limits, Solve(config, config.problem));
  ExpectWithinLimits(limited);
}

TEST(JointLimits, AllegroVariantKeepsTheThumbWithinItsRange) {
  const ExampleConfig config = LoadExample("allegro_limits");
  ProblemDefinition without = config.problem;
  without.limits = LimitPenalties{};
  const Excess free = MeasureExcess(config.model, config.problem.limits, Solve(config, without));
  EXPECT_GT(free.position, 0.1);  // the thumb's last joint 0.21 rad past its 1.719 rad limit
  const Excess limited =
      MeasureExcess(config.model, config.problem.limits, Solve(config, config.problem));
  ExpectWithinLimits(limited);
}

// With limit terms active, the gradient is that of the cost (central difference along random
// directions) and the Hessian is the Gauss-Newton one (symmetric, positive semidefinite rows
// are checked through the factorization in the solver tests).
TEST(JointLimits, GradientWithActiveLimitsMatchesTheCost) {
  const ExampleConfig config = LoadExample("allegro_limits");
  ProblemDefinition p = config.problem;
  // Tight bounds so that every kind of limit is active somewhere along the initial guess.
  p.limits.tau_max = Eigen::VectorXd::Constant(config.model.nv(), 0.01);
  p.limits.v_max = Eigen::VectorXd::Constant(config.model.nv(), 0.05);
  Transcription t(config.model, p);
  TrajectoryState s = t.MakeState();
  s.q = MakeInitialGuess(config);
  test::Random noise(3);
  for (int k = 1; k <= t.num_steps(); ++k) {
    s.q[k] += noise.Vector(t.nq(), -0.05, 0.05);
    NormalizeQuaternions(config.model, &s.q[k]);
  }
  const double cost = t.Evaluate(&s);
  TrajectoryState s_free = s;
  Transcription t_free(config.model, config.problem);
  t_free.Evaluate(&s_free);
  EXPECT_GT(cost, s_free.cost);  // the tight limits are active
  TrajectoryDerivatives d = t.MakeDerivatives();
  t.CalcDerivatives(s, &d);
  Eigen::VectorXd g(t.num_steps() * t.nq());
  t.CalcGradient(s, d, &g);
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::VectorXd dir = noise.Vector(g.size());
    const double h = 1e-7;
    TrajectoryState sp = s, sm = s;
    for (int k = 1; k <= t.num_steps(); ++k) {
      sp.q[k] += h * dir.segment((k - 1) * t.nq(), t.nq());
      sm.q[k] -= h * dir.segment((k - 1) * t.nq(), t.nq());
    }
    const double fd = (t.Evaluate(&sp) - t.Evaluate(&sm)) / (2.0 * h);
    EXPECT_NEAR(g.dot(dir), fd, 1e-5 * std::max(1.0, std::abs(fd)));
  }
}

TEST(JointLimits, BadLimitsAreRefusedWithTheField) {
  const ExampleConfig config = LoadExample("quadruped_limits");
  ProblemDefinition p = config.problem;
  p.limits.position_weight = -1.0;
  EXPECT_THROW(
      {
        try {
          p.Validate(config.model);
        } catch (const InvalidArgument& e) {
          EXPECT_NE(std::string(e.what()).find("limits.position_weight"), std::string::npos);
          throw;
        }
      },
      InvalidArgument);
  p = config.problem;
  p.limits.tau_max = Eigen::VectorXd::Constant(3, 1.0);
  EXPECT_THROW(p.Validate(config.model), InvalidArgument);
  p = config.problem;
  p.limits.q_lower = config.model.position_upper_limits();
  p.limits.q_upper = config.model.position_lower_limits();
  EXPECT_THROW(p.Validate(config.model), InvalidArgument);
  p = config.problem;
  p.limits.v_max = Eigen::VectorXd::Constant(config.model.nv(), std::nan(""));
  EXPECT_THROW(p.Validate(config.model), InvalidArgument);
}

}  // namespace
}  // namespace idto
