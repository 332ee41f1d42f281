// Analytic RNEA derivatives (ComputeRneaDerivatives) against automatic differentiation of the
// Scalar-templated RNEA (Eigen's AutoDiffScalar instantiating the same kernels), on random trees
// with every joint type and on the URDF models, with and without external forces.

#include <gtest/gtest.h>

#include <algorithm>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include "idto/idto.hpp"
#include "idto/multibody/algorithms/dynamics-inl.hpp"
#include "idto/multibody/algorithms/kinematics-inl.hpp"
#include "idto/multibody/algorithms/rnea_derivatives-inl.hpp"
#include "idto/multibody/data-inl.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using AD = Eigen::AutoDiffScalar<Eigen::VectorXd>;
using test::Random;
using test::RandomConfiguration;
using test::RandomTreeModel;
using test::RandomTreeOptions;

constexpr double kTolerance = 1e-12;

// ||A - B||_F / max(||B||_F, floor): relative per block. The floor (the mass matrix's norm where
// given) covers blocks that vanish identically, whose entries on both sides are round-off (e.g.
// d tau / d v of a free sphere).
double RelativeError(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double floor = 1e-300) {
  return (A - B).norm() / std::max(B.norm(), floor);
}

// The oracle: d tau / d (q, v, a) of the templated RNEA by forward-mode AD, in raw coordinates.
struct AdDerivatives {
  Eigen::VectorXd tau;
  Eigen::MatrixXd dtau_dq, dtau_dv, dtau_da;
};

AdDerivatives AutoDiffRnea(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                           const Eigen::VectorXd& a, const BodyForces* F_ext) {
  const int nq = model.nq(), nv = model.nv(), n = nq + 2 * nv;
  VectorX<AD> q_ad(nq), v_ad(nv), a_ad(nv);
  for (int i = 0; i < nq; ++i) q_ad(i) = AD(q(i), n, i);
  for (int i = 0; i < nv; ++i) v_ad(i) = AD(v(i), n, nq + i);
  for (int i = 0; i < nv; ++i) a_ad(i) = AD(a(i), n, nq + nv + i);
  BodyForcesTpl<AD> F_ad;
  if (F_ext != nullptr) {
    F_ad.resize(6, F_ext->cols());
    for (int j = 0; j < F_ext->cols(); ++j) {
      for (int i = 0; i < 6; ++i) F_ad(i, j) = AD((*F_ext)(i, j), Eigen::VectorXd::Zero(n));
    }
  }
  DataTpl<AD> data(model);
  const VectorX<AD>& tau =
      InverseDynamics(model, q_ad, v_ad, a_ad, F_ext != nullptr ? &F_ad : nullptr, &data);
  AdDerivatives out;
  out.tau.resize(nv);
  Eigen::MatrixXd J(nv, n);
  for (int i = 0; i < nv; ++i) {
    out.tau(i) = tau(i).value();
    J.row(i) = tau(i).derivatives().size() == n ? Eigen::VectorXd(tau(i).derivatives())
                                                : Eigen::VectorXd::Zero(n);
  }
  out.dtau_dq = J.leftCols(nq);
  out.dtau_dv = J.middleCols(nq, nv);
  out.dtau_da = J.rightCols(nv);
  return out;
}

void ExpectMatchesAutoDiff(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                           const Eigen::VectorXd& a, const BodyForces* F_ext, Data* data) {
  ComputeRneaDerivatives(model, q, v, a, F_ext, data);
  const AdDerivatives ad = AutoDiffRnea(model, q, v, a, F_ext);
  const double floor = ad.dtau_da.norm();
  EXPECT_LE(RelativeError(data->tau, ad.tau, floor), kTolerance);
  EXPECT_LE(RelativeError(data->dtau_dq, ad.dtau_dq, floor), kTolerance)
      << "analytic\n"
      << data->dtau_dq << "\nAD\n"
      << ad.dtau_dq;
  EXPECT_LE(RelativeError(data->dtau_dv, ad.dtau_dv, floor), kTolerance)
      << "analytic\n"
      << data->dtau_dv << "\nAD\n"
      << ad.dtau_dv;
  EXPECT_LE(RelativeError(data->M, ad.dtau_da), kTolerance);
  // The tangent derivative is the raw one along N(q).
  Eigen::MatrixXd N;
  CalcNMatrix(model, q, &N);
  EXPECT_LE(RelativeError(data->dtau_dq * N, data->dtau_dq_tangent, floor), kTolerance);
  // tau and M also match the double RNEA and CRBA.
  const Eigen::MatrixXd M = data->M;
  const Eigen::VectorXd tau = data->tau;
  Data ref(model);
  const Eigen::VectorXd tau_rnea = F_ext != nullptr ? InverseDynamics(model, q, v, a, *F_ext, &ref)
                                                    : InverseDynamics(model, q, v, a, &ref);
  EXPECT_LE(RelativeError(tau, tau_rnea, floor), kTolerance);
  EXPECT_LE(RelativeError(M, MassMatrix(model, q, &ref)), kTolerance);
}

std::vector<std::pair<std::string, Model>> RandomTrees() {
  std::vector<std::pair<std::string, Model>> models;
  for (std::uint32_t seed : {1u, 2u, 3u, 4u}) {
    RandomTreeOptions o;
    o.num_bodies = 10;
    o.base = BaseType::kFloating;
    models.emplace_back("floating" + std::to_string(seed), RandomTreeModel(seed, o));
    o.base = BaseType::kFixed;
    models.emplace_back("fixed" + std::to_string(seed), RandomTreeModel(seed + 10, o));
    o.base = BaseType::kPlanar;
    models.emplace_back("planar" + std::to_string(seed), RandomTreeModel(seed + 20, o));
  }
  return models;
}

TEST(RneaDerivatives, RandomTreesMatchAutoDiff) {
  Random rng(11);
  for (const auto& [name, model] : RandomTrees()) {
    SCOPED_TRACE(name);
    Data data(model);
    for (int trial = 0; trial < 3; ++trial) {
      const Eigen::VectorXd q = RandomConfiguration(model, &rng);
      const Eigen::VectorXd v = rng.Vector(model.nv(), -2.0, 2.0);
      const Eigen::VectorXd a = rng.Vector(model.nv(), -2.0, 2.0);
      ExpectMatchesAutoDiff(model, q, v, a, nullptr, &data);
      const BodyForces F = rng.Matrix(6, model.num_bodies());
      ExpectMatchesAutoDiff(model, q, v, a, &F, &data);
    }
  }
}

TEST(RneaDerivatives, NonUnitQuaternionsInRawCoordinates) {
  RandomTreeOptions o;
  o.num_bodies = 8;
  const Model model = RandomTreeModel(5, o);
  ASSERT_FALSE(model.floating_joints().empty());
  Random rng(3);
  Data data(model);
  Eigen::VectorXd q = RandomConfiguration(model, &rng);
  for (JointIndex j : model.floating_joints()) q.segment<4>(model.position_start(j)) *= 1.7;
  const Eigen::VectorXd v = rng.Vector(model.nv());
  const Eigen::VectorXd a = rng.Vector(model.nv());
  const BodyForces F = rng.Matrix(6, model.num_bodies());
  ComputeRneaDerivatives(model, q, v, a, &F, &data);
  const AdDerivatives ad = AutoDiffRnea(model, q, v, a, &F);
  EXPECT_LE(RelativeError(data.dtau_dq, ad.dtau_dq), kTolerance);
  // Scale invariance: the quaternion columns annihilate the quaternion.
  for (JointIndex j : model.floating_joints()) {
    const int iq = model.position_start(j);
    EXPECT_LE((data.dtau_dq.middleCols<4>(iq) * q.segment<4>(iq)).norm(),
              1e-12 * data.dtau_dq.norm());
  }
}

// The tangent-space entry point (what the solver calls) is the full one without the raw
// coordinates: the same tau, dtau_dq_tangent, dtau_dv and M bit for bit, and dtau_dq untouched.
TEST(RneaDerivatives, TangentEntryPointMatchesFullOne) {
  RandomTreeOptions o;
  o.num_bodies = 9;
  for (int seed : {5, 6, 7}) {
    const Model model = RandomTreeModel(seed, o);
    Random rng(seed);
    Data full(model), tangent(model);
    const Eigen::VectorXd q = RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(model.nv());
    const Eigen::VectorXd a = rng.Vector(model.nv());
    const BodyForces F = rng.Matrix(6, model.num_bodies());
    for (const BodyForces* f : {static_cast<const BodyForces*>(nullptr), &F}) {
      ComputeRneaDerivatives(model, q, v, a, f, &full);
      tangent.dtau_dq.setConstant(7.0);
      ComputeRneaDerivativesTangent(model, q, v, a, f, &tangent);
      EXPECT_EQ(tangent.tau, full.tau);
      EXPECT_EQ(tangent.dtau_dq_tangent, full.dtau_dq_tangent);
      EXPECT_EQ(tangent.dtau_dv, full.dtau_dv);
      EXPECT_EQ(tangent.M, full.M);
      EXPECT_TRUE((tangent.dtau_dq.array() == 7.0).all());
    }
  }
  const Model model = RandomTreeModel(5, o);
  Data data(model);
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());
  EXPECT_THROW(ComputeRneaDerivativesTangent(model, Eigen::VectorXd::Zero(model.nq() + 1), v, v,
                                             nullptr, &data),
               InvalidArgument);
}

std::vector<std::pair<std::string, Model>> UrdfModels() {
  std::vector<std::pair<std::string, Model>> models;
  const std::string dir = std::string(IDTO_SOURCE_DIR) + "/models/";
  for (const char* file : {"acrobot", "allegro_hand", "arm7", "hopper", "jaco_arm", "pendulum",
                           "spinner", "quadruped", "ball", "box"}) {
    for (BaseType base : {BaseType::kFixed, BaseType::kFloating, BaseType::kPlanar}) {
      UrdfOptions options;
      options.base = base;
      options.X_WB.translation() = Eigen::Vector3d(0.1, -0.2, 0.3);
      // Some models cannot take some bases (a massless root link cannot float): skipped.
      try {
        models.emplace_back(std::string(file) + "/" + std::to_string(static_cast<int>(base)),
                            ParseUrdfFile(dir + file + ".urdf", options));
      } catch (const std::exception&) {
      }
    }
  }
  EXPECT_GE(models.size(), 20u);
  return models;
}

TEST(RneaDerivatives, UrdfModelsMatchAutoDiff) {
  Random rng(17);
  for (const auto& [name, model] : UrdfModels()) {
    SCOPED_TRACE(name);
    if (model.nv() == 0) continue;
    Data data(model);
    for (int trial = 0; trial < 2; ++trial) {
      const Eigen::VectorXd q = RandomConfiguration(model, &rng);
      const Eigen::VectorXd v = rng.Vector(model.nv(), -2.0, 2.0);
      const Eigen::VectorXd a = rng.Vector(model.nv(), -2.0, 2.0);
      ExpectMatchesAutoDiff(model, q, v, a, nullptr, &data);
      const BodyForces F = 10.0 * rng.Matrix(6, model.num_bodies());
      ExpectMatchesAutoDiff(model, q, v, a, &F, &data);
    }
  }
}

TEST(TemplatedKernels, AutoDiffInstantiationsMatchDouble) {
  RandomTreeOptions o;
  o.num_bodies = 9;
  const Model model = RandomTreeModel(7, o);
  Random rng(5);
  const Eigen::VectorXd q = RandomConfiguration(model, &rng);
  const Eigen::VectorXd v = rng.Vector(model.nv());
  const VectorX<AD> q_ad = q.cast<AD>(), v_ad = v.cast<AD>();
  DataTpl<AD> data_ad(model);
  Data data(model);
  ForwardKinematics(model, q_ad, v_ad, &data_ad);
  ForwardKinematics(model, q, v, &data);
  for (BodyIndex b = 0; b < model.num_bodies(); ++b) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(data_ad.p_WB(b)(i).value(), data.p_WB(b)(i), 1e-14);
      EXPECT_NEAR(data_ad.v_WBo(b)(i).value(), data.v_WBo(b)(i), 1e-14);
    }
  }
  const MatrixX<AD>& M_ad = MassMatrix(model, q_ad, &data_ad);
  const Eigen::MatrixXd& M = MassMatrix(model, q, &data);
  for (int i = 0; i < model.nv(); ++i) {
    for (int j = 0; j < model.nv(); ++j) EXPECT_NEAR(M_ad(i, j).value(), M(i, j), 1e-14);
  }
  MatrixX<AD> Nplus_ad;
  Eigen::MatrixXd Nplus;
  CalcNplusMatrix(model, q_ad, &Nplus_ad);
  CalcNplusMatrix(model, q, &Nplus);
  for (int i = 0; i < Nplus.size(); ++i) EXPECT_NEAR(Nplus_ad(i).value(), Nplus(i), 1e-14);
}

}  // namespace
}  // namespace idto
