// Closed loop: the spinner example against the built-in plant makes progress; the latency
// model and logs; the mpc: section's errors.

#include <cmath>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "idto/mpc/closed_loop.hpp"
#include "idto/parsers/mpc_config.hpp"
#include "idto/sim/plant.hpp"

namespace idto {
namespace {

using ::testing::HasSubstr;

ExampleConfig LoadSpinner() {
  return LoadExampleConfig(std::string(IDTO_SOURCE_DIR) + "/examples/spinner/spinner.yaml",
                           {std::string(IDTO_SOURCE_DIR)});
}

TEST(ClosedLoop, SpinnerOnTheBuiltinPlantKeepsSpinning) {
  const ExampleConfig config = LoadSpinner();
  MpcConfig mpc = ParseMpcConfig(config);
  mpc.closed_loop.duration = 1.5;
  mpc.closed_loop.latency = mpc::LatencyModel::kControlPeriod;  // machine-independent
  std::unique_ptr<sim::Plant> plant = sim::MakeBuiltinPlant(config.model, mpc.builtin);
  plant->Reset(config.problem.q_init, config.problem.v_init);
  mpc::Controller controller(config.model, config.problem, config.solver, mpc.controller);
  controller.Initialize(MakeInitialGuess(config), mpc.initial_iterations);
  const mpc::ClosedLoopLog log =
      mpc::RunClosedLoop(config.model, mpc.closed_loop, &controller, plant.get());
  const int spinner = config.model.GetPositionStart("spinner_axle");
  const double gained = plant->q()(spinner) - config.problem.q_init(spinner);
  EXPECT_GT(gained, 0.5) << "the spinner turned " << gained << " rad in 1.5 s";
  // Logs: one re-plan per control period (after t = 0), every state finite.
  EXPECT_NEAR(static_cast<double>(log.solve_time.size()), 1.5 * mpc.controller.control_rate - 1,
              1.0);
  EXPECT_EQ(log.num_rejected_plans, 0);
  for (const Eigen::VectorXd& q : log.q) ASSERT_TRUE(q.allFinite());
  // Timing itself is measured by benchmarks, not asserted here (a sanitizer build is slow).
  EXPECT_GE(log.fraction_on_time(), 0.0);
  EXPECT_LE(log.fraction_on_time(), 1.0);
  EXPECT_LE(log.percentile_solve_time(50), log.max_solve_time());
  const std::string csv = log.ToCsv(config.model);
  EXPECT_THAT(csv, HasSubstr("q_spinner_axle"));
  EXPECT_THAT(csv, HasSubstr("contact_"));
}

TEST(ClosedLoop, ADisturbancePushesThePlant) {
  // A free-floating ball (no contact, no gravity) pushed for 0.1 s by 1 N along x.
  ModelBuilder b;
  BodyInertia I;
  I.mass = 1.0;
  I.I_BBcm_B = Eigen::Matrix3d::Identity() * 0.01;
  JointSpec free;
  free.name = "free";
  free.type = JointType::kFloating;
  b.AddBody("ball", I, kWorldBody, free);
  b.SetGravity(Eigen::Vector3d::Zero());
  const Model model = b.Build();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 10);
  p.Qq.setConstant(1.0);
  p.R.setConstant(1.0);
  mpc::MpcOptions o;
  o.control_rate = 20;
  mpc::Controller controller(model, p, SolverOptions{}, o);
  controller.Initialize(std::vector<Eigen::VectorXd>(11, p.q_init), 5);
  std::unique_ptr<sim::Plant> plant = sim::MakeBuiltinPlant(model, sim::BuiltinPlantOptions{});
  plant->Reset(p.q_init, p.v_init);
  mpc::ClosedLoopOptions cl;
  cl.duration = 0.3;
  cl.disturbances.push_back({1, 0.0, 0.1, Eigen::Vector3d(1.0, 0.0, 0.0)});
  mpc::RunClosedLoop(model, cl, &controller, plant.get());
  // Unactuated: only the push acts. x = 1/2 a t^2 + a t (0.3 - 0.1) with a = 1 m/s^2.
  EXPECT_NEAR(plant->q()(4), 0.5 * 0.01 + 0.1 * 0.2, 2e-3);
  EXPECT_NEAR(plant->q()(5), 0.0, 1e-12);
}

TEST(MpcConfig, ErrorsNameTheKey) {
  ExampleConfig config = LoadSpinner();
  auto throws = [&](const std::string& yaml, const std::string& text) {
    config.mpc = yaml;
    EXPECT_THAT([&] { ParseMpcConfig(config); }, ::testing::ThrowsMessage<FileError>(AllOf(
                                                     HasSubstr("spinner.yaml"), HasSubstr(text))));
  };
  throws("control_rate: -5", "mpc.control_rate (line 1): is -5; expected a positive number");
  throws("plant: gazebo", "mpc.plant (line 1): is \"gazebo\"; expected mujoco or builtin");
  throws("no_such_key: 1", "mpc.no_such_key (line 1): is not a known key");
  throws("relative: [elbow]", "expected a joint of the scene");
  throws("kp: [1, 2]", "mpc.kp (line 1): is a list of 2 entries; expected nv = 3");
  throws("disturbances: [{body: nowhere, force: [1, 0, 0]}]", "expected a body of the scene");
  throws("latency: sometimes", "expected solve_time or control_period");
}

}  // namespace
}  // namespace idto
