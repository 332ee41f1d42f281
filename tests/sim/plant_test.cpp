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
#include "support/allocation_counter.hpp"
#include "support/eigen_matchers.hpp"
#include "support/mujoco_helpers.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using sim::BuiltinPlantOptions;
using sim::MujocoPlantOptions;
using sim::Plant;
using test::Random;
using test::RandomConfiguration;
using test::RandomTreeModel;
using test::RandomTreeOptions;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::ThrowsMessage;

constexpr double kBallRadius = 0.1;
constexpr double kBallMass = 1.0;

// A solid ball of radius 0.1 m and 1 kg on a floating joint, over a ground half-space.
Model BallModel(const Eigen::Vector3d& gravity = Eigen::Vector3d(0, 0, -9.81)) {
  ModelBuilder builder("ball_on_ground");
  builder.SetGravity(gravity);
  BodyInertia inertia;
  inertia.mass = kBallMass;
  inertia.I_BBcm_B = 0.4 * kBallMass * kBallRadius * kBallRadius * Eigen::Matrix3d::Identity();
  JointSpec joint;
  joint.name = "ball_joint";
  joint.type = JointType::kFloating;
  const BodyIndex ball = builder.AddBody("ball", inertia, kWorldBody, joint);
  builder.AddGeometry("ball_sphere", ball, Eigen::Isometry3d::Identity(), Sphere{kBallRadius});
  builder.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  return builder.Build();
}

// q of the ball model at height z (identity orientation).
Eigen::VectorXd BallAt(double x, double y, double z) {
  Eigen::VectorXd q(7);
  q << 1, 0, 0, 0, x, y, z;
  return q;
}

// A pendulum in code: a rod of length 2 l (uniform, mass m) hinged at one end about y.
constexpr double kPendulumHalfLength = 0.25;
constexpr double kPendulumMass = 2.0;
Model PendulumModel() {
  ModelBuilder builder("pendulum");
  BodyInertia inertia;
  inertia.mass = kPendulumMass;
  inertia.p_BBcm = Eigen::Vector3d(0, 0, -kPendulumHalfLength);
  const double I = kPendulumMass * std::pow(2 * kPendulumHalfLength, 2) / 12.0;
  inertia.I_BBcm_B = Eigen::Vector3d(I, I, 1e-4).asDiagonal();
  JointSpec joint;
  joint.name = "hinge";
  joint.axis = Eigen::Vector3d::UnitY();
  builder.AddBody("rod", inertia, kWorldBody, joint);
  return builder.Build();
}

// Kinetic plus gravitational potential energy.
double MechanicalEnergy(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                        Data* data) {
  const Eigen::MatrixXd& M = MassMatrix(model, q, data);
  double energy = 0.5 * v.dot(M * v);
  ForwardKinematics(model, q, data);
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const BodyInertia& inertia = model.body_inertia(b);
    energy -= inertia.mass * model.gravity().dot(data->X_WB(b) * inertia.p_BBcm);
  }
  return energy;
}

// The height at which the plant's contact law holds a ball of mass m at rest: c(phi) = m g.
double RestingHeight(const ContactParameters& p, double weight) {
  // c(phi) = sigma k log(1 + exp(-phi / sigma)) = W  ->  phi = -sigma log(exp(W / (sigma k)) - 1).
  const double phi = -p.smoothing * std::log(std::expm1(weight / (p.smoothing * p.stiffness)));
  return kBallRadius + phi;
}

std::string ModelPath(const std::string& file) {
  return std::string(IDTO_SOURCE_DIR) + "/models/" + file;
}

// The quadruped on a ground half-space, standing (examples/quadruped).
void QuadrupedModel(Model* model, Eigen::VectorXd* q_stand) {
  // A shipped file: when it is missing, ParseUrdf throws and the test fails (never skips).
  const std::string path = ModelPath("quadruped.urdf");
  ModelBuilder builder("quadruped_scene");
  UrdfOptions options;
  options.base = BaseType::kFloating;
  AddUrdfFile(path, options, &builder);
  builder.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  *model = builder.Build();
  *q_stand = model->NeutralConfiguration();
  (*q_stand)(model->GetPositionStart("body_root_joint") + 6) = 0.3056;
  for (const char* leg : {"FL", "FR", "HL", "HR"}) {
    (*q_stand)(model->GetPositionStart(std::string(leg) + "_hip_joint")) = -0.8;
    (*q_stand)(model->GetPositionStart(std::string(leg) + "_knee_joint")) = 1.6;
  }
}

// A rod spinning about a fixed axis without gravity: I v' = -d v.
Model SpinningRod() {
  ModelBuilder builder("rod");
  BodyInertia inertia;
  inertia.mass = 1.0;
  inertia.I_BBcm_B = Eigen::Vector3d(0.02, 0.02, 0.02).asDiagonal();
  JointSpec joint;
  joint.name = "axle";
  joint.axis = Eigen::Vector3d::UnitY();
  builder.AddBody("rod", inertia, kWorldBody, joint);
  builder.SetGravity(Eigen::Vector3d::Zero());
  return builder.Build();
}

// Extra damping d decays v like exp(-d t / I); with d h / I = 100 (an explicit step would
// diverge) the implicit step stays monotone. Checks Plant::SetExtraDamping of any plant.
void CheckExtraDamping(Plant* plant) {
  const double I = 0.02;
  plant->Reset(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 1.0));
  plant->SetExtraDamping(Eigen::VectorXd::Constant(1, 0.01));  // time constant 2 s
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  plant->Advance(1.0, u);
  EXPECT_NEAR(plant->v()(0), std::exp(-0.01 / I), 2e-3);
  plant->Reset(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 1.0));
  plant->SetExtraDamping(Eigen::VectorXd::Constant(1, 100 * I / 1e-3));
  double previous = 1.0;
  for (int i = 0; i < 20; ++i) {
    plant->Advance(1e-3, u);
    ASSERT_GE(plant->v()(0), 0.0);
    ASSERT_LE(plant->v()(0), previous);
    previous = plant->v()(0);
  }
  // Back to none: the rod keeps its speed.
  plant->SetExtraDamping(Eigen::VectorXd::Zero(1));
  plant->Reset(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 1.0));
  plant->Advance(0.1, u);
  EXPECT_NEAR(plant->v()(0), 1.0, 1e-12);
  // Bad arguments.
  EXPECT_THROW(plant->SetExtraDamping(Eigen::VectorXd::Zero(2)), InvalidArgument);
  EXPECT_THROW(plant->SetExtraDamping(Eigen::VectorXd::Constant(1, -1.0)), InvalidArgument);
  EXPECT_THROW(plant->SetExtraDamping(Eigen::VectorXd::Constant(1, NAN)), InvalidArgument);
}

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
  plant->Reset(BallAt(0, 0, 0.1), Eigen::VectorXd::Zero(6));
  plant->Advance(0.3, Eigen::VectorXd::Zero(6));  // settle
  const Eigen::Vector3d p0 = plant->q().tail<3>();
  const BodyIndex ball = model.GetBodyIndex("ball");
  plant->Advance(0.2, Eigen::VectorXd::Zero(6), ball, Eigen::Vector3d(0.0, 8.0, 0.0));
  const Eigen::Vector3d dp = plant->q().tail<3>() - p0;
  EXPECT_GT(dp.y(), 0.02);
  EXPECT_LT(std::abs(dp.x()), 1e-6);
  EXPECT_LT(std::abs(dp.z()), 1e-3);
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
  ModelBuilder builder("two_balls");
  BodyInertia inertia;
  inertia.mass = 1.0;
  inertia.I_BBcm_B = 0.004 * Eigen::Matrix3d::Identity();
  for (const char* name : {"ball_a", "ball_b"}) {
    JointSpec joint;
    joint.name = std::string(name) + "_joint";
    joint.type = JointType::kFloating;
    const BodyIndex b = builder.AddBody(name, inertia, kWorldBody, joint);
    builder.AddGeometry(std::string(name) + "_sphere", b, Eigen::Isometry3d::Identity(),
                        Sphere{0.1});
  }
  builder.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  const Model model = builder.Build();
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

// Runs the quadruped under joint PD control towards q_stand for `steps` 1 ms steps.
void StandWithPd(const Eigen::VectorXd& q_stand, int steps, Plant* plant,
                 double* max_base_speed_late) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(plant->v().size());
  *max_base_speed_late = 0.0;
  for (int i = 0; i < steps; ++i) {
    u.tail(12) = 60.0 * (q_stand.tail(12) - plant->q().tail(12)) - 2.0 * plant->v().tail(12);
    plant->Advance(1e-3, u);
    ASSERT_TRUE(plant->q().allFinite()) << "step " << i;
    if (i >= steps - 300) {
      *max_base_speed_late = std::max(*max_base_speed_late, plant->v().head<6>().norm());
    }
  }
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
  ModelBuilder builder("two_balls");
  BodyInertia inertia;
  inertia.mass = 1.0;
  inertia.I_BBcm_B = 0.004 * Eigen::Matrix3d::Identity();
  for (const char* name : {"ball_a", "ball_b"}) {
    JointSpec joint;
    joint.name = std::string(name) + "_joint";
    joint.type = JointType::kFloating;
    const BodyIndex b = builder.AddBody(name, inertia, kWorldBody, joint);
    builder.AddGeometry(std::string(name) + "_sphere", b, Eigen::Isometry3d::Identity(),
                        Sphere{0.1});
  }
  builder.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  const Model model = builder.Build();
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

// ---------------------------------------------------------------------------------------------
// MuJoCo plant.

#ifdef IDTO_HAVE_MUJOCO

TEST(MujocoPlant, ExtraDampingIsImplicit) {
  std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(SpinningRod(), {});
  CheckExtraDamping(plant.get());
  // Not on a multi-DoF joint.
  std::unique_ptr<Plant> ball = sim::MakeMujocoPlant(BallModel(), {});
  EXPECT_THROW(ball->SetExtraDamping(Eigen::VectorXd::Constant(6, 1.0)), InvalidArgument);
}

// The hopper (models/hopper.urdf, planar base) standing on its level foot, its knee and ankle
// held by PD with the damping handed to the plant as extra (implicit) damping, as the closed loop
// does. Returns the standard deviation of the foot's contact force and the largest ankle speed
// over the last `window` steps of `steps` 1 ms steps.
void HoldHopper(Plant* plant, const Model& model, double kp, double kd, int steps, int window,
                double* force_sd, double* max_ankle_speed) {
  Eigen::VectorXd q0(5);
  // Base height with the foot spheres' lowest points exactly on the ground (models/README.md).
  q0 << 0.0, 0.25 * std::cos(0.3) + 0.3 * std::cos(0.2) + 0.08, 0.3, -0.5, 0.2;
  plant->Reset(q0, Eigen::VectorXd::Zero(5));
  Eigen::VectorXd d = Eigen::VectorXd::Zero(5);
  d.tail<2>().setConstant(kd);
  plant->SetExtraDamping(d);
  const BodyIndex foot = model.GetBodyIndex("foot");
  Eigen::VectorXd u = Eigen::VectorXd::Zero(5);
  double sum = 0.0, sum2 = 0.0;
  *max_ankle_speed = 0.0;
  for (int i = 0; i < steps; ++i) {
    u.tail<2>() = kp * (q0.tail<2>() - plant->q().tail<2>());
    plant->Advance(1e-3, u);
    ASSERT_TRUE(plant->q().allFinite()) << "step " << i;
    if (i >= steps - window) {
      const double f = plant->contact_force_per_body()(foot);
      sum += f;
      sum2 += f * f;
      *max_ankle_speed = std::max(*max_ankle_speed, std::abs(plant->v()(4)));
    }
  }
  *force_sd = std::sqrt(std::max(0.0, sum2 / window - (sum / window) * (sum / window)));
}

TEST(MujocoPlant, StiffImplicitDampingKeepsALightFootQuietOnTheGround) {
  // The hopper's 0.1 kg foot under an ankle damper of 10 N m s/rad: h d / I is about 24 at 1 ms.
  // The damping must be implicit in the same step as the contact forces: applied after MuJoCo's
  // constraint solve (its own implicit dof_damping), the foot chattered on the ground (contact
  // force varying by tens of N under a 12.75 N robot) and the closed-loop hopper tumbled.
  const std::string path = ModelPath("hopper.urdf");
  ModelBuilder builder("hopper_scene");
  UrdfOptions urdf;
  urdf.base = BaseType::kPlanar;
  urdf.planar_normal = Eigen::Vector3d(0, -1, 0);
  AddUrdfFile(path, urdf, &builder);
  builder.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  const Model model = builder.Build();
  MujocoPlantOptions options;
  options.pairs.included_pairs = {{"ground", "*"}};
  std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(model, options);
  const double weight = 1.3 * 9.81;
  for (const double kd : {1.0, 5.0, 10.0}) {
    double force_sd = 0.0, max_ankle_speed = 0.0;
    HoldHopper(plant.get(), model, 100.0, kd, 1500, 500, &force_sd, &max_ankle_speed);
    EXPECT_LT(force_sd, 0.02 * weight) << "kd " << kd;
    EXPECT_LT(max_ankle_speed, 0.02) << "kd " << kd;
    EXPECT_NEAR(plant->contact_force_per_body()(model.GetBodyIndex("foot")), weight, 0.05 * weight)
        << "kd " << kd;
  }
}

TEST(MujocoPlant, Available) {
  EXPECT_TRUE(sim::HaveMujoco());
  std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(BallModel(), {});
  EXPECT_EQ(plant->name(), "mujoco");
}

TEST(MujocoPlant, BallDroppedOnTheGroundComesToRest) {
  const Model model = BallModel();
  std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(model, {});
  plant->Reset(BallAt(0.1, -0.2, 0.5), Eigen::VectorXd::Zero(6));
  EXPECT_EIGEN_NEAR(plant->q(), BallAt(0.1, -0.2, 0.5), 1e-15);
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(6);
  Data data(model);
  const double e0 = MechanicalEnergy(model, plant->q(), plant->v(), &data);
  double e_max = e0;
  for (int i = 0; i < 100; ++i) {
    plant->Advance(0.02, u);
    e_max = std::max(e_max, MechanicalEnergy(model, plant->q(), plant->v(), &data));
  }
  EXPECT_NEAR(plant->time(), 2.0, 1e-12);
  // MuJoCo's soft constraints let the ball sink a little (default solref / solimp: < 1 mm).
  EXPECT_NEAR(plant->q()(6), kBallRadius, 2e-3);
  EXPECT_NEAR(plant->q()(4), 0.1, 1e-6);
  EXPECT_NEAR(plant->q()(5), -0.2, 1e-6);
  EXPECT_LT(plant->v().norm(), 1e-3);
  EXPECT_LT(e_max, e0 * (1.0 + 1e-6));
  const BodyIndex ball = model.GetBodyIndex("ball");
  EXPECT_NEAR(plant->contact_force_per_body()(ball), kBallMass * 9.81, 0.05);
  EXPECT_NEAR(plant->contact_force_per_body()(kWorldBody), kBallMass * 9.81, 0.05);
}

// A ball set rolling on the ground (v = w x r, no slip) keeps rolling with sliding friction only
// (a point contact resists no roll); rolling friction stops it, and torsional friction stops a
// ball spinning about the vertical.
TEST(MujocoPlant, RollingAndTorsionalFrictionStopARollingAndASpinningBall) {
  const Model model = BallModel();
  auto final_speed = [&](double torsional, double rolling, const Eigen::Vector3d& w) {
    MujocoPlantOptions options;
    options.torsional_friction = torsional;
    options.rolling_friction = rolling;
    std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(model, options);
    Eigen::VectorXd v(6);
    v << w, w.cross(Eigen::Vector3d(0, 0, kBallRadius));  // contact point at rest
    plant->Reset(BallAt(0, 0, kBallRadius), v);
    plant->Advance(1.0, Eigen::VectorXd::Zero(6));
    return plant->v().head<3>().norm();
  };
  const Eigen::Vector3d roll(2.0, 0.0, 0.0);  // rad/s about x: rolls along -y at 0.2 m/s
  EXPECT_GT(final_speed(0.0, 0.0, roll), 1.9);
  // Rolling resistance 0.01 m x 9.81 N on I + m r^2 = 0.014 kg m^2 would stop it in 0.3 s;
  // MuJoCo's soft constraints let it creep (measured: 0.13 rad/s after 1 s); with 0.03 m it
  // stops (measured: 4e-10 rad/s).
  EXPECT_LT(final_speed(0.0, 0.01, roll), 0.2);
  EXPECT_LT(final_speed(0.0, 0.03, roll), 1e-3);
  const Eigen::Vector3d spin(0.0, 0.0, 2.0);  // about the vertical
  EXPECT_GT(final_speed(0.0, 0.0, spin), 1.9);
  EXPECT_LT(final_speed(0.01, 0.0, spin), 1e-3);  // measured: 3e-5 rad/s
}

// Coulomb's friction does not depend on the sliding direction. A ball thrown without spin slides
// until its contact point stops (~0.146 s here): meanwhile its centre decelerates at mu g whichever
// way it moves. MuJoCo's elliptic cone (the plant's default) does that (measured: the same speed,
// 0.8986 m/s, in every direction, 3 % more deceleration than mu g while the soft contact
// settles); its pyramidal cone bounds each of the contact frame's two tangential components
// instead, and brakes a diagonal throw less (measured: 0.9023 m/s along x, 0.9319 diagonally).
TEST(MujocoPlant, EllipticConeFrictionDoesNotDependOnTheSlidingDirection) {
  const Model model = BallModel();
  constexpr double kMu = 0.2, kSpeed = 1.0, kTime = 0.05;
  auto speed_after = [&](const std::string& cone, double angle) {
    MujocoPlantOptions options;
    options.friction_coefficient = kMu;
    options.friction_cone = cone;
    std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(model, options);
    Eigen::VectorXd v = Eigen::VectorXd::Zero(6);
    v(3) = kSpeed * std::cos(angle);
    v(4) = kSpeed * std::sin(angle);
    plant->Reset(BallAt(0, 0, kBallRadius), v);
    plant->Advance(kTime, Eigen::VectorXd::Zero(6));
    return plant->v().tail<3>().norm();
  };
  const double coulomb_loss = kMu * 9.81 * kTime;
  const double along_x = speed_after("elliptic", 0.0);
  EXPECT_NEAR(kSpeed - along_x, coulomb_loss, 0.05 * coulomb_loss);
  for (double angle : {0.3, M_PI / 4, 2.0}) {
    SCOPED_TRACE(angle);
    EXPECT_NEAR(speed_after("elliptic", angle), along_x, 1e-6);
  }
  EXPECT_GT(speed_after("pyramidal", M_PI / 4) - speed_after("pyramidal", 0.0), 0.2 * coulomb_loss);
}

TEST(MujocoPlant, ExcludedPairsDoNotCollide) {
  ModelBuilder builder("two_balls");
  BodyInertia inertia;
  inertia.mass = 1.0;
  inertia.I_BBcm_B = 0.004 * Eigen::Matrix3d::Identity();
  for (const char* name : {"ball_a", "ball_b"}) {
    JointSpec joint;
    joint.name = std::string(name) + "_joint";
    joint.type = JointType::kFloating;
    const BodyIndex b = builder.AddBody(name, inertia, kWorldBody, joint);
    builder.AddGeometry(std::string(name) + "_sphere", b, Eigen::Isometry3d::Identity(),
                        Sphere{0.1});
  }
  builder.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  const Model model = builder.Build();
  MujocoPlantOptions options;
  options.pairs.excluded_pairs = {{"ball_a", "ground"}};
  std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(model, options);
  Eigen::VectorXd q(14);
  q << BallAt(0, 0, 0.1), BallAt(1, 0, 0.1);
  plant->Reset(q, Eigen::VectorXd::Zero(12));
  plant->Advance(0.5, Eigen::VectorXd::Zero(12));
  EXPECT_LT(plant->q()(6), -0.5);
  EXPECT_NEAR(plant->q()(13), 0.1, 2e-3);
}

// Compares MuJoCo's mass matrix and inverse dynamics of the plant's MJCF with idto's at random
// states (bodies lifted clear of the ground so that no contact enters mj_inverse).
void CompareExportedDynamics(const std::string& label, const Model& model,
                             const MujocoPlantOptions& options, double lift, double tol) {
  SCOPED_TRACE(label);
  const test::MjModelPtr m = test::LoadMjcfString(sim::MakeMujocoPlantMjcf(model, options));
  const test::MjDataPtr d(mj_makeData(m.get()));
  ASSERT_EQ(m->nq, model.nq());
  ASSERT_EQ(m->nv, model.nv());
  const MujocoMap map(model);
  Data data(model);
  Random rng(17);
  const int nv = model.nv();
  for (int s = 0; s < 5; ++s) {
    SCOPED_TRACE("sample " + std::to_string(s));
    Eigen::VectorXd q = RandomConfiguration(model, &rng);
    for (const JointIndex j : model.floating_joints()) q(model.position_start(j) + 6) += lift;
    const Eigen::VectorXd v = rng.Vector(nv, -2.0, 2.0);
    const Eigen::VectorXd a = rng.Vector(nv, -3.0, 3.0);
    map.IdtoToMujocoState(q, v, d->qpos, d->qvel);
    map.IdtoToMujocoVelocity(q, a, d->qacc);
    mj_inverse(m.get(), d.get());
    EXPECT_EQ(d->ncon, 0);
    Eigen::VectorXd tau_mj;
    map.MujocoToIdtoForce(q, d->qfrc_inverse, &tau_mj);
    EXPECT_EIGEN_NEAR_REL(InverseDynamics(model, q, v, a, &data), tau_mj, tol);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M_mj(nv, nv);
    mj_fullM(m.get(), M_mj.data(), d->qM);
    Eigen::MatrixXd T;
    map.VelocityMap(q, &T);
    const Eigen::MatrixXd M_mapped = T.transpose() * M_mj * T;
    EXPECT_EIGEN_NEAR_REL(MassMatrix(model, q, &data), M_mapped, tol);
  }
}

TEST(MujocoPlant, ExportedModelHasIdtosDynamics) {
  MujocoPlantOptions options;
  CompareExportedDynamics("ball", BallModel(), options, 2.0, 1e-8);
  RandomTreeOptions o;
  o.num_bodies = 8;
  CompareExportedDynamics("random tree", RandomTreeModel(44, o), options, 0.0, 1e-8);
  Model quadruped;
  Eigen::VectorXd q_stand;
  QuadrupedModel(&quadruped, &q_stand);
  options.pairs.included_pairs = {{"ground", "*"}};
  CompareExportedDynamics("quadruped", quadruped, options, 3.0, 1e-8);
  // Shipped files: a missing one fails (ParseUrdfFile throws with its path).
  for (const char* file : {"spinner.urdf", "hopper.urdf", "acrobot.urdf"}) {
    const Model model = ParseUrdfFile(ModelPath(file));
    CompareExportedDynamics(file, model, MujocoPlantOptions{}, 0.0, 1e-8);
  }
}

// (v1 - v0) / h of one plant step against ForwardDynamics(q0, v0, u) (no damping, no contact).
void CompareOneStep(const Model& model, double h, std::uint32_t seed, double tol) {
  MujocoPlantOptions options;
  options.time_step = h;
  std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(model, options);
  Random rng(seed);
  Data data(model);
  for (int s = 0; s < 3; ++s) {
    SCOPED_TRACE("sample " + std::to_string(s));
    const Eigen::VectorXd q = RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(model.nv());
    const Eigen::VectorXd u = rng.Vector(model.nv(), -5.0, 5.0);
    plant->Reset(q, v);
    plant->Advance(h, u);
    const Eigen::VectorXd a = ForwardDynamics(model, q, v, u, &data);
    EXPECT_EIGEN_NEAR_REL((plant->v() - v) / h, a, tol);
  }
}

TEST(MujocoPlant, GeneralizedForcesGiveIdtosAccelerations) {
  RandomTreeOptions o;
  o.num_bodies = 7;
  o.with_damping = false;
  o.include_floating = false;
  // Revolute, prismatic, planar and fixed joints: T is a permutation, so one Euler step gives
  // MuJoCo's qacc exactly.
  o.base = BaseType::kFixed;
  CompareOneStep(RandomTreeModel(71, o), 1e-3, 1, 1e-6);
  o.base = BaseType::kPlanar;
  CompareOneStep(RandomTreeModel(72, o), 1e-3, 2, 1e-6);
  // Floating joints: idto's angular velocity is in J, MuJoCo's in B, and the map rotates with
  // q; over one step (v1 - v0) / h then differs from the acceleration by O(h |w|), so use a
  // tiny step.
  o.base = BaseType::kFloating;
  o.include_floating = true;
  CompareOneStep(RandomTreeModel(73, o), 1e-8, 3, 1e-6);
}

TEST(MujocoPlant, DisturbanceIsAForceAtTheBodyOrigin) {
  // Zero gravity, no contact, centres of mass off the body origins (and welded bodies): the
  // first step's acceleration is ForwardDynamics with the generalized force of f at Bo.
  RandomTreeOptions o;
  o.num_bodies = 6;
  o.with_damping = false;
  o.gravity = Eigen::Vector3d::Zero();
  const Model model = RandomTreeModel(8, o);
  const double h = 1e-8;
  MujocoPlantOptions options;
  options.time_step = h;
  std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(model, options);
  Random rng(2);
  Data data(model);
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    SCOPED_TRACE("body " + model.body_name(b));
    const Eigen::VectorXd q = RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());
    const Eigen::Vector3d f = rng.Vector(3, -2.0, 2.0);
    plant->Reset(q, v);
    plant->Advance(h, Eigen::VectorXd::Zero(model.nv()), b, f);
    ForwardKinematics(model, q, &data);
    BodyForces F = BodyForces::Zero(6, model.num_bodies());
    F.col(b).tail<3>() = f;
    Eigen::VectorXd tau;
    GeneralizedForceFromBodyForces(model, F, &data, &tau);
    EXPECT_EIGEN_NEAR_REL(plant->v() / h, ForwardDynamics(model, q, v, tau, &data), 1e-6);
  }
}

TEST(MujocoPlant, DisturbancePushesTheBallAlongTheForce) {
  const Model model = BallModel();
  std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(model, {});
  plant->Reset(BallAt(0, 0, 0.1), Eigen::VectorXd::Zero(6));
  plant->Advance(0.3, Eigen::VectorXd::Zero(6));  // settle
  const Eigen::Vector3d p0 = plant->q().tail<3>();
  const BodyIndex ball = model.GetBodyIndex("ball");
  plant->Advance(0.2, Eigen::VectorXd::Zero(6), ball, Eigen::Vector3d(0.0, 8.0, 0.0));
  const Eigen::Vector3d dp = plant->q().tail<3>() - p0;
  EXPECT_GT(dp.y(), 0.02);
  EXPECT_LT(std::abs(dp.x()), 1e-6);
  EXPECT_LT(std::abs(dp.z()), 2e-3);
  // The force is held only for the Advance call that passes it.
  const Eigen::VectorXd v_before = plant->v();
  plant->Advance(0.05, Eigen::VectorXd::Zero(6));
  EXPECT_LT(plant->v()(4), v_before(4) + 0.01);  // held, it would add 0.3 m/s
}

TEST(MujocoPlant, QuadrupedStandsUnderPdControl) {
  Model model;
  Eigen::VectorXd q_stand;
  QuadrupedModel(&model, &q_stand);
  MujocoPlantOptions options;
  options.pairs.included_pairs = {{"ground", "*"}};
  std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(model, options);
  q_stand(6) += 0.01;
  plant->Reset(q_stand, Eigen::VectorXd::Zero(model.nv()));
  double max_speed_late = 0.0;
  StandWithPd(q_stand, 2500, plant.get(), &max_speed_late);
  EXPECT_NEAR(plant->q()(6), 0.30, 0.03);
  EXPECT_LT((plant->q().segment<2>(4)).norm(), 0.02);
  EXPECT_LT(max_speed_late, 5e-3);
  double total = 0.0;
  for (const char* leg : {"FL", "FR", "HL", "HR"}) {
    total += plant->contact_force_per_body()(model.GetBodyIndex(std::string(leg) + "_foot"));
  }
  EXPECT_NEAR(total, 8.25 * 9.81, 2.0);
}

TEST(MujocoPlant, AdvanceDoesNotAllocate) {
  if (!test::AllocationCountingAvailable()) GTEST_SKIP() << "malloc is owned by a sanitizer";
  Model model;
  Eigen::VectorXd q_stand;
  QuadrupedModel(&model, &q_stand);
  std::unique_ptr<Plant> plant = sim::MakeMujocoPlant(model, {});
  plant->Reset(q_stand, Eigen::VectorXd::Zero(model.nv()));
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(model.nv(), 0.1);
  plant->Advance(0.002, u, 1, Eigen::Vector3d(1, 2, 3));
  test::ScopedAllocationCounter counter;
  plant->Advance(0.02, u, 1, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(counter.count(), 0);
}

#else  // IDTO_HAVE_MUJOCO

TEST(MujocoPlant, UnavailableWithoutMujoco) {
  EXPECT_FALSE(sim::HaveMujoco());
  EXPECT_THAT([] { sim::MakeMujocoPlant(BallModel(), {}); },
              ThrowsMessage<std::runtime_error>(HasSubstr("without MuJoCo")));
}

#endif  // IDTO_HAVE_MUJOCO

}  // namespace
}  // namespace idto
