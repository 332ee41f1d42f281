// The plants of idto/sim/plant.hpp: the built-in plant (semi-implicit Euler on idto's dynamics
// with a stiff compliant contact law) and, when idto was built with MuJoCo, the MuJoCo plant and
// the MJCF it loads.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#define IDTO_DEFINE_ALLOCATION_COUNTER
#include "idto/idto.hpp"
#include "idto/parsers/urdf.hpp"
#include "idto/sim/mjcf.hpp"
#include "idto/sim/plant.hpp"
#include "sim/plant_test_helpers.hpp"
#include "support/allocation_counter.hpp"
#include "support/eigen_matchers.hpp"
#include "support/mujoco_helpers.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using namespace plant_test;  // NOLINT(build/namespaces): the shared models

// ---------------------------------------------------------------------------------------------
// Built-in plant.

TEST(BuiltinPlant, ExtraDampingIsImplicit) {
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(SpinningRod(), {});
  CheckExtraDamping(plant.get());
  std::unique_ptr<Plant> ball = sim::MakeBuiltinPlant(BallModel(), {});
  EXPECT_THROW(ball->SetExtraDamping(Eigen::VectorXd::Constant(6, 1.0)), InvalidArgument);
}

TEST(BuiltinPlant, BallDroppedOnTheGroundComesToRest) {
  const Model model = BallModel();
  BuiltinPlantOptions options;
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, options);
  EXPECT_EQ(plant->name(), "builtin");
  plant->Reset(BallAt(0, 0, 0.5), Eigen::VectorXd::Zero(6));
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(6);
  Data data(model);
  const double e0 = MechanicalEnergy(model, plant->q(), plant->v(), &data);
  double max_energy_growth = 0.0;
  double min_height = 1.0;
  for (int i = 0; i < 2000; ++i) {  // 2 s in 1 ms control periods
    const double e = MechanicalEnergy(model, plant->q(), plant->v(), &data);
    plant->Advance(1e-3, u);
    max_energy_growth =
        std::max(max_energy_growth, MechanicalEnergy(model, plant->q(), plant->v(), &data) - e);
    min_height = std::min(min_height, plant->q()(6));
  }
  EXPECT_NEAR(plant->time(), 2.0, 1e-12);
  const double z_rest = RestingHeight(options.contact, kBallMass * 9.81);
  EXPECT_NEAR(plant->q()(6), z_rest, 1e-5);
  EXPECT_LT(plant->v().norm(), 1e-4);
  EXPECT_GT(min_height, kBallRadius - 0.01);  // the impact at 3.1 m/s penetrates < 1 cm
  // Energy never grows by more than the semi-implicit scheme's O(h) per step (it is not exactly
  // conservative for the stiff contact spring), and the ball loses most of it.
  EXPECT_LT(max_energy_growth, 1e-3 * e0);
  EXPECT_LT(MechanicalEnergy(model, plant->q(), plant->v(), &data),
            kBallMass * 9.81 * kBallRadius + 1e-3);
  // At rest the contact carries the weight: m g on the ball and on the world.
  const BodyIndex ball = model.GetBodyIndex("ball");
  EXPECT_NEAR(plant->contact_force_per_body()(ball), kBallMass * 9.81, 1e-3);
  EXPECT_NEAR(plant->contact_force_per_body()(kWorldBody), kBallMass * 9.81, 1e-3);
}

TEST(BuiltinPlant, EnergyNeverGrowsWithoutInput) {
  // A ball thrown sideways with spin: bounces, slides and rolls; kinetic plus potential energy
  // only decreases (up to the scheme's small per-step error), in both integration modes.
  const Model model = BallModel();
  for (const bool implicit : {true, false}) {
    SCOPED_TRACE(implicit ? "implicit contact damping" : "explicit");
    BuiltinPlantOptions options;
    options.implicit_contact = implicit;
    std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, options);
    Eigen::VectorXd v(6);
    v << 3.0, -5.0, 1.0, 1.5, 0.5, -2.0;  // w (world), v_WBo
    plant->Reset(BallAt(0, 0, 0.4), v);
    Data data(model);
    const double e0 = MechanicalEnergy(model, plant->q(), plant->v(), &data);
    double e_max = e0;
    double e = e0;
    for (int i = 0; i < 1500; ++i) {
      plant->Advance(1e-3, Eigen::VectorXd::Zero(6));
      e = MechanicalEnergy(model, plant->q(), plant->v(), &data);
      e_max = std::max(e_max, e);
      ASSERT_TRUE(plant->q().allFinite() && plant->v().allFinite()) << "step " << i;
    }
    EXPECT_LT(e_max, e0 * (1.0 + 1e-3));
    EXPECT_LT(e, 0.9 * e0);
    EXPECT_NEAR(plant->q()(6), RestingHeight(options.contact, kBallMass * 9.81), 1e-3);
  }
}

TEST(BuiltinPlant, PendulumSmallAnglePeriod) {
  // No contact: the period of small oscillations equals 2 pi / omega with omega^2 = -a / theta
  // from ForwardDynamics at a small angle (= m g l / (I + m l^2) for this rod).
  const Model model = PendulumModel();
  Data data(model);
  const double theta0 = 0.02;
  const double a = ForwardDynamics(model, Eigen::VectorXd::Constant(1, theta0),
                                   Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), &data)(0);
  const double omega = std::sqrt(-a / theta0);
  const double l = kPendulumHalfLength;
  const double I_pivot = kPendulumMass * std::pow(2 * l, 2) / 3.0;
  EXPECT_NEAR(omega * omega, kPendulumMass * 9.81 * l / I_pivot, 1e-4 * omega * omega);
  const double period = 2 * M_PI / omega;

  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, {});
  plant->Reset(Eigen::VectorXd::Constant(1, theta0), Eigen::VectorXd::Zero(1));
  // Upward zero crossings of theta, linearly interpolated.
  std::vector<double> crossings;
  double t_prev = 0.0;
  double theta_prev = theta0;
  double amplitude = 0.0;
  while (plant->time() < 5.0 * period) {
    plant->Advance(1e-3, Eigen::VectorXd::Zero(1));
    const double theta = plant->q()(0);
    amplitude = std::max(amplitude, std::abs(theta));
    if (theta_prev < 0.0 && theta >= 0.0) {
      crossings.push_back(t_prev + (plant->time() - t_prev) * (-theta_prev) / (theta - theta_prev));
    }
    t_prev = plant->time();
    theta_prev = theta;
  }
  ASSERT_GE(crossings.size(), 4u);
  const double measured = (crossings.back() - crossings.front()) / (crossings.size() - 1);
  EXPECT_NEAR(measured, period, 2e-3 * period);
  EXPECT_NEAR(amplitude, theta0, 1e-3 * theta0);  // no energy gained or lost
}

TEST(BuiltinPlant, FollowsForwardDynamicsWithoutContact) {
  // One step of size h: v1 = v0 + h ForwardDynamics(q0, v0, u) exactly (no damping, no contact).
  RandomTreeOptions o;
  o.num_bodies = 6;
  o.with_damping = false;
  const Model model = RandomTreeModel(31, o);
  BuiltinPlantOptions options;
  options.time_step = 1e-3;
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, options);
  Random rng(5);
  Data data(model);
  const Eigen::VectorXd q = RandomConfiguration(model, &rng);
  const Eigen::VectorXd v = rng.Vector(model.nv());
  const Eigen::VectorXd u = rng.Vector(model.nv(), -3.0, 3.0);
  plant->Reset(q, v);
  plant->Advance(1e-3, u);
  const Eigen::VectorXd a = ForwardDynamics(model, q, v, u, &data);
  EXPECT_EIGEN_NEAR_REL((plant->v() - v) / 1e-3, a, 1e-9);
  Eigen::VectorXd q1;
  Integrate(model, q, plant->v(), 1e-3, &q1);
  EXPECT_EIGEN_NEAR(plant->q(), q1, 1e-14);
}

TEST(BuiltinPlant, DisturbanceIsAForceAtTheBodyOrigin) {
  // Zero gravity, no contact, a body whose centre of mass is off its origin: the first step's
  // acceleration is ForwardDynamics with the generalized force of f at Bo.
  RandomTreeOptions o;
  o.num_bodies = 4;
  o.with_damping = false;
  o.gravity = Eigen::Vector3d::Zero();
  const Model model = RandomTreeModel(8, o);
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, {});
  Random rng(2);
  const Eigen::VectorXd q = RandomConfiguration(model, &rng);
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());
  const BodyIndex b = 3;
  const Eigen::Vector3d f(1.0, -2.0, 0.5);
  plant->Reset(q, v);
  plant->Advance(1e-3, Eigen::VectorXd::Zero(model.nv()), b, f);
  Data data(model);
  ForwardKinematics(model, q, &data);
  BodyForces F = BodyForces::Zero(6, model.num_bodies());
  F.col(b).tail<3>() = f;
  Eigen::VectorXd tau;
  GeneralizedForceFromBodyForces(model, F, &data, &tau);
  EXPECT_EIGEN_NEAR_REL(plant->v() / 1e-3, ForwardDynamics(model, q, v, tau, &data), 1e-9);
}

TEST(BuiltinPlant, DisturbancePushesTheBallAlongTheForce) {
  const Model model = BallModel();
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, {});
  CheckPushAlongY(model, plant.get(), 1e-3);
}

TEST(BuiltinPlant, ClockTakesWholeStepsNearestTheRequestedTime) {
  const Model model = PendulumModel();
  BuiltinPlantOptions options;
  options.time_step = 1e-3;
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, options);
  plant->Reset(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1));
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  for (int i = 1; i <= 60; ++i) {
    plant->Advance(1.0 / 60.0, u);  // a 60 Hz control period: 16.67 steps
    EXPECT_NEAR(plant->time(), i / 60.0, 0.5e-3 + 1e-12);
  }
  EXPECT_NEAR(plant->time(), 1.0, 1e-12);
  plant->Advance(0.0, u);
  EXPECT_NEAR(plant->time(), 1.0, 1e-12);
  plant->Reset(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1));
  EXPECT_EQ(plant->time(), 0.0);
}

TEST(BuiltinPlant, RejectsBadArguments) {
  const Model model = BallModel();
  BuiltinPlantOptions bad;
  bad.time_step = 0.0;
  EXPECT_THAT([&] { sim::MakeBuiltinPlant(model, bad); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("time_step")));
  bad = {};
  bad.contact.stiffness = -1.0;
  EXPECT_THROW(sim::MakeBuiltinPlant(model, bad), std::invalid_argument);
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, {});
  EXPECT_THROW(plant->Reset(Eigen::VectorXd::Zero(6), Eigen::VectorXd::Zero(6)),
               std::invalid_argument);
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(6);
  EXPECT_THAT([&] { plant->Advance(-1.0, u); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("duration")));
  EXPECT_THAT([&] { plant->Advance(0.01, Eigen::VectorXd::Zero(5)); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("u")));
  EXPECT_THAT([&] { plant->Advance(0.01, u, 7); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("disturbed_body")));
  EXPECT_THAT([&] { plant->Advance(0.01, u, -1, Eigen::Vector3d(NAN, 0, 0)); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("f_ext_W")));
}

TEST(BuiltinPlant, ScenePairFiltersHoldAndOnlyFrictionOverridesCarryOver) {
  // Two balls over the ground; the pair (ball_a, ground) is excluded: ball a falls through.
  const Model model = TwoBallsModel();
  BuiltinPlantOptions options;
  options.pairs.parameters.stiffness = 1.0;  // the planner's law: replaced by options.contact
  options.pairs.excluded_pairs = {{"ball_a", "ground"}};
  ContactParameterOverride soft;
  soft.a = "ball_b";
  soft.b = "ground";
  soft.stiffness = 10.0;  // dropped: the plant keeps its own law
  options.pairs.overrides = {soft};
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, options);
  Eigen::VectorXd q(14);
  q << BallAt(0, 0, 0.1), BallAt(1, 0, 0.1);
  plant->Reset(q, Eigen::VectorXd::Zero(12));
  plant->Advance(0.5, Eigen::VectorXd::Zero(12));
  EXPECT_LT(plant->q()(6), -0.5);  // ball a fell through the ground
  EXPECT_NEAR(plant->q()(13), RestingHeight(options.contact, 9.81), 1e-4);
}

TEST(BuiltinPlant, QuadrupedStandsUnderPdControl) {
  // The 8.25 kg quadruped dropped 1 cm onto the ground with joint PD control: the stiff contact
  // (feet with an apparent mass of 9 g) stays stable at 1 ms and the robot comes to rest.
  Model model;
  Eigen::VectorXd q_stand;
  QuadrupedModel(&model, &q_stand);
  q_stand(6) += 0.01;
  BuiltinPlantOptions options;
  options.pairs.included_pairs = {{"ground", "*"}};
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, options);
  plant->Reset(q_stand, Eigen::VectorXd::Zero(model.nv()));
  double max_speed_late = 0.0;
  StandWithPd(q_stand, 2500, plant.get(), &max_speed_late);
  EXPECT_NEAR(plant->q()(6), 0.30, 0.03);
  EXPECT_LT((plant->q().segment<2>(4)).norm(), 0.02);  // a slow rocking settles within 1.2 cm
  EXPECT_LT(max_speed_late, 5e-3);
  // Four feet carry the weight.
  double total = 0.0;
  for (const char* leg : {"FL", "FR", "HL", "HR"}) {
    const double f =
        plant->contact_force_per_body()(model.GetBodyIndex(std::string(leg) + "_foot"));
    EXPECT_GT(f, 5.0) << leg;
    total += f;
  }
  EXPECT_NEAR(total, 8.25 * 9.81, 0.5);
}

TEST(BuiltinPlant, ExplicitSchemeDivergesOnTheQuadrupedAndSaysSo) {
  // Documents why implicit_contact is the default: with every force explicit, the contact
  // damping (c / v_d) and friction (mu f_n / v_s) on the 9 g apparent mass of a foot exceed the
  // explicit stability limit at 1 ms. The plant throws and keeps the last finite state.
  Model model;
  Eigen::VectorXd q_stand;
  QuadrupedModel(&model, &q_stand);
  q_stand(6) += 0.01;
  BuiltinPlantOptions options;
  options.implicit_contact = false;
  options.pairs.included_pairs = {{"ground", "*"}};
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, options);
  plant->Reset(q_stand, Eigen::VectorXd::Zero(model.nv()));
  double max_speed_late = 0.0;
  EXPECT_THAT([&] { StandWithPd(q_stand, 1000, plant.get(), &max_speed_late); },
              ThrowsMessage<std::runtime_error>(HasSubstr("diverged")));
  EXPECT_TRUE(plant->q().allFinite() && plant->v().allFinite());
}

TEST(BuiltinPlant, RunawayFiniteStateCountsAsDivergedLikeMujoco) {
  // A finite but absurd command (a controller gone wrong) drives the pendulum's speed past 1e10
  // rad/s in one step. The plant must say so (MuJoCo's instability check uses the same bound)
  // rather than hand the closed loop a finite, meaningless state.
  const Model model = PendulumModel();
  std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, {});
  plant->Reset(Eigen::VectorXd::Constant(1, 0.1), Eigen::VectorXd::Zero(1));
  plant->Advance(1e-3, Eigen::VectorXd::Constant(1, 1e3));  // large but sane: accepted
  const Eigen::VectorXd q_good = plant->q(), v_good = plant->v();
  EXPECT_LT(std::abs(v_good(0)), 1e10);
  EXPECT_THAT([&] { plant->Advance(1e-3, Eigen::VectorXd::Constant(1, 1e15)); },
              ThrowsMessage<std::runtime_error>(AllOf(
                  HasSubstr("diverged"), HasSubstr("beyond 1e10"), HasSubstr("max |u| = 1e+15"))));
  EXPECT_EQ(plant->q(), q_good);  // the last good state is kept
  EXPECT_EQ(plant->v(), v_good);
}

TEST(BuiltinPlant, AdvanceDoesNotAllocate) {
  if (!test::AllocationCountingAvailable()) GTEST_SKIP() << "malloc is owned by a sanitizer";
  Model model;
  Eigen::VectorXd q_stand;
  QuadrupedModel(&model, &q_stand);
  for (const bool implicit : {true, false}) {
    BuiltinPlantOptions options;
    options.implicit_contact = implicit;
    std::unique_ptr<Plant> plant = sim::MakeBuiltinPlant(model, options);
    q_stand(6) -= 0.005;  // in contact
    plant->Reset(q_stand, Eigen::VectorXd::Zero(model.nv()));
    const Eigen::VectorXd u = Eigen::VectorXd::Constant(model.nv(), 0.1);
    plant->Advance(0.002, u, 1, Eigen::Vector3d(1, 2, 3));
    test::ScopedAllocationCounter counter;
    plant->Advance(0.02, u, 1, Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(counter.count(), 0) << (implicit ? "implicit" : "explicit");
  }
}

// ---------------------------------------------------------------------------------------------
// MJCF of the MuJoCo plant (no MuJoCo needed).

TEST(MujocoPlantMjcf, ExplicitPairsFollowTheSceneFilters) {
  const Model model = TwoBallsModel();
  MujocoPlantOptions options;
  options.friction_coefficient = 0.7;
  options.pairs.excluded_pairs = {{"ball_a", "ground"}};
  ContactParameterOverride slippery;
  slippery.a = "ball_b_sphere";
  slippery.b = "ball_a";
  slippery.friction_coefficient = 0.25;
  options.pairs.overrides = {slippery};
  const std::string xml = sim::MakeMujocoPlantMjcf(model, options);
  EXPECT_THAT(xml, HasSubstr("contype=\"0\" conaffinity=\"0\""));
  EXPECT_THAT(xml, Not(HasSubstr("contype=\"1\"")));
  EXPECT_THAT(xml, HasSubstr("<contact>"));
  EXPECT_THAT(xml, Not(HasSubstr("geom1=\"ball_a_sphere\" geom2=\"ground\"")));
  EXPECT_THAT(xml, Not(HasSubstr("geom1=\"ground\" geom2=\"ball_a_sphere\"")));
  const bool b_ground = xml.find("geom1=\"ball_b_sphere\" geom2=\"ground\"") != std::string::npos ||
                        xml.find("geom1=\"ground\" geom2=\"ball_b_sphere\"") != std::string::npos;
  EXPECT_TRUE(b_ground) << xml;
  EXPECT_THAT(xml, HasSubstr("friction=\"0.7 0.7 "));
  EXPECT_THAT(xml, HasSubstr("friction=\"0.25 0.25 "));
  EXPECT_THAT(xml, HasSubstr("timestep=\"0.001\""));
  EXPECT_THAT(xml, Not(HasSubstr("contact=\"disable\"")));
}

TEST(MujocoPlantMjcf, TorsionalAndRollingFrictionSelectTheContactDimension) {
  const Model model = BallModel();
  MujocoPlantOptions options;
  options.friction_coefficient = 0.5;
  // Defaults: sliding friction only (condim 3, MuJoCo's default unused coefficients).
  EXPECT_THAT(sim::MakeMujocoPlantMjcf(model, options),
              HasSubstr("condim=\"3\" friction=\"0.5 0.5 0.005 0.0001 0.0001\""));
  options.torsional_friction = 0.004;
  EXPECT_THAT(sim::MakeMujocoPlantMjcf(model, options),
              HasSubstr("condim=\"4\" friction=\"0.5 0.5 0.004 0.0001 0.0001\""));
  options.rolling_friction = 0.002;
  EXPECT_THAT(sim::MakeMujocoPlantMjcf(model, options),
              HasSubstr("condim=\"6\" friction=\"0.5 0.5 0.004 0.002 0.002\""));
  options.torsional_friction = 0.0;
  EXPECT_THAT(sim::MakeMujocoPlantMjcf(model, options),
              HasSubstr("condim=\"6\" friction=\"0.5 0.5 0 0.002 0.002\""));
  options.rolling_friction = -0.001;
  EXPECT_THAT([&] { sim::MakeMujocoPlantMjcf(model, options); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("options.rolling_friction")));
  options.rolling_friction = 0.0;
  options.torsional_friction = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT([&] { sim::MakeMujocoPlantMjcf(model, options); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("options.torsional_friction")));
  MjcfOptions mjcf;
  mjcf.contact_pairs = {{0, 1, 1.0, -0.1, 0.0}};
  EXPECT_THAT(
      [&] { MakeMjcf(model, mjcf); },
      ThrowsMessage<std::invalid_argument>(HasSubstr("contact_pairs[0].torsional_friction")));
  mjcf.contact_pairs = {{0, 1, 1.0, 0.0, std::numeric_limits<double>::infinity()}};
  EXPECT_THAT([&] { MakeMjcf(model, mjcf); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("contact_pairs[0].rolling_friction")));
}

TEST(MujocoPlantMjcf, FrictionConeIsEllipticUnlessAskedOtherwise) {
  const Model model = BallModel();
  MujocoPlantOptions options;
  EXPECT_THAT(sim::MakeMujocoPlantMjcf(model, options), HasSubstr(" cone=\"elliptic\""));
  options.friction_cone = "pyramidal";  // MuJoCo's default: no attribute
  EXPECT_THAT(sim::MakeMujocoPlantMjcf(model, options), Not(HasSubstr("cone=")));
  options.friction_cone = "Elliptic";
  EXPECT_THAT([&] { sim::MakeMujocoPlantMjcf(model, options); },
              ThrowsMessage<std::invalid_argument>(
                  AllOf(HasSubstr("options.friction_cone"), HasSubstr("'Elliptic'"))));
  MjcfOptions mjcf;
  mjcf.cone = "round";
  EXPECT_THAT([&] { MakeMjcf(model, mjcf); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("cone is 'round'")));
}

TEST(MujocoPlantMjcf, RejectsBadContactPairs) {
  const Model model = BallModel();
  MjcfOptions options;
  options.contact_pairs = {{0, 5, 1.0}};
  EXPECT_THAT([&] { MakeMjcf(model, options); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("contact_pairs[0]")));
  options.contact_pairs = {{0, 1, -1.0}};
  EXPECT_THAT([&] { MakeMjcf(model, options); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("friction_coefficient")));
  options.contact_pairs = {{0, 1, 1.0}};
  options.include_geometry = false;
  EXPECT_THROW(MakeMjcf(model, options), std::invalid_argument);
}

}  // namespace
}  // namespace idto
