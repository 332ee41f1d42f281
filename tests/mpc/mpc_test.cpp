// MPC building blocks: cubic splines, PD+, the real-time-iteration controller's warm start.

#include <cmath>
#include <limits>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "idto/mpc/controller.hpp"
#include "support/eigen_matchers.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto::mpc {
namespace {

using test::Pendulum;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

TEST(CubicSpline, InterpolatesKnotsAndIsTwiceContinuouslyDifferentiable) {
  test::Random rng(1);
  std::vector<double> t{0.0};
  for (int i = 1; i < 9; ++i) t.push_back(t.back() + rng.Uniform(0.05, 0.3));
  std::vector<Eigen::VectorXd> x;
  for (size_t i = 0; i < t.size(); ++i) x.push_back(rng.Vector(3));
  const CubicSpline s(t, x);
  Eigen::VectorXd y, yd, ydd, yl, ydl, yddl, yr, ydr, yddr;
  for (size_t i = 0; i < t.size(); ++i) {
    s.Evaluate(t[i], &y, &yd, &ydd);
    EXPECT_EIGEN_NEAR(y, x[i], 1e-14);
    if (i == 0 || i + 1 == t.size()) {
      EXPECT_EIGEN_NEAR(ydd, Eigen::VectorXd::Zero(3), 1e-12);  // natural ends
      continue;
    }
    const double e = 1e-9;
    s.Evaluate(t[i] - e, &yl, &ydl, &yddl);
    s.Evaluate(t[i] + e, &yr, &ydr, &yddr);
    // Sampled 2e-9 apart: differences are O(2e-9 x the next derivative) if continuous, O(1)
    // otherwise.
    EXPECT_EIGEN_NEAR(yl, yr, 1e-6);
    EXPECT_EIGEN_NEAR(ydl, ydr, 1e-5);
    EXPECT_EIGEN_NEAR(yddl, yddr, 1e-4);
  }
  // Derivatives against finite differences inside an interval.
  const double tm = 0.5 * (t[3] + t[4]), h = 1e-6;
  Eigen::VectorXd yp, ym;
  s.Evaluate(tm, &y, &yd, &ydd);
  s.Evaluate(tm + h, &yp);
  s.Evaluate(tm - h, &ym);
  EXPECT_EIGEN_NEAR(yd, Eigen::VectorXd((yp - ym) / (2 * h)), 1e-7);
  EXPECT_EIGEN_NEAR(ydd, Eigen::VectorXd((yp - 2 * y + ym) / (h * h)), 1e-3);
}

TEST(CubicSpline, ReproducesLinesExactlyAndExtendsLinearly) {
  std::vector<double> t{0.0, 0.1, 0.3, 0.35, 1.0};
  std::vector<Eigen::VectorXd> x;
  for (double ti : t) x.push_back(Eigen::Vector2d(2.0 * ti - 1.0, -ti));
  const CubicSpline s(t, x);
  Eigen::VectorXd y, yd;
  for (double ti : {-0.5, 0.0, 0.2, 0.77, 1.0, 1.4}) {
    s.Evaluate(ti, &y, &yd);
    EXPECT_EIGEN_NEAR(y, Eigen::Vector2d(2.0 * ti - 1.0, -ti), 1e-13) << ti;
    EXPECT_EIGEN_NEAR(yd, Eigen::Vector2d(2.0, -1.0), 1e-12) << ti;
  }
}

TEST(CubicSpline, BadKnotsAreErrors) {
  const std::vector<Eigen::VectorXd> two(2, Eigen::VectorXd::Zero(1));
  EXPECT_THAT(
      [&] {
        CubicSpline({0.0, 0.0}, two);
      },
      ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("times[1] is 0")));
  EXPECT_THAT([&] { CubicSpline({0.0}, {Eigen::VectorXd::Zero(1)}); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("at least 2")));
}

Model TwoLinkWithFreeBase() {
  ModelBuilder b;
  BodyInertia I;
  I.mass = 1.0;
  I.I_BBcm_B = Eigen::Matrix3d::Identity() * 0.01;
  JointSpec free;
  free.name = "base";
  free.type = JointType::kFloating;
  const BodyIndex base = b.AddBody("base", I, kWorldBody, free);
  JointSpec hinge;
  hinge.name = "hinge";
  hinge.type = JointType::kRevolute;
  hinge.axis = Eigen::Vector3d::UnitY();
  b.AddBody("arm", I, base, hinge);
  return b.Build();
}

TEST(PdController, SignsUnitsAndUnactuatedDofs) {
  const Model model = TwoLinkWithFreeBase();  // nq = 8, nv = 7; hinge: q index 7, v index 6
  PdGains gains{Eigen::VectorXd::Constant(7, 10.0), Eigen::VectorXd::Constant(7, 2.0)};
  const PdController pd(model, {6}, gains);
  Eigen::VectorXd q = model.NeutralConfiguration(), q_d = q;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(7), v_d = v, u_ff = Eigen::VectorXd::Zero(7);
  q_d(7) = 0.1;   // desired ahead of the measured angle: positive torque
  v_d(6) = -0.5;  // desired slower: negative damping term
  u_ff(6) = 3.0;
  u_ff(0) = 99.0;  // on an unactuated DoF: ignored
  Eigen::VectorXd u;
  pd.Compute(q, v, q_d, v_d, u_ff, &u);
  EXPECT_NEAR(u(6), 3.0 + 10.0 * 0.1 + 2.0 * (-0.5), 1e-15);
  EXPECT_EQ(u.head<6>().norm(), 0.0);
  EXPECT_THAT([&] { PdController(model, {0}, gains); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("floating")));
  gains.Kp(6) = -1.0;
  EXPECT_THAT([&] { PdController(model, {6}, gains); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("gains.Kp(6) is -1")));
}

ProblemDefinition SwingUp(const Model& model) {
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 20);
  p.Qq.setConstant(0.1);
  p.Qv.setConstant(0.1);
  p.R.setConstant(0.01);
  p.Qfq.setConstant(100.0);
  p.Qfv.setConstant(10.0);
  p.SetConstantNominal(Eigen::VectorXd::Constant(1, M_PI), Eigen::VectorXd::Zero(1));
  return p;
}

TEST(Controller, WarmStartIsThePreviousPlanShiftedInTime) {
  const Model model = Pendulum();
  const ProblemDefinition p = SwingUp(model);
  MpcOptions o;
  Controller c(model, p, SolverOptions{}, o);
  c.Initialize(std::vector<Eigen::VectorXd>(21, p.q_init), 30);
  const Plan before = c.plan();
  // Re-plan exactly one knot later, from the plan's own state there.
  const double t = p.time_step;
  c.Replan(t, before.q[1], before.v[1]);
  const std::vector<Eigen::VectorXd>& w = c.last_warm_start();
  for (int k = 0; k < 20; ++k) EXPECT_EIGEN_NEAR(w[k], before.q[k + 1], 1e-12) << k;
  // Past the old horizon: the spline's linear extension.
  EXPECT_NEAR(w[20](0), before.q[20](0) + (before.q[20](0) - before.q[19](0)), 0.05);
  EXPECT_DOUBLE_EQ(c.plan().start_time, t);
  // Sampling the new plan at its start gives the measured state (q_0 is fixed to it).
  Eigen::VectorXd q_d, v_d, u_ff;
  c.plan().Sample(model, t, &q_d, &v_d, &u_ff);
  EXPECT_EIGEN_NEAR(q_d, before.q[1], 1e-12);
}

// initial_iterations counts the cold start's iterations exactly: 0 publishes the guess itself (it
// used to run one iteration anyway); a negative count is refused.
TEST(Controller, InitialIterationsAreExact) {
  const Model model = Pendulum();
  const ProblemDefinition p = SwingUp(model);
  std::vector<Eigen::VectorXd> guess(21, p.q_init);
  for (int k = 0; k <= 20; ++k) guess[k](0) = 0.01 * k;
  for (const int n : {0, 1, 3}) {
    Controller c(model, p, SolverOptions{}, MpcOptions{});
    const SolverSummary s = c.Initialize(guess, n);
    EXPECT_EQ(s.iterations, n);
    if (n == 0) {
      for (int k = 0; k <= 20; ++k) EXPECT_EQ(c.plan().q[k], guess[k]) << k;
    } else {
      EXPECT_NE(c.plan().q[20], guess[20]);
    }
  }
  Controller c(model, p, SolverOptions{}, MpcOptions{});
  EXPECT_THAT([&] { c.Initialize(guess, -1); },
              ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("initial_iterations"), HasSubstr("-1"), HasSubstr(">= 0"))));
}

TEST(Controller, RelativeNominalsMoveWithTheMeasuredState) {
  const Model model = Pendulum();
  ProblemDefinition p = SwingUp(model);
  // Target: 2 rad ahead of the initial angle, kept ahead of wherever the pendulum is.
  p.SetConstantNominal(Eigen::VectorXd::Constant(1, 2.0), Eigen::VectorXd::Zero(1));
  MpcOptions o;
  o.relative_positions = {0};
  Controller c(model, p, SolverOptions{}, o);
  c.Initialize(std::vector<Eigen::VectorXd>(21, p.q_init), 5);
  c.Replan(0.05, Eigen::VectorXd::Constant(1, 0.7), Eigen::VectorXd::Zero(1));
  EXPECT_NEAR(c.optimizer().problem().q_nom[20](0), 2.7, 1e-15);
}

TEST(Controller, RelativeGoalsStopTheMovingNominal) {
  const Model model = Pendulum();
  ProblemDefinition p = SwingUp(model);
  // Offsets 0 at knot 0 up to 2 rad at knot 20 ahead of the measured angle, stopped at 2.5 rad.
  for (int k = 0; k <= 20; ++k) p.q_nom[k](0) = p.q_init(0) + 0.1 * k;
  MpcOptions o;
  o.relative_positions = {0};
  o.relative_goals = {{0, 2.5}};
  Controller c(model, p, SolverOptions{}, o);
  c.Initialize(std::vector<Eigen::VectorXd>(21, p.q_init), 5);
  c.Replan(0.05, Eigen::VectorXd::Constant(1, 0.7), Eigen::VectorXd::Zero(1));
  const std::vector<Eigen::VectorXd>& q_nom = c.optimizer().problem().q_nom;
  for (int k = 0; k <= 20; ++k) EXPECT_NEAR(q_nom[k](0), std::min(0.7 + 0.1 * k, 2.5), 1e-14);
  // Past the goal, every knot's target is the goal (the robot is brought back).
  c.Replan(0.1, Eigen::VectorXd::Constant(1, 3.0), Eigen::VectorXd::Zero(1));
  for (int k = 0; k <= 20; ++k) EXPECT_EQ(c.optimizer().problem().q_nom[k](0), 2.5);
  // Negative offsets stop at a goal below the start (q_init = 0).
  for (int k = 0; k <= 20; ++k) p.q_nom[k](0) = p.q_init(0) - 0.1 * k;
  o.relative_goals = {{0, -1.0}};
  Controller d(model, p, SolverOptions{}, o);
  d.Initialize(std::vector<Eigen::VectorXd>(21, p.q_init), 5);
  d.Replan(0.05, Eigen::VectorXd::Constant(1, 0.2), Eigen::VectorXd::Zero(1));
  for (int k = 0; k <= 20; ++k) {
    EXPECT_NEAR(d.optimizer().problem().q_nom[k](0), std::max(0.2 - 0.1 * k, -1.0), 1e-14);
  }
}

TEST(Controller, RelativeGoalsAreValidated) {
  const Model model = Pendulum();
  const ProblemDefinition p = SwingUp(model);
  MpcOptions o;
  o.relative_goals = {{0, 1.0}};  // position 0 is not relative
  EXPECT_THAT(
      [&] { Controller(model, p, SolverOptions{}, o); },
      ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("relative_goals[0].position")));
  o.relative_positions = {0};
  o.relative_goals = {{0, 1.0}, {0, 2.0}};
  EXPECT_THAT(
      [&] { Controller(model, p, SolverOptions{}, o); },
      ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("relative_goals[1].position")));
  o.relative_goals = {{0, std::numeric_limits<double>::quiet_NaN()}};
  EXPECT_THAT([&] { Controller(model, p, SolverOptions{}, o); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("relative_goals[0].goal")));
}

TEST(LeadOrientation, TurnsTowardsTheTargetByAtMostTheLead) {
  const Eigen::Quaterniond measured(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
  // A target 0.4 rad away (about z, applied on the left): returned as is when within the lead.
  const Eigen::Quaterniond target =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ())) * measured;
  EXPECT_TRUE(LeadOrientation(measured, target, 0.5).isApprox(target, 1e-15));
  const Eigen::Quaterniond led = LeadOrientation(measured, target, 0.1);
  const Eigen::Quaterniond expected =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ())) * measured;
  EXPECT_NEAR(led.angularDistance(expected), 0.0, 1e-12);
  EXPECT_NEAR(led.angularDistance(measured), 0.1, 1e-12);
  EXPECT_NEAR(led.angularDistance(target), 0.3, 1e-12);
  // The sign of a quaternion does not matter: -target is the same orientation.
  const Eigen::Quaterniond minus(-target.w(), -target.x(), -target.y(), -target.z());
  EXPECT_NEAR(LeadOrientation(measured, minus, 0.1).angularDistance(expected), 0.0, 1e-12);
  // The shortest way round: a target 3 rad about -z is reached by turning about -z.
  const Eigen::Quaterniond far(Eigen::AngleAxisd(-3.0, Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond step = LeadOrientation(Eigen::Quaterniond::Identity(), far, 0.5);
  EXPECT_NEAR(
      step.angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(-0.5, Eigen::Vector3d::UnitZ()))),
      0.0, 1e-12);
}

// A free ball (no gravity, no contact) whose nominal orientation is 3 rad about z away.
Model FreeBall() { return test::FreeBodyWithoutGravity(); }

TEST(Controller, OrientationLeadsMoveTheNominalAheadOfTheMeasuredOrientation) {
  const Model model = FreeBall();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 10);
  const Eigen::Quaterniond target(Eigen::AngleAxisd(3.0, Eigen::Vector3d::UnitZ()));
  Eigen::VectorXd q_target = p.q_init;
  q_target.head<4>() << target.w(), target.x(), target.y(), target.z();
  q_target.tail<3>() << 0.1, 0.2, 0.3;
  p.SetConstantNominal(q_target, Eigen::VectorXd::Zero(6));
  MpcOptions o;
  o.orientation_leads = {{0, 0.5}};
  Controller c(model, p, SolverOptions{}, o);
  c.Initialize(std::vector<Eigen::VectorXd>(11, p.q_init), 2);
  // Measured: 2.7 rad about z, the position elsewhere. Every knot's nominal: 0.3 rad further
  // (the target is within the lead), with a sign continuous with the measured quaternion;
  // positions are the problem's.
  const Eigen::Quaterniond at(Eigen::AngleAxisd(2.7, Eigen::Vector3d::UnitZ()));
  Eigen::VectorXd q_hat = p.q_init;
  q_hat.head<4>() << -at.w(), -at.x(), -at.y(), -at.z();
  c.Replan(0.05, q_hat, Eigen::VectorXd::Zero(6));
  for (const Eigen::VectorXd& q : c.optimizer().problem().q_nom) {
    const Eigen::Quaterniond Q(q(0), q(1), q(2), q(3));
    EXPECT_NEAR(Q.angularDistance(target), 0.0, 1e-12);
    EXPECT_GT(q.head<4>().dot(q_hat.head<4>()), 0.0);
    EXPECT_EIGEN_NEAR(Eigen::Vector3d(q.tail<3>()), Eigen::Vector3d(0.1, 0.2, 0.3), 0.0);
  }
  // From the start (3 rad away): 0.5 rad ahead about +z, the shortest way.
  c.Replan(0.1, p.q_init, Eigen::VectorXd::Zero(6));
  const Eigen::Quaterniond lead(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  for (const Eigen::VectorXd& q : c.optimizer().problem().q_nom) {
    EXPECT_NEAR(Eigen::Quaterniond(q(0), q(1), q(2), q(3)).angularDistance(lead), 0.0, 1e-12);
    EXPECT_GT(q(0), 0.0);
  }
}

TEST(Controller, OrientationLeadsAreValidated) {
  const Model model = FreeBall();
  const ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 10);
  MpcOptions o;
  o.orientation_leads = {{1, 0.5}};  // not the first index of a quaternion
  EXPECT_THAT([&] { Controller(model, p, SolverOptions{}, o); },
              ::testing::ThrowsMessage<std::invalid_argument>(
                  HasSubstr("orientation_leads[0].position_start")));
  o.orientation_leads = {{0, 0.0}};
  EXPECT_THAT(
      [&] { Controller(model, p, SolverOptions{}, o); },
      ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("orientation_leads[0].max_angle")));
}

TEST(Controller, AFailedReplanKeepsThePreviousPlan) {
  const Model model = Pendulum();
  const ProblemDefinition p = SwingUp(model);
  Controller c(model, p, SolverOptions{}, MpcOptions{});
  c.Initialize(std::vector<Eigen::VectorXd>(21, p.q_init), 3);
  const double start = c.plan().start_time;
  const Eigen::VectorXd q0 = c.plan().q[3];
  // A measured angle so large that velocities overflow: the cost is not finite.
  const SolverSummary s =
      c.Replan(0.05, Eigen::VectorXd::Constant(1, 1e300), Eigen::VectorXd::Zero(1));
  EXPECT_EQ(s.termination, TerminationType::kFailure);
  EXPECT_THAT(s.message, HasSubstr("previous plan is kept"));
  EXPECT_EQ(c.plan().start_time, start);
  EXPECT_EQ(c.plan().q[3], q0);
  EXPECT_EQ(c.num_rejected_plans(), 1);
  for (const Eigen::VectorXd& q : c.plan().q) EXPECT_TRUE(q.allFinite());
}

}  // namespace
}  // namespace idto::mpc
