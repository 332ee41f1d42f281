// The quadruped (flat and hills) and Allegro hand examples: their configurations load with the
// paper's parameters, their initial states are physically consistent (feet and ball resting
// on their supports near static equilibrium), and their task measures (QuadrupedTask,
// AllegroTask in examples/run/metrics_quadruped_allegro.cpp) accept and reject what they should.
// Short and full idto-run solves are ctest tests in examples/CMakeLists.txt.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "examples/example_test_support.hpp"
#include "idto/config/config.hpp"
#include "idto/contact/contact_engine.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/multibody/data.hpp"
#include "idto/solver/trajectory_optimizer.hpp"
#include "run/metrics.hpp"

namespace idto {
namespace {

using test::LoadExample;
using test::MetricValue;
using test::RestingTrajectory;

using examples::EvaluateTask;
using examples::TaskResult;

/// One evaluated contact pair, by geometry names.
struct StaticContact {
  std::string a, b;
  double phi{0.0};
  double fn{0.0};
  bool Involves(const std::string& part) const {
    return a.find(part) != std::string::npos || b.find(part) != std::string::npos;
  }
};

/// Contacts at q_init and the generalized force the floating joint `joint` needs to stay at
/// rest there (inverse dynamics with the contact forces, v = a = 0).
struct StaticCheck {
  std::vector<StaticContact> contacts;
  Eigen::VectorXd tau_joint;  // 6: [torque; force]
};

StaticCheck CheckStatic(const ExampleConfig& config, const std::string& joint) {
  const Model& model = config.model;
  Data data(model);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv());
  ForwardKinematics(model, config.problem.q_init, zero, &data);
  ContactEngine engine(model, config.problem.contact);
  ContactData contact = engine.MakeData(model);
  engine.Evaluate(model, data, &contact);
  StaticCheck check;
  for (int i = 0; i < contact.num_active; ++i) {
    const ContactResult& r = contact.results[i];
    const ContactPair& pair = engine.pairs()[r.pair];
    check.contacts.push_back({model.geometries()[pair.geometry_a].name,
                              model.geometries()[pair.geometry_b].name, r.phi, r.force.fn});
  }
  const Eigen::VectorXd tau =
      InverseDynamics(model, config.problem.q_init, zero, zero, contact.F_ext, &data);
  check.tau_joint = tau.segment<6>(model.GetVelocityStart(joint));
  return check;
}

// ---------------------------------------------------------------------------- quadruped

TEST(QuadrupedExampleTest, LoadsWithThePapersParameters) {
  for (const char* name : {"quadruped", "quadruped_hills"}) {
    SCOPED_TRACE(name);
    const ExampleConfig config = LoadExample(name);
    EXPECT_EQ(config.name, name);
    EXPECT_TRUE(examples::HasTaskMeasure(name));
    EXPECT_EQ(config.model.nq(), 19);
    EXPECT_EQ(config.model.nv(), 18);
    EXPECT_EQ(config.problem.num_steps, 20);  // 1.0 s
    EXPECT_DOUBLE_EQ(config.problem.time_step, 0.05);
    const ContactParameters& p = config.problem.contact.parameters;
    EXPECT_DOUBLE_EQ(p.stiffness, 2000.0);
    EXPECT_DOUBLE_EQ(p.smoothing, 0.01);
    EXPECT_DOUBLE_EQ(p.friction_coefficient, 1.0);
    EXPECT_DOUBLE_EQ(p.stiction_velocity, 0.5);
    EXPECT_DOUBLE_EQ(p.dissipation_velocity, 0.1);
    // Table 3: base position 10, orientation 1 in the running cost; R 100 on the base.
    const int qs = config.model.GetPositionStart("body_root_joint");
    const int vs = config.model.GetVelocityStart("body_root_joint");
    EXPECT_DOUBLE_EQ(config.problem.Qq(qs), 1.0);
    EXPECT_DOUBLE_EQ(config.problem.Qq(qs + 4), 10.0);
    EXPECT_DOUBLE_EQ(config.problem.Qq(qs + 7), 0.0);
    EXPECT_DOUBLE_EQ(config.problem.R(vs), 100.0);
    EXPECT_DOUBLE_EQ(config.problem.R(vs + 6), 0.01);
    EXPECT_EQ(config.problem.UnactuatedDofs(config.model).size(), 6u);
    // The nominal base goes 0.4 m forward.
    EXPECT_NEAR(config.problem.q_nom.back()(qs + 4) - config.problem.q_init(qs + 4), 0.4, 1e-12);
  }
}

TEST(QuadrupedExampleTest, StandsOnItsFeetNearStaticEquilibrium) {
  for (const char* name : {"quadruped", "quadruped_hills"}) {
    SCOPED_TRACE(name);
    const ExampleConfig config = LoadExample(name);
    const StaticCheck check = CheckStatic(config, "body_root_joint");
    // Every foot rests on a support (ground or hill) with a few mm of compression.
    int feet_down = 0;
    for (const StaticContact& c : check.contacts) {
      if (c.fn > 1.0) {
        EXPECT_TRUE(c.Involves("foot")) << c.a << " - " << c.b;
        EXPECT_GT(c.phi, -0.008);
        EXPECT_LT(c.phi, 0.0);
        ++feet_down;
      }
    }
    EXPECT_EQ(feet_down, 4);
    // The base needs less than 1% of the weight (81 N) and 1 N m to stay at rest.
    EXPECT_LT(check.tau_joint.tail<3>().norm(), 0.8);
    EXPECT_LT(check.tau_joint.head<3>().norm(), 1.0);
  }
}

TEST(QuadrupedExampleTest, HillsAreAnalyticCylinders) {
  const ExampleConfig config = LoadExample("quadruped_hills");
  int hills = 0;
  for (const GeometryInstance& g : config.model.geometries()) {
    if (const auto* cylinder = std::get_if<Cylinder>(&g.shape)) {
      EXPECT_EQ(g.body, kWorldBody);
      EXPECT_DOUBLE_EQ(cylinder->radius, 0.5);  // 1 m diameter
      EXPECT_TRUE(SignedDistanceIsExact(Sphere{0.02}, g.shape));
      ++hills;
    }
  }
  EXPECT_EQ(hills, 2);
}

TEST(QuadrupedExampleTest, TaskMeasure) {
  const ExampleConfig config = LoadExample("quadruped");
  const int qs = config.model.GetPositionStart("body_root_joint");
  const int vs = config.model.GetVelocityStart("body_root_joint");
  Trajectory t = RestingTrajectory(config);
  // Standing still fails (no forward motion); 0.1 m forward succeeds.
  EXPECT_FALSE(EvaluateTask(config, t).task_success);
  t.q.back()(qs + 4) += 0.1;
  TaskResult result = EvaluateTask(config, t);
  EXPECT_TRUE(result.task_success);
  EXPECT_NEAR(MetricValue(result, "base_distance_m"), 0.1, 1e-12);
  EXPECT_NEAR(MetricValue(result, "mean_forward_speed_m_s"), 0.1, 1e-12);
  EXPECT_NEAR(MetricValue(result, "nominal_distance_m"), 0.4, 1e-12);
  EXPECT_NEAR(MetricValue(result, "final_base_height_m"), 0.3056, 1e-12);
  EXPECT_DOUBLE_EQ(MetricValue(result, "max_tilt_rad"), 0.0);
  // Sideways motion does not count.
  Trajectory sideways = RestingTrajectory(config);
  sideways.q.back()(qs + 5) += 0.3;
  EXPECT_FALSE(EvaluateTask(config, sideways).task_success);
  // Tilted by 0.4 rad at one step: fails, and the tilt is measured.
  Trajectory tilted = t;
  const Eigen::Quaterniond pitch(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()));
  tilted.q[7].segment<4>(qs) << pitch.w(), pitch.x(), pitch.y(), pitch.z();
  result = EvaluateTask(config, tilted);
  EXPECT_FALSE(result.task_success);
  EXPECT_NEAR(MetricValue(result, "max_tilt_rad"), 0.4, 1e-12);
  // Collapsed to 0.15 m: fails.
  Trajectory collapsed = t;
  collapsed.q.back()(qs + 6) = 0.15;
  EXPECT_FALSE(EvaluateTask(config, collapsed).task_success);
  // A phantom base force: 2 N forward over the whole horizon would push the 8.25 kg robot
  // 2 x 1^2 / (2 x 8.25) = 0.12 m (> 10% of 0.4 m) by itself: fails. 0.2 N (1.2 cm) passes.
  Trajectory pushed = t;
  for (int k = 0; k < config.problem.num_steps; ++k) pushed.tau[k](vs + 3) = 2.0;
  result = EvaluateTask(config, pushed);
  EXPECT_FALSE(result.task_success);
  EXPECT_DOUBLE_EQ(MetricValue(result, "max_base_force_N"), 2.0);
  // With the joints locked, the robot's mass is the base's linear inertia, x = f dt^2 sum_k k
  // / m, up to the coupling with rotation (the centre of mass is not at the base origin).
  const double N = config.problem.num_steps;
  const double dt = config.problem.time_step;
  EXPECT_NEAR(MetricValue(result, "phantom_displacement_m"),
              2.0 * dt * dt * N * (N + 1) / 2 / config.model.total_mass(), 2e-3);
  for (int k = 0; k < config.problem.num_steps; ++k) pushed.tau[k](vs + 3) = 0.2;
  EXPECT_TRUE(EvaluateTask(config, pushed).task_success);
  // A phantom pitch torque of 1 N m over the horizon: fails.
  Trajectory twisted = t;
  for (int k = 0; k < config.problem.num_steps; ++k) twisted.tau[k](vs + 1) = 1.0;
  result = EvaluateTask(config, twisted);
  EXPECT_FALSE(result.task_success);
  EXPECT_GT(MetricValue(result, "phantom_rotation_rad"), 0.1);
}

// ---------------------------------------------------------------------------- allegro

TEST(AllegroExampleTest, LoadsWithThePapersParameters) {
  const ExampleConfig config = LoadExample("allegro");
  EXPECT_TRUE(examples::HasTaskMeasure("allegro"));
  EXPECT_EQ(config.model.nv(), 22);
  EXPECT_EQ(config.model.nq(), 23);
  EXPECT_EQ(config.problem.num_steps, 40);  // 2.0 s
  const ContactParameters& p = config.problem.contact.parameters;
  EXPECT_DOUBLE_EQ(p.stiffness, 100.0);
  EXPECT_DOUBLE_EQ(p.smoothing, 0.001);
  EXPECT_DOUBLE_EQ(p.friction_coefficient, 1.0);
  EXPECT_DOUBLE_EQ(p.stiction_velocity, 0.1);
  const std::vector<int> unactuated = config.problem.UnactuatedDofs(config.model);
  ASSERT_EQ(unactuated.size(), 6u);
  EXPECT_EQ(unactuated.front(), config.model.GetVelocityStart("ball_root_joint"));
  EXPECT_EQ(config.solver.constraint_method, ConstraintMethod::kLagrangeMultipliers);
  // Only ball-hand pairs: the palm box and the 11 finger spheres.
  ContactEngine engine(config.model, config.problem.contact);
  EXPECT_EQ(engine.num_pairs(), 12);
  const GeometryIndex ball = config.model.GetGeometryIndex("ball_sphere");
  for (const ContactPair& pair : engine.pairs()) {
    EXPECT_TRUE(pair.geometry_a == ball || pair.geometry_b == ball);
  }
}

TEST(AllegroExampleTest, BallRestsInTheHand) {
  const ExampleConfig config = LoadExample("allegro");
  const StaticCheck check = CheckStatic(config, "ball_root_joint");
  // The palm carries the ball's weight; the fingertips are within a few mm of it.
  double palm_force = 0.0;
  int fingertips = 0;
  for (const StaticContact& c : check.contacts) {
    if (c.Involves("palm_box")) palm_force = c.fn;
    if (c.Involves("_tip_")) {
      EXPECT_GT(c.phi, 0.0);
      EXPECT_LT(c.phi, 0.005);
      ++fingertips;
    }
  }
  EXPECT_NEAR(palm_force, 0.05 * 9.81, 0.01);
  EXPECT_EQ(fingertips, 4);
  // The ball needs less than 5% of its weight to stay at rest.
  EXPECT_LT(check.tau_joint.tail<3>().norm(), 0.05 * 0.05 * 9.81);
}

TEST(AllegroExampleTest, TaskMeasure) {
  const ExampleConfig config = LoadExample("allegro");
  const int qs = config.model.GetPositionStart("ball_root_joint");
  const int vs = config.model.GetVelocityStart("ball_root_joint");
  Trajectory t = RestingTrajectory(config);
  // Not rotated: fails with an error of the full target rotation (pi/2).
  TaskResult result = EvaluateTask(config, t);
  EXPECT_FALSE(result.task_success);
  EXPECT_NEAR(MetricValue(result, "target_rotation_rad"), M_PI / 2, 1e-9);
  EXPECT_NEAR(MetricValue(result, "orientation_error_rad"), M_PI / 2, 1e-9);
  // At the target orientation: succeeds.
  t.q.back().segment<4>(qs) = config.problem.q_nom.back().segment<4>(qs);
  result = EvaluateTask(config, t);
  EXPECT_TRUE(result.task_success);
  EXPECT_NEAR(MetricValue(result, "ball_rotation_rad"), M_PI / 2, 1e-9);
  EXPECT_NEAR(MetricValue(result, "orientation_error_rad"), 0.0, 1e-7);
  // 0.15 rad short of the target about another axis: fails.
  Trajectory off = t;
  const Eigen::Quaterniond target(t.q.back()(qs), t.q.back()(qs + 1), t.q.back()(qs + 2),
                                  t.q.back()(qs + 3));
  const Eigen::Quaterniond tilted =
      target * Eigen::Quaterniond(Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitX()));
  off.q.back().segment<4>(qs) << tilted.w(), tilted.x(), tilted.y(), tilted.z();
  result = EvaluateTask(config, off);
  EXPECT_FALSE(result.task_success);
  EXPECT_NEAR(MetricValue(result, "orientation_error_rad"), 0.15, 1e-9);
  // The ball leaves the hand for a while (3 cm): fails.
  Trajectory dropped = t;
  dropped.q[20](qs + 6) -= 0.03;
  result = EvaluateTask(config, dropped);
  EXPECT_FALSE(result.task_success);
  EXPECT_NEAR(MetricValue(result, "ball_drift_m"), 0.03, 1e-12);
  // A phantom torque about z of 5e-4 N m over the 2 s would spin the free ball (I = 2/5 m r^2
  // = 7.2e-5 kg m^2) by 5e-4 x 0.05^2 x (40 x 41 / 2) / 7.2e-5 = 14 rad by itself: fails.
  Trajectory spun = t;
  for (int k = 0; k < config.problem.num_steps; ++k) spun.tau[k](vs + 2) = 5e-4;
  result = EvaluateTask(config, spun);
  EXPECT_FALSE(result.task_success);
  EXPECT_NEAR(MetricValue(result, "phantom_rotation_rad"), 5e-4 * 0.05 * 0.05 * 820 / 7.2e-5, 1e-6);
  EXPECT_DOUBLE_EQ(MetricValue(result, "max_ball_torque_Nm"), 5e-4);
  // A single 1e-4 N m kick at the last step turns it by 1e-4 x 0.05^2 / 7.2e-5 = 3.5e-3 rad:
  // passes.
  Trajectory kicked = t;
  kicked.tau[39](vs + 2) = 1e-4;
  EXPECT_TRUE(EvaluateTask(config, kicked).task_success);
  // A phantom lift of 0.01 N over the horizon would move the ball 0.41 m: fails.
  Trajectory lifted = t;
  for (int k = 0; k < config.problem.num_steps; ++k) lifted.tau[k](vs + 5) = 0.01;
  result = EvaluateTask(config, lifted);
  EXPECT_FALSE(result.task_success);
  EXPECT_GT(MetricValue(result, "phantom_displacement_m"), 0.01);
}

}  // namespace
}  // namespace idto
