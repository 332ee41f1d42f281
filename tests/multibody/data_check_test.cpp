// The dynamics API refuses a null Data and a Data made for another model (whose buffers it would
// overrun), with InvalidArgument naming the function; a copy of the model keeps its tag.

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include <Eigen/Core>

#include "idto/idto.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

void ExpectRefused(const std::function<void()>& call, const std::string& where,
                   const std::string& what) {
  try {
    call();
    ADD_FAILURE() << where << " accepted a bad Data";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(DataCheck, NullAndForeignDataAreRefused) {
  const Model small = test::Pendulum();
  const Model big = test::RandomTreeModel(3);
  Data data_small(small);
  const Eigen::VectorXd q = big.NeutralConfiguration();
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(big.nv());
  const char* kForeign = "made for another model";
  ExpectRefused([&] { ForwardKinematics(big, q, &data_small); }, "ForwardKinematics", kForeign);
  ExpectRefused([&] { ForwardKinematics(big, q, v, &data_small); }, "ForwardKinematics", kForeign);
  ExpectRefused([&] { InverseDynamics(big, q, v, v, &data_small); }, "InverseDynamics", kForeign);
  ExpectRefused([&] { MassMatrix(big, q, &data_small); }, "MassMatrix", kForeign);
  ExpectRefused([&] { BiasTerm(big, q, v, &data_small); }, "BiasTerm", kForeign);
  ExpectRefused([&] { ForwardDynamics(big, q, v, v, &data_small); }, "ForwardDynamics", kForeign);
  ExpectRefused([&] { ComputeRneaDerivatives(big, q, v, v, &data_small); },
                "ComputeRneaDerivatives", kForeign);
  Eigen::Matrix3Xd J;
  ExpectRefused([&] { CalcPointJacobian(big, data_small, 1, Eigen::Vector3d::Zero(), &J); },
                "CalcPointJacobian", kForeign);
  ExpectRefused([&] { ForwardKinematics(big, q, nullptr); }, "ForwardKinematics", "null");
  ExpectRefused([&] { MassMatrix(big, q, nullptr); }, "MassMatrix", "null");
  // A copy of the model shares its tag: Data made for either works with both.
  const Model copy = big;
  Data data_big(big);
  EXPECT_NO_THROW(MassMatrix(copy, q, &data_big));
  EXPECT_EQ(copy.tag(), big.tag());
  EXPECT_NE(small.tag(), big.tag());
}

}  // namespace
}  // namespace idto
