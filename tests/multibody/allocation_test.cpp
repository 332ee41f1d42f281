// No algorithm allocates once its Data exists (design.md §4).

#include <gtest/gtest.h>

#define IDTO_DEFINE_ALLOCATION_COUNTER
#include "idto/idto.hpp"
#include "support/allocation_counter.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

TEST(Allocation, AlgorithmsDoNotAllocateAfterDataIsBuilt) {
  if (!test::AllocationCountingAvailable()) GTEST_SKIP() << "malloc is owned by a sanitizer";
  test::RandomTreeOptions o;
  o.num_bodies = 12;
  const Model model = test::RandomTreeModel(21, o);
  Data data(model);
  test::Random rng(1);
  const Eigen::VectorXd q = test::RandomConfiguration(model, &rng);
  const Eigen::VectorXd v = rng.Vector(model.nv());
  const Eigen::VectorXd a = rng.Vector(model.nv());
  const BodyForces F = rng.Matrix(6, model.num_bodies());
  Eigen::Matrix3Xd J(3, model.nv());
  Eigen::Matrix<double, 6, Eigen::Dynamic> J6(6, model.nv());
  Eigen::VectorXd q_next(model.nq()), dv(model.nv());
  {
    // A counter that cannot see allocations would make this test vacuous: check it counts.
    test::ScopedAllocationCounter counter;
    Eigen::VectorXd tmp(100);
    tmp.setZero();
    EXPECT_GE(counter.count(), 1);
  }
  test::ScopedAllocationCounter counter;
  ForwardKinematics(model, q, &data);
  ForwardKinematics(model, q, v, &data);
  InverseDynamics(model, q, v, a, &data);
  InverseDynamics(model, q, v, a, F, &data);
  BiasTerm(model, q, v, &data);
  MassMatrix(model, q, &data);
  ForwardDynamics(model, q, v, a, &data);
  CalcPointJacobian(model, data, model.num_bodies() - 1, Eigen::Vector3d(0.1, 0.2, 0.3), &J);
  CalcFrameJacobian(model, data, 3, Eigen::Isometry3d::Identity(), &J6);
  Integrate(model, q, v, 0.01, &q_next);
  Difference(model, q_next, q, &dv);
  ComputeRneaDerivatives(model, q, v, a, &data);
  ComputeRneaDerivatives(model, q, v, a, &F, &data);
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace idto
