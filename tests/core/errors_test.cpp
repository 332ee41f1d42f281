#include "idto/core/errors.hpp"

#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "support/eigen_matchers.hpp"
#include "support/finite_difference.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

TEST(Errors, CheckSizeNamesFunctionArgumentFoundAndExpected) {
  EXPECT_NO_THROW(CheckSize("Foo", "q", 7, 7));
  EXPECT_THAT([] { CheckSize("idto::Foo", "q", 3, 7, "nq"); },
              ThrowsMessage<InvalidArgument>("idto::Foo: q is of size 3; expected size 7 (nq)"));
}

TEST(Errors, InvalidArgumentIsAStdInvalidArgument) {
  EXPECT_THROW(CheckPositive("f", "dt", 0.0), std::invalid_argument);
}

TEST(Errors, CheckPositiveRejectsZeroNegativeAndNonFinite) {
  EXPECT_NO_THROW(CheckPositive("f", "dt", 1e-300));
  EXPECT_THAT(
      [] { CheckPositive("f", "time_step", -0.5); },
      ThrowsMessage<InvalidArgument>(HasSubstr("time_step is -0.5; expected a finite positive")));
  EXPECT_THAT([] { CheckPositive("f", "dt", std::numeric_limits<double>::quiet_NaN()); },
              ThrowsMessage<InvalidArgument>(HasSubstr("dt is nan")));
  EXPECT_THAT([] { CheckPositive("f", "dt", std::numeric_limits<double>::infinity()); },
              ThrowsMessage<InvalidArgument>(HasSubstr("dt is inf")));
}

TEST(Errors, CheckNonNegativeScalarAndVector) {
  EXPECT_NO_THROW(CheckNonNegative("f", "w", 0.0));
  EXPECT_THROW(CheckNonNegative("f", "w", -1e-12), InvalidArgument);
  Eigen::Vector3d w(1.0, 0.0, 2.0);
  EXPECT_NO_THROW(CheckNonNegative("f", "Qq", w));
  w(1) = -3.0;
  EXPECT_THAT(
      [&] { CheckNonNegative("SetWeights", "Qq", w); },
      ThrowsMessage<InvalidArgument>("SetWeights: Qq(1) is -3; expected a non-negative number"));
}

TEST(Errors, CheckFiniteNamesFirstBadEntryOfMatrix) {
  Eigen::Matrix2d m = Eigen::Matrix2d::Identity();
  EXPECT_NO_THROW(CheckFinite("f", "m", m));
  m(1, 0) = -std::numeric_limits<double>::infinity();
  EXPECT_THAT([&] { CheckFinite("f", "m", m); },
              ThrowsMessage<InvalidArgument>("f: m(1, 0) is -inf; expected a finite number"));
}

TEST(Errors, FileErrorKeepsFileAndElement) {
  try {
    ThrowFileError("robot.urdf", "joint 'j1'", "unknown joint type 'ball'");
    FAIL() << "no throw";
  } catch (const FileError& e) {
    EXPECT_EQ(e.file(), "robot.urdf");
    EXPECT_EQ(e.element(), "joint 'j1'");
    EXPECT_STREQ(e.what(), "robot.urdf: joint 'j1': unknown joint type 'ball'");
    EXPECT_NE(dynamic_cast<const std::runtime_error*>(&e), nullptr);
  }
}

TEST(Errors, FormatValueRoundTrips) {
  EXPECT_EQ(FormatValue(0.1), "0.1");
  EXPECT_EQ(FormatValue(-2.5e8), "-250000000");
  EXPECT_EQ(FormatValue(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(TestSupport, EigenNearDetectsDifferencesAndNaN) {
  Eigen::Vector2d a(1.0, 2.0), b(1.0, 2.0 + 1e-3);
  EXPECT_TRUE(test::EigenNear("a", "b", "tol", a, b, 1e-2));
  EXPECT_FALSE(test::EigenNear("a", "b", "tol", a, b, 1e-4));
  b(0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(test::EigenNear("a", "b", "tol", a, b, 1e10));
  EXPECT_FALSE(test::EigenNear("a", "b", "tol", a, Eigen::Vector3d::Zero(), 1.0));
}

TEST(TestSupport, FiniteDifferenceJacobianOfKnownFunction) {
  auto f = [](const Eigen::VectorXd& x) {
    Eigen::VectorXd y(2);
    y << std::sin(x(0)) * x(1), x(0) * x(0) * x(0);
    return y;
  };
  Eigen::VectorXd x(2);
  x << 0.3, -1.2;
  Eigen::MatrixXd J(2, 2);
  J << std::cos(0.3) * -1.2, std::sin(0.3), 3 * 0.09, 0.0;
  EXPECT_EIGEN_NEAR(test::FiniteDifferenceJacobian(f, x), J, 1e-8);
  EXPECT_EIGEN_NEAR(test::FiniteDifferenceJacobian(f, x, 1e-3, true), J, 1e-10);
}

TEST(TestSupport, RandomIsSeeded) {
  test::Random a(7), b(7);
  EXPECT_EQ(a.Vector(5), b.Vector(5));
  EXPECT_NEAR(a.Quaternion().norm(), 1.0, 1e-15);
}

}  // namespace
}  // namespace idto
