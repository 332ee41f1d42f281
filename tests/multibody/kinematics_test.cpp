// Kinematics, Jacobians and configuration maps checked against finite differences.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "idto/idto.hpp"
#include "support/eigen_matchers.hpp"
#include "support/finite_difference.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using test::Random;
using test::RandomConfiguration;
using test::RandomTreeModel;
using test::RandomTreeOptions;

std::vector<Model> Models() {
  std::vector<Model> models;
  RandomTreeOptions o;
  o.num_bodies = 9;
  for (BaseType base : {BaseType::kFloating, BaseType::kFixed, BaseType::kPlanar}) {
    o.base = base;
    models.push_back(RandomTreeModel(30 + static_cast<int>(base), o));
  }
  return models;
}

TEST(Kinematics, PointJacobianMatchesFiniteDifferencesOfPositions) {
  Random rng(1);
  for (const Model& model : Models()) {
    SCOPED_TRACE(model.name());
    Data data(model);
    const Eigen::VectorXd q = RandomConfiguration(model, &rng);
    ForwardKinematics(model, q, &data);
    for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
      const Eigen::Vector3d p_BC = rng.Vector(3);
      Eigen::Matrix3Xd J;
      CalcPointJacobian(model, data, b, p_BC, &J);
      // Column i: d p_WC / d v_i, i.e. the derivative along Integrate(q, e_i, t).
      Data fd(model);
      const Eigen::MatrixXd J_fd = test::FiniteDifferenceJacobian(
          [&](const Eigen::VectorXd& dv) {
            Eigen::VectorXd qt;
            Integrate(model, q, dv, 1.0, &qt);
            ForwardKinematics(model, qt, &fd);
            return Eigen::VectorXd(fd.X_WB(b) * p_BC);
          },
          Eigen::VectorXd::Zero(model.nv()), 1e-6);
      EXPECT_EIGEN_NEAR(J, J_fd, 1e-8);
    }
  }
}

TEST(Kinematics, FrameJacobianGivesForwardKinematicsVelocities) {
  Random rng(2);
  for (const Model& model : Models()) {
    SCOPED_TRACE(model.name());
    Data data(model);
    const Eigen::VectorXd q = RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(model.nv());
    ForwardKinematics(model, q, v, &data);
    Eigen::Matrix<double, 6, Eigen::Dynamic> J;
    for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
      CalcFrameJacobian(model, data, b, Eigen::Isometry3d::Identity(), &J);
      EXPECT_EIGEN_NEAR(Eigen::VectorXd(J * v), Eigen::VectorXd(data.V_WB(b)), 1e-12);
      // Angular rows by finite differences of orientation: R(t) = R0 exp(...), w = vee(Rdot R^T).
      Data fd(model);
      auto rotation_at = [&](double t) {
        Eigen::VectorXd qt;
        Integrate(model, q, v, t, &qt);
        ForwardKinematics(model, qt, &fd);
        return Eigen::Matrix3d(fd.R_WB(b));
      };
      const double h = 1e-6;
      const Eigen::Matrix3d Rdot = (rotation_at(h) - rotation_at(-h)) / (2 * h);
      const Eigen::Matrix3d W = Rdot * rotation_at(0).transpose();
      EXPECT_EIGEN_NEAR(Eigen::Vector3d(W(2, 1), W(0, 2), W(1, 0)), data.w_WB(b), 1e-7);
    }
  }
}

TEST(Kinematics, NMapsVelocitiesToConfigurationRates) {
  Random rng(3);
  for (const Model& model : Models()) {
    SCOPED_TRACE(model.name());
    const Eigen::VectorXd q = RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(model.nv());
    Eigen::MatrixXd N, Nplus;
    CalcNMatrix(model, q, &N);
    CalcNplusMatrix(model, q, &Nplus);
    const double h = 1e-6;
    Eigen::VectorXd qp, qm;
    Integrate(model, q, v, h, &qp);
    Integrate(model, q, v, -h, &qm);
    EXPECT_EIGEN_NEAR(Eigen::VectorXd(N * v), Eigen::VectorXd((qp - qm) / (2 * h)), 1e-8);
    EXPECT_EIGEN_NEAR(Eigen::MatrixXd(Nplus * N), Eigen::MatrixXd::Identity(model.nv(), model.nv()),
                      1e-14);
  }
}

TEST(Kinematics, NplusIsThePseudoInverseForNonUnitQuaternions) {
  const Model model = RandomTreeModel(4);
  Random rng(4);
  Eigen::VectorXd q = RandomConfiguration(model, &rng);
  q.segment<4>(model.position_start(model.floating_joints()[0])) *= 1.7;
  Eigen::MatrixXd N, Nplus;
  CalcNMatrix(model, q, &N);
  CalcNplusMatrix(model, q, &Nplus);
  const Eigen::MatrixXd pinv = N.completeOrthogonalDecomposition().pseudoInverse();
  EXPECT_EIGEN_NEAR(Nplus, pinv, 1e-12);
}

TEST(Kinematics, IntegrateAndDifferenceAreInverse) {
  Random rng(5);
  for (const Model& model : Models()) {
    SCOPED_TRACE(model.name());
    const Eigen::VectorXd q0 = RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(model.nv());
    Eigen::VectorXd q1, v_back;
    Integrate(model, q0, v, 0.7, &q1);
    Difference(model, q1, q0, &v_back);
    EXPECT_EIGEN_NEAR(v_back, Eigen::VectorXd(0.7 * v), 1e-12);
    // Quaternions stay unit, and Integrate may alias its input.
    Eigen::VectorXd q = q0;
    Integrate(model, q, v, 0.7, &q);
    EXPECT_EIGEN_NEAR(q, q1, 0.0);
    for (JointIndex j : model.floating_joints()) {
      EXPECT_NEAR(q1.segment<4>(model.position_start(j)).norm(), 1.0, 1e-15);
    }
  }
}

TEST(Kinematics, DifferenceTakesTheShortestRotationAcrossTheSignFlip) {
  ModelBuilder builder;
  BodyInertia I;
  I.mass = 1.0;
  I.I_BBcm_B = Eigen::Matrix3d::Identity() * 0.01;
  JointSpec j;
  j.name = "free";
  j.type = JointType::kFloating;
  builder.AddBody("b", I, kWorldBody, j);
  const Model model = builder.Build();
  Eigen::VectorXd q0 = model.NeutralConfiguration();
  Eigen::VectorXd q1 = q0;
  const Eigen::Quaterniond Q(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
  q1.head<4>() << -Q.w(), -Q.x(), -Q.y(), -Q.z();  // the same rotation, other hemisphere
  Eigen::VectorXd v;
  Difference(model, q1, q0, &v);
  EXPECT_EIGEN_NEAR(v, (Eigen::VectorXd(6) << 0.1, 0, 0, 0, 0, 0).finished(), 1e-14);
  // Tiny rotations: no loss of accuracy in the log map.
  const Eigen::Quaterniond Qs(Eigen::AngleAxisd(1e-12, Eigen::Vector3d::UnitY()));
  q1.head<4>() << Qs.w(), Qs.x(), Qs.y(), Qs.z();
  Difference(model, q1, q0, &v);
  EXPECT_NEAR(v(1), 1e-12, 1e-26);
}

TEST(Kinematics, NormalizeQuaternionsHandlesZeroAndScaled) {
  const Model model = RandomTreeModel(6);
  Eigen::VectorXd q = model.NeutralConfiguration();
  const int i = model.position_start(model.floating_joints()[0]);
  q.segment<4>(i) << 0, 0, 0, 0;
  const int k = model.position_start(model.floating_joints()[1]);
  q.segment<4>(k) << 2, 0, 0, 0;
  NormalizeQuaternions(model, &q);
  EXPECT_EIGEN_NEAR(Eigen::Vector4d(q.segment<4>(i)), Eigen::Vector4d(1, 0, 0, 0), 0.0);
  EXPECT_EIGEN_NEAR(Eigen::Vector4d(q.segment<4>(k)), Eigen::Vector4d(1, 0, 0, 0), 0.0);
}

TEST(Kinematics, WeldedBodiesFollowTheirParentsAndKeepTheirFrames) {
  ModelBuilder builder;
  BodyInertia I;
  I.mass = 1.0;
  I.I_BBcm_B = Eigen::Matrix3d::Identity() * 0.01;
  JointSpec j;
  j.name = "hinge";
  j.type = JointType::kRevolute;
  j.axis = Eigen::Vector3d::UnitZ();
  const BodyIndex link = builder.AddBody("link", I, kWorldBody, j);
  JointSpec weld;
  weld.name = "weld";
  weld.type = JointType::kFixed;
  weld.X_PJ.translation() << 1.0, 0.0, 0.0;
  const BodyIndex tool = builder.AddBody("tool", BodyInertia{}, link, weld);
  Eigen::Isometry3d X_BF = Eigen::Isometry3d::Identity();
  X_BF.translation() << 0.0, 0.5, 0.0;
  builder.AddFrame("tip", tool, X_BF);
  const Model model = builder.Build();
  EXPECT_EQ(model.nv(), 1);
  EXPECT_EQ(model.num_bodies(), 3);
  EXPECT_EQ(model.mobilized_body(tool), link);
  Data data(model);
  Eigen::VectorXd q(1);
  q << M_PI / 2;
  ForwardKinematics(model, q, &data);
  EXPECT_EIGEN_NEAR(data.p_WB(tool), Eigen::Vector3d(0, 1, 0), 1e-15);
  const FrameIndex tip = model.GetFrameIndex("tip");
  EXPECT_EIGEN_NEAR(Eigen::Vector3d(data.X_WF(model, tip).translation()),
                    Eigen::Vector3d(-0.5, 1, 0), 1e-15);
}

}  // namespace
}  // namespace idto
