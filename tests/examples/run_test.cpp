// idto-run's task measures (examples/run/metrics.cpp), in process: the pendulum and acrobot
// criteria, the generic fallback, and a full pendulum solve from its configuration file.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "examples/example_test_support.hpp"
#include "idto/config/config.hpp"
#include "idto/solver/trajectory_optimizer.hpp"
#include "run/metrics.hpp"

namespace idto {
namespace {

using test::LoadExample;

using examples::EvaluateTask;
using examples::TaskResult;

/// A trajectory that stays at q_init and ends at q_final, with zero velocities and efforts.
Trajectory MakeTrajectory(const ExampleConfig& config, const Eigen::VectorXd& q_final) {
  const int N = config.problem.num_steps;
  Trajectory t;
  t.q.assign(N + 1, config.problem.q_init);
  t.q.back() = q_final;
  t.v.assign(N + 1, Eigen::VectorXd::Zero(config.model.nv()));
  t.tau.assign(N + 1, Eigen::VectorXd::Zero(config.model.nv()));
  return t;
}

const examples::Metric* Find(const TaskResult& result, const std::string& name) {
  for (const examples::Metric& m : result.metrics) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

TEST(TaskMetricsTest, Pendulum) {
  const ExampleConfig config = LoadExample("pendulum");
  ASSERT_TRUE(examples::HasTaskMeasure("pendulum"));
  Eigen::VectorXd q(1);
  q << M_PI - 5e-4;
  TaskResult result = EvaluateTask(config, MakeTrajectory(config, q));
  EXPECT_TRUE(result.task_success);
  ASSERT_NE(Find(result, "final_angle_rad"), nullptr);
  ASSERT_NE(Find(result, "angle_error_rad"), nullptr);
  EXPECT_DOUBLE_EQ(Find(result, "final_angle_rad")->values[0], M_PI - 5e-4);
  EXPECT_NEAR(Find(result, "angle_error_rad")->values[0], 5e-4, 1e-15);
  EXPECT_FALSE(Find(result, "angle_error_rad")->is_array);
  EXPECT_THAT(result.criterion, ::testing::HasSubstr("1e-3"));
  q << M_PI + 2e-3;
  result = EvaluateTask(config, MakeTrajectory(config, q));
  EXPECT_FALSE(result.task_success);
}

TEST(TaskMetricsTest, Acrobot) {
  const ExampleConfig config = LoadExample("acrobot");
  const Eigen::Vector2d upright(M_PI, 0.0);
  Trajectory t = MakeTrajectory(config, upright);
  TaskResult result = EvaluateTask(config, t);
  EXPECT_TRUE(result.task_success);
  ASSERT_NE(Find(result, "final_angles_rad"), nullptr);
  EXPECT_TRUE(Find(result, "final_angles_rad")->is_array);
  EXPECT_EQ(Find(result, "final_angles_rad")->values.size(), 2u);
  ASSERT_NE(Find(result, "error_rad"), nullptr);
  EXPECT_DOUBLE_EQ(Find(result, "error_rad")->values[0], 0.0);
  // A torque on the passive shoulder fails the task.
  t.tau[3](0) = 0.5;
  result = EvaluateTask(config, t);
  EXPECT_FALSE(result.task_success);
  EXPECT_DOUBLE_EQ(examples::MaxUnactuatedEffort(config, t), 0.5);
  // Missing the upright state fails it too.
  t = MakeTrajectory(config, Eigen::Vector2d(M_PI, 0.1));
  EXPECT_FALSE(EvaluateTask(config, t).task_success);
}

TEST(TaskMetricsTest, GenericFallback) {
  ExampleConfig config = LoadExample("pendulum");
  config.name = "my_pendulum";
  ASSERT_FALSE(examples::HasTaskMeasure(config.name));
  Eigen::VectorXd q = config.problem.q_nom.back();
  TaskResult result = EvaluateTask(config, MakeTrajectory(config, q));
  EXPECT_TRUE(result.task_success);
  ASSERT_NE(Find(result, "final_error"), nullptr);
  q(0) += 0.1;
  result = EvaluateTask(config, MakeTrajectory(config, q));
  EXPECT_FALSE(result.task_success);
  EXPECT_NEAR(Find(result, "final_error")->values[0], 0.1, 1e-12);
}

TEST(ExamplesTest, PendulumSwingUpReachesUpright) {
  const ExampleConfig config = LoadExample("pendulum");
  TrajectoryOptimizer optimizer(config.model, config.problem, config.solver);
  Trajectory solution;
  const SolverSummary summary = optimizer.Solve(MakeInitialGuess(config), &solution);
  EXPECT_NE(summary.termination, TerminationType::kFailure) << summary.message;
  ASSERT_EQ(solution.q.size(), 41u);
  EXPECT_LT(std::abs(solution.q.back()(0) - M_PI), 1e-3);
  EXPECT_TRUE(EvaluateTask(config, solution).task_success);
}

TEST(ExamplesTest, AcrobotSwingUpWithPassiveShoulder) {
  const ExampleConfig config = LoadExample("acrobot");
  TrajectoryOptimizer optimizer(config.model, config.problem, config.solver);
  Trajectory solution;
  const SolverSummary summary = optimizer.Solve(MakeInitialGuess(config), &solution);
  EXPECT_NE(summary.termination, TerminationType::kFailure) << summary.message;
  const TaskResult result = EvaluateTask(config, solution);
  EXPECT_TRUE(result.task_success)
      << "error " << Find(result, "error_rad")->values[0] << " rad, shoulder torque "
      << examples::MaxUnactuatedEffort(config, solution);
}

}  // namespace
}  // namespace idto
