// The MuJoCo plant of idto/sim/plant.hpp (when idto was built with MuJoCo): contact, friction,
// damping, disturbances and errors against known answers (the built-in plant and the MJCF it
// loads: plant_test.cpp).

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "idto/sim/mjcf.hpp"
#include "idto/sim/plant.hpp"
#include "sim/plant_test_helpers.hpp"
#include "support/allocation_counter.hpp"
#include "support/mujoco_helpers.hpp"

namespace idto {
namespace {

using namespace plant_test;  // NOLINT(build/namespaces): the shared models

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
  const Model model = TwoBallsModel();
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
  CheckPushAlongY(model, plant.get(), 2e-3);
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
