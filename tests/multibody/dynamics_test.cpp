// Dynamics checked against independent identities: energy computed body by body from forward
// kinematics (not from M), power balance, RNEA = M a + bias, ABA-free forward dynamics inverting
// RNEA, free fall, external forces against Jacobians.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "idto/idto.hpp"
#include "support/eigen_matchers.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using test::Random;
using test::RandomConfiguration;
using test::RandomTreeModel;
using test::RandomTreeOptions;

// Kinetic energy summed body by body from world velocities of each body's centre of mass.
double KineticEnergy(const Model& model, const Data& data) {
  double T = 0.0;
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const BodyInertia& I = model.body_inertia(b);
    if (I.mass == 0.0) continue;
    const Eigen::Matrix3d& R = data.R_WB(b);
    const Eigen::Vector3d w = data.w_WB(b);
    const Eigen::Vector3d v_com = data.v_WBo(b) + w.cross(R * I.p_BBcm);
    T += 0.5 * I.mass * v_com.squaredNorm() + 0.5 * w.dot(R * I.I_BBcm_B * R.transpose() * w);
  }
  return T;
}

double PotentialEnergy(const Model& model, const Data& data) {
  double V = 0.0;
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const BodyInertia& I = model.body_inertia(b);
    V -= I.mass * model.gravity().dot(data.X_WB(b) * I.p_BBcm);
  }
  return V;
}

std::vector<std::pair<std::string, Model>> TestModels() {
  std::vector<std::pair<std::string, Model>> models;
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    RandomTreeOptions o;
    o.num_bodies = 9;
    o.base = BaseType::kFloating;
    models.emplace_back("floating" + std::to_string(seed), RandomTreeModel(seed, o));
    o.base = BaseType::kFixed;
    models.emplace_back("fixed" + std::to_string(seed), RandomTreeModel(seed + 10, o));
    o.base = BaseType::kPlanar;
    o.include_floating = false;
    models.emplace_back("planar" + std::to_string(seed), RandomTreeModel(seed + 20, o));
  }
  return models;
}

TEST(Dynamics, RneaEqualsMassMatrixTimesAccelerationPlusBias) {
  Random rng(7);
  for (const auto& [name, model] : TestModels()) {
    SCOPED_TRACE(name);
    Data data(model);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd q = RandomConfiguration(model, &rng);
      const Eigen::VectorXd v = rng.Vector(model.nv());
      const Eigen::VectorXd a = rng.Vector(model.nv());
      const Eigen::VectorXd tau = InverseDynamics(model, q, v, a, &data);
      const Eigen::VectorXd bias = BiasTerm(model, q, v, &data);
      const Eigen::MatrixXd M = MassMatrix(model, q, &data);
      EXPECT_EIGEN_NEAR_REL(tau, Eigen::VectorXd(M * a + bias), 1e-12);
      // RNEA is linear in a: columns of M from unit accelerations.
      const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv());
      const Eigen::VectorXd g = InverseDynamics(model, q, zero, zero, &data);
      Eigen::MatrixXd M_rnea(model.nv(), model.nv());
      for (int i = 0; i < model.nv(); ++i) {
        M_rnea.col(i) =
            InverseDynamics(model, q, zero, Eigen::VectorXd::Unit(model.nv(), i), &data) - g;
      }
      EXPECT_EIGEN_NEAR_REL(M_rnea, M, 1e-12);
    }
  }
}

TEST(Dynamics, MassMatrixIsSymmetricPositiveDefiniteAndGivesKineticEnergy) {
  Random rng(8);
  for (const auto& [name, model] : TestModels()) {
    SCOPED_TRACE(name);
    Data data(model);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd q = RandomConfiguration(model, &rng);
      const Eigen::VectorXd v = rng.Vector(model.nv(), -2, 2);
      const Eigen::MatrixXd M = MassMatrix(model, q, &data);
      EXPECT_EIGEN_NEAR(M, Eigen::MatrixXd(M.transpose()), 0.0);
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
      EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
      ForwardKinematics(model, q, v, &data);
      const double T = KineticEnergy(model, data);
      EXPECT_NEAR(0.5 * v.dot(M * v), T, 1e-12 * std::max(1.0, T));
    }
  }
}

TEST(Dynamics, PowerBalanceAlongRandomTrajectories) {
  // v^T (tau - D v) = d/dt (kinetic + potential energy), with the derivative by central
  // differences along q(t) = Integrate(q, v, t), v(t) = v + a t.
  Random rng(9);
  for (const auto& [name, model] : TestModels()) {
    SCOPED_TRACE(name);
    Data data(model);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd q = RandomConfiguration(model, &rng);
      const Eigen::VectorXd v = rng.Vector(model.nv());
      const Eigen::VectorXd a = rng.Vector(model.nv());
      auto energy = [&, &m = model](double t) {
        Eigen::VectorXd qt;
        Integrate(m, q, v, t, &qt);
        const Eigen::VectorXd vt = v + t * a;
        ForwardKinematics(m, qt, vt, &data);
        return KineticEnergy(m, data) + PotentialEnergy(m, data);
      };
      const double h = 1e-4;
      const double dE = (energy(h) - energy(-h)) / (2 * h);
      const Eigen::VectorXd tau = InverseDynamics(model, q, v, a, &data);
      const double power = v.dot(tau - model.damping().cwiseProduct(v));
      EXPECT_NEAR(power, dE, 1e-6 * std::max(1.0, std::abs(dE)));
    }
  }
}

TEST(Dynamics, FreeBodyInFreeFallNeedsNoForce) {
  ModelBuilder builder;
  BodyInertia I;
  I.mass = 2.0;
  I.I_BBcm_B = Eigen::Vector3d(0.1, 0.2, 0.25).asDiagonal();
  JointSpec j;
  j.name = "free";
  j.type = JointType::kFloating;
  builder.AddBody("ball", I, kWorldBody, j);
  const Model model = builder.Build();
  Data data(model);
  Random rng(3);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd q = RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(6, -3, 3);
    ForwardKinematics(model, q, &data);
    // Torque-free Euler equations in the world: I_W wdot + w x I_W w = 0; com falls with g.
    const Eigen::Matrix3d I_W = data.R_WB(1) * I.I_BBcm_B * data.R_WB(1).transpose();
    const Eigen::Vector3d w = v.head<3>();
    Eigen::VectorXd a(6);
    a.head<3>() = -I_W.ldlt().solve(w.cross(I_W * w));
    a.tail<3>() = model.gravity();
    EXPECT_EIGEN_NEAR(InverseDynamics(model, q, v, a, &data), Eigen::VectorXd::Zero(6), 1e-12);
  }
}

TEST(Dynamics, ForwardDynamicsInvertsInverseDynamics) {
  Random rng(10);
  for (const auto& [name, model] : TestModels()) {
    SCOPED_TRACE(name);
    Data data(model);
    const Eigen::VectorXd q = RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(model.nv());
    const Eigen::VectorXd a = rng.Vector(model.nv());
    const Eigen::VectorXd tau = InverseDynamics(model, q, v, a, &data);
    EXPECT_EIGEN_NEAR_REL(ForwardDynamics(model, q, v, tau, &data), a, 1e-9);
  }
}

TEST(Dynamics, ExternalForcesEnterThroughFrameJacobians) {
  Random rng(11);
  for (const auto& [name, model] : TestModels()) {
    SCOPED_TRACE(name);
    Data data(model);
    const Eigen::VectorXd q = RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(model.nv());
    const Eigen::VectorXd a = rng.Vector(model.nv());
    BodyForces F = rng.Matrix(6, model.num_bodies());
    const Eigen::VectorXd tau0 = InverseDynamics(model, q, v, a, &data);
    const Eigen::VectorXd tau = InverseDynamics(model, q, v, a, F, &data);
    ForwardKinematics(model, q, &data);
    Eigen::VectorXd expected = tau0;
    Eigen::Matrix<double, 6, Eigen::Dynamic> J;
    for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
      CalcFrameJacobian(model, data, b, Eigen::Isometry3d::Identity(), &J);
      expected -= J.transpose() * F.col(b);
    }
    EXPECT_EIGEN_NEAR_REL(tau, expected, 1e-12);
  }
}

TEST(Dynamics, DampingAddsDv) {
  RandomTreeOptions o;
  o.with_damping = true;
  const Model model = RandomTreeModel(5, o);
  EXPECT_GT(model.damping().maxCoeff(), 0.0);
  Random rng(12);
  Data data(model);
  const Eigen::VectorXd q = RandomConfiguration(model, &rng);
  const Eigen::VectorXd v = rng.Vector(model.nv());
  const Eigen::VectorXd a = rng.Vector(model.nv());
  const Eigen::VectorXd tau = InverseDynamics(model, q, v, a, &data);
  const Eigen::VectorXd bias = BiasTerm(model, q, v, &data);
  const Eigen::VectorXd zero_v = Eigen::VectorXd::Zero(model.nv());
  // Damping is the only term linear in v that does not vanish at v -> 0 scaled: check tau(v) -
  // tau(-v) = 2 D v (the Coriolis term is quadratic, gravity constant).
  const Eigen::VectorXd tau_minus = InverseDynamics(model, q, -v, a, &data);
  EXPECT_EIGEN_NEAR_REL(Eigen::VectorXd(tau - tau_minus),
                        Eigen::VectorXd(2.0 * model.damping().cwiseProduct(v)), 1e-12);
  (void)bias;
  (void)zero_v;
}

TEST(Dynamics, SizeErrorsNameTheArgument) {
  const Model model = RandomTreeModel(1);
  Data data(model);
  const Eigen::VectorXd q = model.NeutralConfiguration();
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());
  const Eigen::VectorXd bad = Eigen::VectorXd::Zero(model.nv() + 1);
  using ::testing::HasSubstr;
  EXPECT_THAT(
      [&] { InverseDynamics(model, q, v, bad, &data); },
      ::testing::ThrowsMessage<InvalidArgument>(AllOf(
          HasSubstr("InverseDynamics"), HasSubstr("a is of size " + std::to_string(model.nv() + 1)),
          HasSubstr("model.nv()"))));
  EXPECT_THAT([&] { MassMatrix(model, v, &data); },
              ::testing::ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("MassMatrix"), HasSubstr("q is of size"),
                        HasSubstr("size " + std::to_string(model.nq())))));
  BodyForces F(6, 2);
  EXPECT_THAT([&] { InverseDynamics(model, q, v, v, F, &data); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("F_ext.cols()")));
}

}  // namespace
}  // namespace idto

namespace idto {
namespace {

TEST(Dynamics, GeneralizedForceFromBodyForcesIsTheRneaExternalForceTerm) {
  test::Random rng(13);
  for (const auto& [name, model] : TestModels()) {
    SCOPED_TRACE(name);
    Data data(model);
    const Eigen::VectorXd q = test::RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(model.nv());
    const Eigen::VectorXd a = rng.Vector(model.nv());
    const BodyForces F = rng.Matrix(6, model.num_bodies());
    const Eigen::VectorXd tau0 = InverseDynamics(model, q, v, a, &data);
    const Eigen::VectorXd tauF = InverseDynamics(model, q, v, a, F, &data);
    ForwardKinematics(model, q, &data);
    Eigen::VectorXd tau_c;
    GeneralizedForceFromBodyForces(model, F, &data, &tau_c);
    EXPECT_EIGEN_NEAR_REL(tau_c, Eigen::VectorXd(tau0 - tauF), 1e-12);
  }
}

}  // namespace
}  // namespace idto

namespace idto {
namespace {

TEST(Dynamics, InverseDynamicsAfterKinematicsEqualsInverseDynamics) {
  test::Random rng(14);
  for (const auto& [name, model] : TestModels()) {
    SCOPED_TRACE(name);
    Data data(model), fresh(model);
    const Eigen::VectorXd q = test::RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(model.nv());
    const Eigen::VectorXd a = rng.Vector(model.nv());
    const BodyForces F = rng.Matrix(6, model.num_bodies());
    ForwardKinematics(model, q, v, &data);
    const Eigen::VectorXd tau = InverseDynamicsAfterKinematics(model, v, a, nullptr, &data);
    EXPECT_EIGEN_NEAR_REL(tau, InverseDynamics(model, q, v, a, &fresh), 1e-14);
    ForwardKinematics(model, q, v, &data);
    const Eigen::VectorXd tauF = InverseDynamicsAfterKinematics(model, v, a, &F, &data);
    EXPECT_EIGEN_NEAR_REL(tauF, InverseDynamics(model, q, v, a, F, &fresh), 1e-14);
  }
}

}  // namespace
}  // namespace idto
