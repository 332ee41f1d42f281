// Closed loop: the spinner example against the built-in plant makes progress; the latency
// model and logs; the estimator. (The mpc: section's keys and errors:
// tests/config/mpc_config_test.cpp.)

#include <algorithm>
#include <cmath>
#include <fstream>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/config/mpc_config.hpp"
#include "idto/idto.hpp"
#include "idto/mpc/closed_loop.hpp"
#include "idto/sim/plant.hpp"
#include "support/test_models.hpp"

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
  // Timing itself is measured by benchmarks, not asserted here (a sanitizer build is slow); the
  // log's statistics are checked against their definitions on the logged solve times.
  ASSERT_FALSE(log.solve_time.empty());
  std::vector<double> sorted = log.solve_time;
  std::sort(sorted.begin(), sorted.end());
  int on_time = 0;
  for (double t : log.solve_time) on_time += t <= log.control_period ? 1 : 0;
  EXPECT_DOUBLE_EQ(log.fraction_on_time(), static_cast<double>(on_time) / sorted.size());
  EXPECT_DOUBLE_EQ(log.max_solve_time(), sorted.back());
  // The median, interpolated between the two middle entries for an even count.
  const size_t n = sorted.size();
  const double median = n % 2 == 1 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  EXPECT_NEAR(log.percentile_solve_time(50), median, 1e-15);
  const std::string csv = log.ToCsv(config.model);
  EXPECT_THAT(csv, HasSubstr("q_spinner_axle"));
  EXPECT_THAT(csv, HasSubstr("contact_"));
}

TEST(ClosedLoop, ADisturbancePushesThePlant) {
  // A free-floating ball (no contact, no gravity) pushed for 0.1 s by 1 N along x.
  const Model model = test::FreeBodyWithoutGravity();
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

// A plant that gives up after a number of steps, as MuJoCo does when it detects instability.
class FailingPlant final : public sim::Plant {
 public:
  FailingPlant(const Model& model, int steps_before_failure)
      : q_(model.NeutralConfiguration()),
        v_(Eigen::VectorXd::Zero(model.nv())),
        f_(Eigen::VectorXd::Zero(model.num_bodies())),
        left_(steps_before_failure) {}
  void Reset(const Eigen::VectorXd& q, const Eigen::VectorXd& v) override {
    q_ = q;
    v_ = v;
  }
  void Advance(double duration, const Eigen::VectorXd&, int, const Eigen::Vector3d&) override {
    if (left_-- <= 0)
      throw std::runtime_error("FailingPlant: unstable at t = " + std::to_string(t_));
    t_ += duration;
  }
  void SetExtraDamping(const Eigen::VectorXd& d) override { damping_ = d; }
  const Eigen::VectorXd& q() const override { return q_; }
  const Eigen::VectorXd& v() const override { return v_; }
  double time() const override { return t_; }
  const Eigen::VectorXd& contact_force_per_body() const override { return f_; }
  std::string name() const override { return "failing"; }
  Eigen::VectorXd damping_;

 private:
  Eigen::VectorXd q_, v_, f_;
  int left_;
  double t_{0.0};
};

TEST(ClosedLoop, APlantFailureStopsTheRunAndKeepsTheLog) {
  const ExampleConfig config = LoadSpinner();
  MpcConfig mpc = ParseMpcConfig(config);
  mpc.closed_loop.duration = 1.0;
  mpc.closed_loop.log_every = 1;
  mpc::Controller controller(config.model, config.problem, config.solver, mpc.controller);
  controller.Initialize(MakeInitialGuess(config), 5);
  FailingPlant plant(config.model, 120);
  plant.Reset(config.problem.q_init, config.problem.v_init);
  mpc::ClosedLoopLog log;
  ASSERT_NO_THROW(log = mpc::RunClosedLoop(config.model, mpc.closed_loop, &controller, &plant));
  EXPECT_THAT(log.failure, HasSubstr("FailingPlant: unstable"));
  EXPECT_NEAR(log.failure_time, 0.120, 1e-9);
  EXPECT_EQ(log.t.size(), 121u);  // every step up to and including the failing one
  // The PD's damping went to the plant (implicit), on the actuated DoFs only.
  const int elbow = config.model.GetPositionStart("finger_elbow");
  const int axle = config.model.GetPositionStart("spinner_axle");
  EXPECT_EQ(plant.damping_(elbow), mpc.controller.gains.Kd(elbow));
  EXPECT_EQ(plant.damping_(axle), 0.0);
}

// The spinner's closed loop on the built-in plant from the example's start, with a 20-iteration
// cold start.
mpc::ClosedLoopLog RunSpinner(const ExampleConfig& config, const MpcConfig& mpc) {
  std::unique_ptr<sim::Plant> plant = sim::MakeBuiltinPlant(config.model, mpc.builtin);
  plant->Reset(config.problem.q_init, config.problem.v_init);
  mpc::Controller controller(config.model, config.problem, config.solver, mpc.controller);
  controller.Initialize(MakeInitialGuess(config), 20);
  return mpc::RunClosedLoop(config.model, mpc.closed_loop, &controller, plant.get());
}

// The spinner's mpc section for a 0.5 s run with a fixed 2 ms latency (machine-independent).
MpcConfig ShortFixedLatencyRun(const ExampleConfig& config) {
  MpcConfig mpc = ParseMpcConfig(config);
  mpc.closed_loop.duration = 0.5;
  mpc.closed_loop.latency = mpc::LatencyModel::kFixed;
  mpc.closed_loop.fixed_latency = 0.002;
  return mpc;
}

TEST(ClosedLoop, FixedLatencyRunsAreReproducible) {
  const ExampleConfig config = LoadSpinner();
  const MpcConfig mpc = ShortFixedLatencyRun(config);
  const mpc::ClosedLoopLog a = RunSpinner(config, mpc);
  const mpc::ClosedLoopLog b = RunSpinner(config, mpc);
  ASSERT_EQ(a.q.size(), b.q.size());
  for (size_t k = 0; k < a.q.size(); ++k) {
    ASSERT_EQ(a.q[k], b.q[k]) << "log entry " << k;
    ASSERT_EQ(a.u[k], b.u[k]) << "log entry " << k;
  }
}

TEST(ClosedLoop, TheEstimatorFiltersTheControllersMeasurements) {
  // MpcOptions::Estimator: with 1 cm / 10 mrad of position noise, the PD+ commands jump with
  // every measurement; with the closed loop's PositionFilter (T = 0.1 s) the command's
  // step-to-step change is several times smaller. Same seed, same latency, both runs.
  const ExampleConfig config = LoadSpinner();
  MpcConfig mpc = ShortFixedLatencyRun(config);
  mpc.closed_loop.sensor_noise = {0.01, 0.0, 0.0};
  mpc.closed_loop.log_every = 1;
  auto command_jitter = [&](double time_constant) {
    mpc.controller.estimator.position_time_constant = time_constant;
    const mpc::ClosedLoopLog log = RunSpinner(config, mpc);
    double sum = 0.0;
    for (size_t k = 1; k < log.u.size(); ++k) sum += (log.u[k] - log.u[k - 1]).squaredNorm();
    return std::sqrt(sum / (log.u.size() - 1));
  };
  const double raw = command_jitter(0.0);
  const double filtered = command_jitter(0.1);
  EXPECT_LT(filtered, 0.3 * raw) << "raw " << raw << ", filtered " << filtered;
}

}  // namespace
}  // namespace idto
