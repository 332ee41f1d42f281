// The bi-manual examples (examples/bimanual, bimanual_lift, bimanual_balance): the scene (two
// Jaco-like arms, a box of 9 inscribed spheres on a table), their task measures
// (examples/run/metrics_bimanual.cpp) and a short solve of each configuration.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "examples/example_test_support.hpp"
#include "idto/config/config.hpp"
#include "idto/contact/contact_engine.hpp"
#include "idto/solver/trajectory_optimizer.hpp"
#include "run/metrics.hpp"

namespace idto {
namespace {

using test::LoadExample;
using test::MetricValue;

using examples::EvaluateTask;
using examples::TaskResult;

const std::vector<std::string> kBimanualExamples = {"bimanual", "bimanual_lift",
                                                    "bimanual_balance"};

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

TEST(BimanualScene, ModelGeometryAndContactPairs) {
  for (const std::string& name : kBimanualExamples) {
    SCOPED_TRACE(name);
    const ExampleConfig config = LoadExample(name);
    const Model& model = config.model;
    // 7 + 7 arm joints and the box's floating base.
    EXPECT_EQ(model.nv(), 20);
    EXPECT_EQ(model.nq(), 21);
    ASSERT_TRUE(model.HasJoint("box_root_joint"));
    EXPECT_EQ(model.velocity_start(model.GetJointIndex("box_root_joint")), 14);
    for (int i = 0; i < 20; ++i) EXPECT_EQ(model.is_base_velocity()[i], i >= 14) << i;

    // The box is 9 inscribed spheres (no box shape is left), the table a half-space.
    std::set<std::string> names;
    for (const GeometryInstance& g : model.geometries()) {
      names.insert(g.name);
      EXPECT_FALSE(std::holds_alternative<Box>(g.shape)) << g.name;
    }
    for (int k = 0; k < 9; ++k) EXPECT_TRUE(names.count("box_sphere" + std::to_string(k)));
    EXPECT_TRUE(names.count("table"));
    EXPECT_EQ(model.geometries().size(), 9u + 1u + 6u);

    // The paper's Table 2 contact parameters.
    const ContactParameters& p = config.problem.contact.parameters;
    EXPECT_DOUBLE_EQ(p.stiffness, 1000.0);
    EXPECT_DOUBLE_EQ(p.smoothing, 0.005);
    EXPECT_DOUBLE_EQ(p.friction_coefficient, 0.2);
    EXPECT_DOUBLE_EQ(p.stiction_velocity, 0.05);
    EXPECT_DOUBLE_EQ(p.dissipation_velocity, 0.1);
    EXPECT_DOUBLE_EQ(config.problem.time_step, 0.05);
    EXPECT_EQ(config.problem.num_steps, 20);

    // Pairs: box spheres against the table and the six arm spheres (63), arm spheres against
    // the table (6); nothing within an arm, nothing between the arms.
    const ContactEngine engine(model, config.problem.contact);
    EXPECT_EQ(engine.num_pairs(), 9 * 7 + 6);
    for (const ContactPair& pair : engine.pairs()) {
      const std::string a = model.geometries()[pair.geometry_a].name;
      const std::string b = model.geometries()[pair.geometry_b].name;
      const bool a_box = a.rfind("box_", 0) == 0;
      const bool b_box = b.rfind("box_", 0) == 0;
      EXPECT_TRUE(a_box != b_box || a == "table" || b == "table") << a << " - " << b;
      EXPECT_FALSE(a_box && b_box) << a << " - " << b;
    }
  }
}

TEST(BimanualTaskMetrics, MoveAndBalance) {
  for (const char* name : {"bimanual", "bimanual_balance"}) {
    SCOPED_TRACE(name);
    const ExampleConfig config = LoadExample(name);
    ASSERT_TRUE(examples::HasTaskMeasure(name));
    const int iq = config.model.position_start(config.model.GetJointIndex("box_root_joint"));
    const int iv = config.model.velocity_start(config.model.GetJointIndex("box_root_joint"));
    Eigen::VectorXd q = config.problem.q_nom.back();
    q(iq + 4) += 0.01;  // 1 cm off in x
    Trajectory t = MakeTrajectory(config, q);
    TaskResult result = EvaluateTask(config, t);
    EXPECT_TRUE(result.task_success) << result.criterion;
    EXPECT_NEAR(MetricValue(result, "box_position_error_m"), 0.01, 1e-12);
    EXPECT_NEAR(MetricValue(result, "box_orientation_error_rad"), 0.0, 1e-7);
    EXPECT_THAT(result.criterion, ::testing::HasSubstr("2 cm"));

    // 3 cm off fails.
    q(iq + 4) += 0.02;
    EXPECT_FALSE(EvaluateTask(config, MakeTrajectory(config, q)).task_success);

    // Turned by 0.2 rad about z fails.
    q = config.problem.q_nom.back();
    const Eigen::Quaterniond target(q(iq), q(iq + 1), q(iq + 2), q(iq + 3));
    const Eigen::Quaterniond turned = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()) * target;
    q.segment<4>(iq) << turned.w(), turned.x(), turned.y(), turned.z();
    result = EvaluateTask(config, MakeTrajectory(config, q));
    EXPECT_FALSE(result.task_success);
    EXPECT_NEAR(MetricValue(result, "box_orientation_error_rad"), 0.2, 1e-9);

    // A force on the box that no contact explains (1 N, more than 10 % of its weight) fails.
    t = MakeTrajectory(config, config.problem.q_nom.back());
    EXPECT_TRUE(EvaluateTask(config, t).task_success);
    t.tau[5](iv + 5) = 1.0;
    result = EvaluateTask(config, t);
    EXPECT_FALSE(result.task_success);
    EXPECT_DOUBLE_EQ(MetricValue(result, "max_unactuated_force_N"), 1.0);
    t.tau[5](iv + 5) = 0.0;
    t.tau[7](iv + 0) = 0.05;  // an unexplained torque
    EXPECT_FALSE(EvaluateTask(config, t).task_success);
  }
}

TEST(BimanualTaskMetrics, Lift) {
  const ExampleConfig config = LoadExample("bimanual_lift");
  ASSERT_TRUE(examples::HasTaskMeasure("bimanual_lift"));
  const int iq = config.model.position_start(config.model.GetJointIndex("box_root_joint"));
  const double z0 = config.problem.q_init(iq + 6);
  const double gain = config.problem.q_nom.back()(iq + 6) - z0;
  EXPECT_NEAR(gain, 0.15, 1e-12);
  Eigen::VectorXd q = config.problem.q_nom.back();
  q(iq + 6) = z0 + 0.8 * gain;
  TaskResult result = EvaluateTask(config, MakeTrajectory(config, q));
  EXPECT_TRUE(result.task_success) << result.criterion;
  EXPECT_NEAR(MetricValue(result, "box_height_gained_m"), 0.12, 1e-12);
  EXPECT_NEAR(MetricValue(result, "box_height_fraction"), 0.8, 1e-12);
  q(iq + 6) = z0 + 0.5 * gain;
  EXPECT_FALSE(EvaluateTask(config, MakeTrajectory(config, q)).task_success);
}

TEST(BimanualTaskMetrics, NoBoxInTheScene) {
  ExampleConfig config = LoadExample("pendulum");
  config.name = "bimanual";
  const Trajectory t = MakeTrajectory(config, config.problem.q_init);
  const TaskResult result = EvaluateTask(config, t);
  EXPECT_FALSE(result.task_success);
  EXPECT_THAT(result.criterion, ::testing::HasSubstr("box_root_joint"));
}

TEST(BimanualExamples, ShortSolves) {
  // Each configuration runs a short solve (20 iterations, 2 threads) without failure, lowering
  // the cost, well within a minute.
  for (const std::string& name : kBimanualExamples) {
    SCOPED_TRACE(name);
    ExampleConfig config = LoadExample(name);
    config.solver.max_iterations = 20;
    config.solver.num_threads = 2;
    const auto start = std::chrono::steady_clock::now();
    TrajectoryOptimizer optimizer(config.model, config.problem, config.solver);
    Trajectory solution;
    const SolverSummary summary = optimizer.Solve(MakeInitialGuess(config), &solution);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_NE(summary.termination, TerminationType::kFailure) << summary.message;
    EXPECT_TRUE(std::isfinite(summary.final_cost));
    EXPECT_LT(summary.final_cost, summary.initial_cost);
    EXPECT_LT(seconds, 60.0);
    ASSERT_EQ(solution.q.size(), 21u);
    const TaskResult result = EvaluateTask(config, solution);
    EXPECT_TRUE(std::isfinite(MetricValue(result, "box_position_error_m")));
  }
}

}  // namespace
}  // namespace idto
