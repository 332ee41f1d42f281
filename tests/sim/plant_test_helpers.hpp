// Models and helpers shared by the plant tests (plant_test.cpp: the built-in plant and the MJCF;
// mujoco_plant_test.cpp: the MuJoCo plant).
#pragma once

#include <cmath>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "idto/parsers/urdf.hpp"
#include "idto/sim/plant.hpp"
#include "support/eigen_matchers.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace plant_test {

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

inline constexpr double kBallRadius = 0.1;
inline constexpr double kBallMass = 1.0;

// A solid ball of radius 0.1 m and 1 kg on a floating joint, over a ground half-space.
inline Model BallModel(const Eigen::Vector3d& gravity = Eigen::Vector3d(0, 0, -9.81)) {
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
inline Eigen::VectorXd BallAt(double x, double y, double z) {
  Eigen::VectorXd q(7);
  q << 1, 0, 0, 0, x, y, z;
  return q;
}

// A pendulum in code: a rod of length 2 l (uniform, mass m) hinged at one end about y.
inline constexpr double kPendulumHalfLength = 0.25;
inline constexpr double kPendulumMass = 2.0;
inline Model PendulumModel() {
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
inline double MechanicalEnergy(const Model& model, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& v, Data* data) {
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
inline double RestingHeight(const ContactParameters& p, double weight) {
  // c(phi) = sigma k log(1 + exp(-phi / sigma)) = W  ->  phi = -sigma log(exp(W / (sigma k)) - 1).
  const double phi = -p.smoothing * std::log(std::expm1(weight / (p.smoothing * p.stiffness)));
  return kBallRadius + phi;
}

inline std::string ModelPath(const std::string& file) {
  return std::string(IDTO_SOURCE_DIR) + "/models/" + file;
}

// The quadruped on a ground half-space, standing (examples/quadruped).
inline void QuadrupedModel(Model* model, Eigen::VectorXd* q_stand) {
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
inline Model SpinningRod() {
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
inline void CheckExtraDamping(Plant* plant) {
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

// Two free balls (bodies ball_a, ball_b: 1 kg, radius 0.1 m, both at the world origin) over a
// ground half-space: the scene of the pair-filter tests.
inline Model TwoBallsModel() {
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
  return builder.Build();
}

// The ball of BallModel settled on the ground, then pushed with 8 N along +y for 0.2 s: it moves
// along y only (within z_tolerance vertically). Checks any plant's disturbance input.
inline void CheckPushAlongY(const Model& model, Plant* plant, double z_tolerance) {
  plant->Reset(BallAt(0, 0, 0.1), Eigen::VectorXd::Zero(6));
  plant->Advance(0.3, Eigen::VectorXd::Zero(6));  // settle
  const Eigen::Vector3d p0 = plant->q().tail<3>();
  const BodyIndex ball = model.GetBodyIndex("ball");
  plant->Advance(0.2, Eigen::VectorXd::Zero(6), ball, Eigen::Vector3d(0.0, 8.0, 0.0));
  const Eigen::Vector3d dp = plant->q().tail<3>() - p0;
  EXPECT_GT(dp.y(), 0.02);
  EXPECT_LT(std::abs(dp.x()), 1e-6);
  EXPECT_LT(std::abs(dp.z()), z_tolerance);
}

// Runs the quadruped under joint PD control towards q_stand for `steps` 1 ms steps.
inline void StandWithPd(const Eigen::VectorXd& q_stand, int steps, Plant* plant,
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

}  // namespace plant_test
}  // namespace idto
