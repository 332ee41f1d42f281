// BlockConstraintJacobian: the block layout of A = ∂h/∂q and its products against the dense
// matrix.

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "idto/solver/banded_kkt.hpp"
#include "solver/banded_test_support.hpp"
#include "support/eigen_matchers.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

using test::KktProblem;
using test::RandomProblem;

TEST(BlockConstraintJacobian, ProductsAgreeWithDense) {
  test::Random rng(1);
  const KktProblem P = RandomProblem(5, 3, 2, 10.0, 1.0, &rng);
  const Eigen::MatrixXd A = P.A.MakeDense();
  ASSERT_EQ(A.rows(), 10);
  ASSERT_EQ(A.cols(), 15);
  // Only s in {j−1, j, j+1} ∩ [1, N]: h_0 involves q_1 only, h_4 involves q_3, q_4, q_5.
  EXPECT_EQ(A.block(0, 3, 2, 12).norm(), 0.0);
  EXPECT_EQ(A.block(8, 0, 2, 6).norm(), 0.0);
  EXPECT_FALSE(P.A.HasBlock(0, 0));
  EXPECT_FALSE(P.A.HasBlock(4, 6));
  EXPECT_THROW(P.A.Block(0, 0), std::invalid_argument);
  EXPECT_THROW(P.A.Block(2, 4 + 1), std::invalid_argument);
  Eigen::VectorXd Ap;
  EXPECT_THROW(P.A.Multiply(rng.Vector(10), &Ap), std::invalid_argument);
}

// Multiply, MultiplyTranspose and AddMultiplyTranspose against the dense matrix, with one
// constraint per step (plain loops) and several (Eigen's block products).
TEST(BlockConstraintJacobian, ProductsAgreeWithDenseForOneAndSeveralConstraints) {
  for (const auto& [N, n, nu] : std::vector<std::array<int, 3>>{
           {5, 3, 2}, {40, 3, 1}, {7, 5, 1}, {6, 1, 1}, {4, 6, 3}, {1, 2, 1}}) {
    SCOPED_TRACE("N " + std::to_string(N) + " n " + std::to_string(n) + " nu " +
                 std::to_string(nu));
    test::Random rng(N + n + nu);
    const KktProblem P = RandomProblem(N, n, nu, 10.0, 1.0, &rng);
    const Eigen::MatrixXd A = P.A.MakeDense();
    const Eigen::VectorXd p = rng.Vector(N * n);
    const Eigen::VectorXd l = rng.Vector(N * nu);
    const Eigen::VectorXd y0 = rng.Vector(N * n);
    Eigen::VectorXd Ap, Atl, y = y0;
    P.A.Multiply(p, &Ap);
    P.A.MultiplyTranspose(l, &Atl);
    P.A.AddMultiplyTranspose(l, &y);
    EXPECT_EIGEN_NEAR_REL(Ap, Eigen::VectorXd(A * p), 1e-14);
    EXPECT_EIGEN_NEAR_REL(Atl, Eigen::VectorXd(A.transpose() * l), 1e-14);
    EXPECT_EIGEN_NEAR_REL(y, Eigen::VectorXd(y0 + A.transpose() * l), 1e-14);
  }
}

// A block resized through its mutable reference is reported, not read out of bounds.
TEST(BlockConstraintJacobian, ProductsRejectAResizedBlock) {
  for (int nu : {1, 2}) {
    test::Random rng(nu);
    KktProblem P = RandomProblem(4, 3, nu, 10.0, 1.0, &rng);
    P.A.Block(2, 3).resize(nu, 2);
    Eigen::VectorXd Ap, y = Eigen::VectorXd::Zero(12);
    for (int call = 0; call < 2; ++call) {
      try {
        if (call == 0) P.A.Multiply(rng.Vector(12), &Ap);
        if (call == 1) P.A.AddMultiplyTranspose(rng.Vector(4 * nu), &y);
        ADD_FAILURE() << "no exception for a " << nu << " x 2 block";
      } catch (const std::invalid_argument& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("block (2, 3)"), std::string::npos) << message;
        EXPECT_NE(message.find(std::to_string(nu) + " x 2"), std::string::npos) << message;
        EXPECT_NE(message.find(std::to_string(nu) + " x 3 (nu x n)"), std::string::npos) << message;
      }
    }
  }
}

}  // namespace
}  // namespace idto
