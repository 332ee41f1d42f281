// The controller's hold law (mpc::MpcOptions::Hold) on the Allegro example: when the ball is at
// its target (or about to reach it) the published plan is a constant grasp with each fingertip at
// the configured distance from the measured ball centre; elsewhere the solver's plan is published;
// bad options name the field. (The closed-loop effect: docs/mpc.md, session 38.)

#include <cmath>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/config/config.hpp"
#include "idto/config/mpc_config.hpp"
#include "idto/core/errors.hpp"
#include "idto/idto.hpp"
#include "idto/mpc/controller.hpp"

namespace idto {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

const ExampleConfig& Allegro() {
  static const ExampleConfig config = LoadExampleConfig(
      std::string(IDTO_SOURCE_DIR) + "/examples/allegro/allegro.yaml", {IDTO_SOURCE_DIR});
  return config;
}

// The measured state of the hand at q_init with the ball turned by `angle` about the vertical
// from its target orientation (the controller's final nominal), spinning at `rate` about z.
void BallNearTarget(const ProblemDefinition& problem, int s, int vs, double angle, double rate,
                    Eigen::VectorXd* q, Eigen::VectorXd* v) {
  *q = problem.q_init;
  const Eigen::VectorXd& q_end = problem.q_nom.back();
  const Eigen::Quaterniond target(q_end(s), q_end(s + 1), q_end(s + 2), q_end(s + 3));
  const Eigen::Quaterniond turned =
      Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ())) * target;
  (*q).segment<4>(s) << turned.w(), turned.x(), turned.y(), turned.z();
  *v = Eigen::VectorXd::Zero(problem.v_init.size());
  (*v)(vs + 2) = rate;
}

class HoldLaw : public ::testing::Test {
 protected:
  void SetUp() override {
    const ExampleConfig& config = Allegro();
    const MpcConfig mpc = ParseMpcConfig(config);
    options_ = mpc.controller;
    options_.iterations_per_step = 1;
    ASSERT_GE(options_.hold.position_start, 0) << "examples/allegro/allegro.yaml: no mpc.hold";
    SolverOptions solver = config.mpc_solver.value_or(config.solver);
    solver.verbosity = 0;
    controller_ = std::make_unique<mpc::Controller>(ControllerModel(config),
                                                    ControllerProblem(config), solver, options_);
    controller_->Initialize(ControllerInitialGuess(config), 3);
    const Model& model = ControllerModel(config);
    s_ = options_.hold.position_start;
    vs_ = model.GetVelocityStart("ball_root_joint");
  }

  // Whether the published plan is the constant grasp: every knot the same, at rest.
  bool PlanIsGrasp() const {
    const mpc::Plan& plan = controller_->plan();
    for (size_t k = 0; k < plan.q.size(); ++k) {
      if (plan.q[k] != plan.q[0] || !plan.v[k].isZero(0.0)) return false;
    }
    return true;
  }

  mpc::MpcOptions options_;
  std::unique_ptr<mpc::Controller> controller_;
  int s_{-1}, vs_{-1};
};

TEST_F(HoldLaw, GraspsTheBallAtTheTargetAndHandsBackFarFromIt) {
  const ProblemDefinition& problem = ControllerProblem(Allegro());
  const Model& model = ControllerModel(Allegro());
  Eigen::VectorXd q, v;
  BallNearTarget(problem, s_, vs_, 0.02, 0.0, &q, &v);
  controller_->Replan(0.1, q, v);
  ASSERT_TRUE(PlanIsGrasp());
  // Each fingertip near distance - squeeze from the measured centre (the inverse kinematics'
  // pull towards q_init leaves up to about 2 mm: measured 0.05, 0.1 and 1.7 mm on the index,
  // ring and thumb tips), the ball where it was measured, the feed-forward holding the fingers
  // against gravity.
  const mpc::Plan& plan = controller_->plan();
  Data data(model);
  ForwardKinematics(model, plan.q[0], &data);
  const Eigen::Vector3d centre = q.segment<3>(s_ + 4);
  const mpc::MpcOptions::Hold& h = options_.hold;
  for (size_t f = 0; f < h.tips.size(); ++f) {
    const double d = (data.X_WB(h.tips[f]).translation() - centre).norm();
    EXPECT_NEAR(d, h.distance - h.squeeze[f], 2.5e-3) << model.body_name(h.tips[f]);
  }
  EXPECT_TRUE(plan.q[0].segment<7>(s_).isApprox(q.segment<7>(s_), 1e-15));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv());
  const Eigen::VectorXd gravity = InverseDynamics(model, plan.q[0], zero, zero, &data);
  EXPECT_TRUE(plan.tau[0].head(16).isApprox(gravity.head(16), 1e-12));
  EXPECT_TRUE(plan.tau[0].tail(6).isZero(0.0));  // the ball is unactuated

  // Half a turn away (beyond the exit angle): the solver's plan again.
  BallNearTarget(problem, s_, vs_, 1.0, 0.0, &q, &v);
  controller_->Replan(0.2, q, v);
  EXPECT_FALSE(PlanIsGrasp());
}

TEST_F(HoldLaw, StartsEarlyForABallSpinningTowardsTheTarget) {
  const ProblemDefinition& problem = ControllerProblem(Allegro());
  const double enter = options_.hold.enter_angle, predict = options_.hold.predict;
  ASSERT_GT(predict, 0.0);
  // Outside the enter angle: turning away, not held; turning towards it fast enough to cross the
  // enter angle within `predict` seconds, held. (The ball sits at +angle about z from the
  // target, so a negative rate about z brings it closer.)
  const double angle = enter + 0.02, rate = 2.0 * 0.02 / predict;
  Eigen::VectorXd q, v;
  BallNearTarget(problem, s_, vs_, angle, +rate, &q, &v);
  controller_->Replan(0.1, q, v);
  EXPECT_FALSE(PlanIsGrasp());
  BallNearTarget(problem, s_, vs_, angle, -rate, &q, &v);
  controller_->Replan(0.2, q, v);
  EXPECT_TRUE(PlanIsGrasp());
}

TEST(HoldLawOptions, BadValuesNameTheField) {
  const ExampleConfig& config = Allegro();
  const Model& model = ControllerModel(config);
  const mpc::MpcOptions good = ParseMpcConfig(config).controller;
  EXPECT_NO_THROW(good.Validate(model));
  const auto expect_throw = [&](const auto& change, const std::string& message) {
    mpc::MpcOptions o = good;
    change(&o);
    EXPECT_THAT([&] { o.Validate(model); }, ThrowsMessage<InvalidArgument>(HasSubstr(message)));
  };
  expect_throw([](mpc::MpcOptions* o) { o->hold.squeeze.pop_back(); }, "hold.tips");
  expect_throw([](mpc::MpcOptions* o) { o->hold.exit_angle = o->hold.enter_angle; },
               "hold.exit_angle");
  expect_throw([](mpc::MpcOptions* o) { o->hold.position_start = 0; }, "hold.position_start");
  expect_throw([](mpc::MpcOptions* o) { o->hold.seek_step = -1.0; }, "hold.seek_step");
  expect_throw([](mpc::MpcOptions* o) { o->hold.squeeze[0] = NAN; }, "hold.squeeze[0]");
  expect_throw([&](mpc::MpcOptions* o) { o->hold.tips[0] = model.num_bodies(); }, "hold.tips[0]");
  // A tip no actuated joint moves: the ball itself.
  mpc::MpcOptions o = good;
  o.hold.tips[0] = model.GetBodyIndex("ball");
  const ProblemDefinition& problem = ControllerProblem(config);
  EXPECT_THAT([&] { mpc::Controller(model, problem, config.solver, o); },
              ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("options.hold.tips[0]"), HasSubstr("0 actuated DoFs"))));
}

TEST(HoldLawOptions, YamlKeysAndErrors) {
  const mpc::MpcOptions::Hold& h = ParseMpcConfig(Allegro()).controller.hold;
  EXPECT_EQ(h.tips.size(), 4u);
  EXPECT_EQ(h.squeeze.size(), 4u);
  EXPECT_DOUBLE_EQ(h.enter_angle, 0.06);
  EXPECT_DOUBLE_EQ(h.predict, 0.12);
  EXPECT_DOUBLE_EQ(h.seek_step, 0.0002);
  const std::string path = std::string(IDTO_SOURCE_DIR) + "/examples/allegro/allegro.yaml";
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto load_with = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const size_t at = t.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    const std::string file = ::testing::TempDir() + "/allegro_hold.yaml";
    std::ofstream(file) << t;
    ParseMpcConfig(LoadExampleConfig(file, {IDTO_SOURCE_DIR}));
  };
  EXPECT_THAT([&] { load_with("ring_tip: 0.0005", "ring_tipp: 0.0005"); },
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("mpc.hold.squeeze.ring_tipp"), HasSubstr("expected a body"))));
  EXPECT_THAT(
      [&] { load_with("joint: ball_root_joint", "joint: index_joint0"); },
      ThrowsMessage<FileError>(AllOf(HasSubstr("mpc.hold.joint"), HasSubstr("a floating joint"))));
  EXPECT_THAT([&] { load_with("seek_step: 0.0002", "seek_steps: 0.0002"); },
              ThrowsMessage<FileError>(HasSubstr("seek_steps")));
}

}  // namespace
}  // namespace idto
