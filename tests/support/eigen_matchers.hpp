#pragma once

/// @file
/// EXPECT_EIGEN_NEAR(a, b, tol): element-wise comparison of Eigen objects with a readable
/// failure message (sizes, the worst entry, both matrices). The tolerance is absolute unless
/// EXPECT_EIGEN_NEAR_REL is used, which scales it by max(1, max|b|).

#include <cmath>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Core>

namespace idto::test {

template <typename A, typename B>
::testing::AssertionResult EigenNear(const char* a_expr, const char* b_expr, const char*,
                                     const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b,
                                     double tol, bool relative = false) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure()
           << a_expr << " is " << a.rows() << "x" << a.cols() << " but " << b_expr << " is "
           << b.rows() << "x" << b.cols();
  }
  double scale = 1.0;
  if (relative && b.size() > 0) scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  double worst = 0.0;
  Eigen::Index wi = 0, wj = 0;
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      const double d = std::abs(static_cast<double>(a(i, j)) - static_cast<double>(b(i, j)));
      if (!(d <= worst) || std::isnan(d)) {  // NaN always counts as worst
        worst = std::isnan(d) ? INFINITY : d;
        wi = i;
        wj = j;
      }
    }
  }
  if (worst <= tol * scale) return ::testing::AssertionSuccess();
  Eigen::IOFormat fmt(Eigen::FullPrecision, 0, ", ", "\n", "[", "]");
  std::ostringstream out;
  out << a_expr << " and " << b_expr << " differ by " << worst << " at (" << wi << ", " << wj
      << "), tolerance " << tol * scale << "\n"
      << a_expr << " =\n"
      << a.format(fmt) << "\n"
      << b_expr << " =\n"
      << b.format(fmt);
  return ::testing::AssertionFailure() << out.str();
}

template <typename A, typename B>
::testing::AssertionResult EigenNearRel(const char* a_expr, const char* b_expr,
                                        const char* tol_expr, const Eigen::MatrixBase<A>& a,
                                        const Eigen::MatrixBase<B>& b, double tol) {
  return EigenNear(a_expr, b_expr, tol_expr, a, b, tol, true);
}

}  // namespace idto::test

#define EXPECT_EIGEN_NEAR(a, b, tol) EXPECT_PRED_FORMAT3(::idto::test::EigenNear, a, b, tol)
#define ASSERT_EIGEN_NEAR(a, b, tol) ASSERT_PRED_FORMAT3(::idto::test::EigenNear, a, b, tol)
#define EXPECT_EIGEN_NEAR_REL(a, b, tol) EXPECT_PRED_FORMAT3(::idto::test::EigenNearRel, a, b, tol)
