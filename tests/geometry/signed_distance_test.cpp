#include "idto/geometry/signed_distance.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/core/errors.hpp"
// This binary's one definition of the malloc counter (see allocation_counter.hpp).
#define IDTO_DEFINE_ALLOCATION_COUNTER
#include "geometry/signed_distance_reference.hpp"
#include "support/allocation_counter.hpp"
#include "support/eigen_matchers.hpp"
#include "support/finite_difference.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

using namespace sd_test;  // NOLINT(build/namespaces): the shared references

// ---------------------------------------------------------------------------------------------
// Analytic pairs.

TEST(SignedDistance, AnalyticPairsMatchExactFormulasSeparatedAndPenetrating) {
  for (const PairCase& pair : kAnalyticPairs) {
    SCOPED_TRACE(pair.name);
    test::Random rng(101 + pair.a * 7 + pair.b);
    int separated = 0, penetrating = 0;
    for (int k = 0; k < 400; ++k) {
      const Shape A = RandomShape(&rng, pair.a);
      const Shape B = RandomShape(&rng, pair.b);
      const Isometry3d X_WA = RandomPose(&rng, 0.6);
      const Isometry3d X_WB = RandomPose(&rng, 0.6);
      for (int order = 0; order < 2; ++order) {
        const SignedDistanceResult r =
            order == 0 ? SignedDistance(A, X_WA, B, X_WB) : SignedDistance(B, X_WB, A, X_WA);
        const double expected = Reference(A, X_WA, B, X_WB);
        ASSERT_NEAR(r.distance, expected, kExactTol) << "pose " << k << " order " << order;
        EXPECT_TRUE(r.exact);
        if (order == 0) {
          ExpectConsistent(A, X_WA, B, X_WB, r, kExactTol);
          // The witnesses are joined by the normal: p_WB − p_WA = φ n.
          EXPECT_EIGEN_NEAR(r.p_WB - r.p_WA, r.distance * r.normal_W, kExactTol);
        } else {
          ExpectConsistent(B, X_WB, A, X_WA, r, kExactTol);
        }
      }
      (Reference(A, X_WA, B, X_WB) > 0 ? separated : penetrating)++;
    }
    EXPECT_GT(separated, 40);
    EXPECT_GT(penetrating, 40);
  }
}

TEST(SignedDistance, SwappingShapesFlipsTheNormalAndSwapsWitnesses) {
  for (const auto& pairs : {kAnalyticPairs, kFclPairs}) {
    for (const PairCase& pair : pairs) {
      SCOPED_TRACE(pair.name);
      test::Random rng(202 + pair.a * 7 + pair.b);
      // Same-type FCL pairs are not reordered, so FCL's own order dependence shows.
      bool fcl_same_type = false;
      double distance_discrepancy = 0, normal_discrepancy_separated = 0,
             normal_discrepancy_penetrating = 0;
      for (int k = 0; k < 100; ++k) {
        const Shape A = RandomShape(&rng, pair.a);
        const Shape B = RandomShape(&rng, pair.b);
        const Isometry3d X_WA = RandomPose(&rng, 0.6);
        const Isometry3d X_WB = RandomPose(&rng, 0.6);
        const SignedDistanceResult ab = SignedDistance(A, X_WA, B, X_WB);
        const SignedDistanceResult ba = SignedDistance(B, X_WB, A, X_WA);
        EXPECT_EQ(ab.exact, ba.exact);
        if (pair.a != pair.b || ab.exact) {
          EXPECT_NEAR(ab.distance, ba.distance, kExactTol);
          EXPECT_EIGEN_NEAR(ab.normal_W, -ba.normal_W, kExactTol);
          EXPECT_EIGEN_NEAR(ab.p_WA, ba.p_WB, kExactTol);
          EXPECT_EIGEN_NEAR(ab.p_WB, ba.p_WA, kExactTol);
          continue;
        }
        fcl_same_type = true;
        distance_discrepancy = std::max(distance_discrepancy, std::abs(ab.distance - ba.distance));
        const double normal_discrepancy = (ab.normal_W + ba.normal_W).cwiseAbs().maxCoeff();
        if (ab.distance > 1e-2) {
          normal_discrepancy_separated = std::max(normal_discrepancy_separated, normal_discrepancy);
        } else if (ab.distance < -1e-2) {
          normal_discrepancy_penetrating =
              std::max(normal_discrepancy_penetrating, normal_discrepancy);
        }
      }
      if (fcl_same_type) {
        std::cout << "[ measured ] " << pair.name << " (A,B) vs (B,A): max |dphi| "
                  << distance_discrepancy << " m, max |dn| separated "
                  << normal_discrepancy_separated << ", penetrating "
                  << normal_discrepancy_penetrating << "\n";
        EXPECT_LT(distance_discrepancy, 1e-5);
        EXPECT_LT(normal_discrepancy_separated, 1e-4);
        EXPECT_LT(normal_discrepancy_penetrating, 1e-2);
      }
    }
  }
}

TEST(SignedDistance, GradientWithRespectToTranslationIsTheNormal) {
  constexpr double kStep = 1e-5;  // fourth-order differences
  for (const PairCase& pair : kAnalyticPairs) {
    SCOPED_TRACE(pair.name);
    test::Random rng(303 + pair.a * 7 + pair.b);
    double worst = 0.0;
    for (int k = 0; k < 100; ++k) {
      const Shape A = RandomShape(&rng, pair.a);
      const Shape B = RandomShape(&rng, pair.b);
      const Isometry3d X_WA = RandomPose(&rng, 0.6);
      const Isometry3d X_WB = RandomPose(&rng, 0.6);
      const SignedDistanceResult r = SignedDistance(A, X_WA, B, X_WB);
      auto phi_of_B = [&](const Eigen::VectorXd& p) {
        Isometry3d X = X_WB;
        X.translation() = p;
        return Eigen::VectorXd::Constant(1, SignedDistance(A, X_WA, B, X).distance);
      };
      auto phi_of_A = [&](const Eigen::VectorXd& p) {
        Isometry3d X = X_WA;
        X.translation() = p;
        return Eigen::VectorXd::Constant(1, SignedDistance(A, X, B, X_WB).distance);
      };
      const Eigen::MatrixXd dphi_dpB =
          test::FiniteDifferenceJacobian(phi_of_B, X_WB.translation(), kStep, true);
      const Eigen::MatrixXd dphi_dpA =
          test::FiniteDifferenceJacobian(phi_of_A, X_WA.translation(), kStep, true);
      EXPECT_EIGEN_NEAR(Vector3d(dphi_dpB.transpose()), r.normal_W, 1e-8) << "pose " << k;
      EXPECT_EIGEN_NEAR(Vector3d(dphi_dpA.transpose()), -r.normal_W, 1e-8) << "pose " << k;
      worst = std::max(worst, (Vector3d(dphi_dpB.transpose()) - r.normal_W).cwiseAbs().maxCoeff());
    }
    RecordProperty(std::string("fd_gradient_error_") + pair.name, std::to_string(worst));
  }
}

TEST(SignedDistance, AnalyticPairsAgreeWithFclWhenSeparated) {
  // Half-space pairs are never given to FCL.
  for (const PairCase& pair : kAnalyticPairs) {
    if (pair.b == 4) continue;
    SCOPED_TRACE(pair.name);
    test::Random rng(404 + pair.a * 7 + pair.b);
    int compared = 0;
    for (int k = 0; k < 300; ++k) {
      const Shape A = RandomShape(&rng, pair.a);
      const Shape B = RandomShape(&rng, pair.b);
      const Isometry3d X_WA = RandomPose(&rng, 0.8);
      const Isometry3d X_WB = RandomPose(&rng, 0.8);
      const SignedDistanceResult exact = SignedDistance(A, X_WA, B, X_WB);
      if (exact.distance <= 1e-3) continue;
      const SignedDistanceResult fcl = SignedDistanceFcl(A, X_WA, B, X_WB);
      EXPECT_FALSE(fcl.exact);
      EXPECT_NEAR(fcl.distance, exact.distance, 1e-6) << "pose " << k;
      EXPECT_EIGEN_NEAR(fcl.normal_W, exact.normal_W, 1e-4);
      EXPECT_EIGEN_NEAR(fcl.p_WA, exact.p_WA, 1e-4);
      EXPECT_EIGEN_NEAR(fcl.p_WB, exact.p_WB, 1e-4);
      ++compared;
    }
    EXPECT_GT(compared, 50);
  }
}

// ---------------------------------------------------------------------------------------------
// FCL fallback.

TEST(SignedDistance, FclPairsAreMarkedApproximateAndConsistent) {
  for (const PairCase& pair : kFclPairs) {
    SCOPED_TRACE(pair.name);
    test::Random rng(505 + pair.a * 7 + pair.b);
    int separated = 0, penetrating = 0;
    for (int k = 0; k < 200; ++k) {
      const Shape A = RandomShape(&rng, pair.a);
      const Shape B = RandomShape(&rng, pair.b);
      const Isometry3d X_WA = RandomPose(&rng, 0.6);
      const Isometry3d X_WB = RandomPose(&rng, 0.6);
      EXPECT_FALSE(SignedDistanceIsExact(A, B));
      const SignedDistanceResult r = SignedDistance(A, X_WA, B, X_WB);
      EXPECT_FALSE(r.exact);
      // Witnesses are on the surfaces to GJK accuracy (separated) or EPA accuracy (penetrating).
      ExpectConsistent(A, X_WA, B, X_WB, r, r.distance > 0 ? 1e-8 : 1e-5);
      (r.distance > 0 ? separated : penetrating)++;
    }
    EXPECT_GT(separated, 20);
    EXPECT_GT(penetrating, 20);
  }
}

TEST(SignedDistance, FclPairsOnPosesWithKnownAnswers) {
  const Isometry3d I = Isometry3d::Identity();
  // Axis-aligned boxes 0.3 apart along x.
  const Box box{Vector3d(1.0, 0.5, 0.5)};
  SignedDistanceResult r = SignedDistance(box, I, box, Translation(1.3, 0.1, -0.05));
  EXPECT_NEAR(r.distance, 0.3, 1e-10);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitX(), 1e-8);
  // Overlapping by 0.2 along y.
  r = SignedDistance(box, I, box, Translation(0.1, 0.3, 0.0));
  EXPECT_NEAR(r.distance, -0.2, 1e-6);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitY(), 1e-5);
  // Coaxial cylinders 0.25 apart along z; penetrating by 0.1.
  const Cylinder cylinder{0.2, 0.6};
  r = SignedDistance(cylinder, I, cylinder, Translation(0.0, 0.05, 0.85));
  EXPECT_NEAR(r.distance, 0.25, 1e-10);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitZ(), 1e-8);
  r = SignedDistance(cylinder, I, cylinder, Translation(0.0, 0.0, 0.5));
  EXPECT_NEAR(r.distance, -0.1, 1e-6);
  // A capsule standing 0.2 above a box.
  const Capsule capsule{0.1, 0.4};
  r = SignedDistance(capsule, Translation(0.1, -0.1, 0.8), box, I);
  EXPECT_NEAR(r.distance, 0.8 - 0.2 - 0.1 - 0.25, 1e-10);
  EXPECT_EIGEN_NEAR(r.normal_W, -Vector3d::UnitZ(), 1e-8);
  // A capsule lying across a cylinder's side.
  Isometry3d X_capsule = Translation(0.0, 0.5, 0.0);
  X_capsule.linear() = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()).toRotationMatrix();
  r = SignedDistance(capsule, X_capsule, cylinder, I);
  EXPECT_NEAR(r.distance, 0.5 - 0.1 - 0.2, 1e-10);
}

TEST(SignedDistance, FclCapsuleBoxAgainstTruthAndMeasuredOrderDependence) {
  test::Random rng(606);
  double max_separated_error = 0, max_penetrating_error = 0;
  double max_fcl_order_discrepancy = 0;  // SignedDistanceFcl(capsule, box) vs (box, capsule)
  int separated = 0, penetrating = 0;
  for (int k = 0; k < 600; ++k) {
    const Capsule capsule{rng.Uniform(0.05, 0.2), rng.Uniform(0.1, 0.6)};
    const Box box{rng.Vector(3, 0.1, 0.6)};
    const Isometry3d X_WA = RandomPose(&rng, 0.6);
    const Isometry3d X_WB = RandomPose(&rng, 0.6);
    double segment_distance = 0;
    const double truth = CapsuleBoxTruth(capsule, X_WA, box, X_WB, &segment_distance);
    if (segment_distance < 1e-4) continue;  // truth above needs the segment outside the box
    const SignedDistanceResult r = SignedDistance(capsule, X_WA, box, X_WB);
    const SignedDistanceResult r_fcl_ba = SignedDistanceFcl(box, X_WB, capsule, X_WA);
    const SignedDistanceResult r_fcl_ab = SignedDistanceFcl(capsule, X_WA, box, X_WB);
    EXPECT_FALSE(r.exact);
    EXPECT_EQ(r.distance, r_fcl_ab.distance);  // the canonical order is (capsule, box)
    const double error = std::abs(r.distance - truth);
    if (truth > 0) {
      ++separated;
      max_separated_error = std::max(max_separated_error, error);
      EXPECT_LT(error, 1e-8) << "pose " << k;
      max_fcl_order_discrepancy =
          std::max(max_fcl_order_discrepancy, std::abs(r_fcl_ab.distance - r_fcl_ba.distance));
    } else {
      ++penetrating;
      max_penetrating_error = std::max(max_penetrating_error, error);
      EXPECT_LT(error, 1e-5) << "pose " << k;
    }
  }
  EXPECT_GT(separated, 100);
  EXPECT_GT(penetrating, 20);
  std::cout << "[ measured ] FCL capsule-box: max |error| separated " << max_separated_error
            << " m (" << separated << " poses), penetrating " << max_penetrating_error << " m ("
            << penetrating << " poses); max |phi(A,B) - phi(B,A)| separated "
            << max_fcl_order_discrepancy << " m\n";
  RecordProperty("fcl_capsule_box_separated_error", std::to_string(max_separated_error));
  RecordProperty("fcl_capsule_box_penetrating_error", std::to_string(max_penetrating_error));
  RecordProperty("fcl_capsule_box_order_discrepancy", std::to_string(max_fcl_order_discrepancy));
}

// The paper's Remark on collision geometries: iterative distance breaks finite differences.
// For FCL's capsule–box answer and an analytic sphere–box answer, on smooth poses, measures
// against the true gradient of φ with respect to B's translation (from the exact reference):
// the error of the returned normal, and the error of central differences of φ with step h.
TEST(SignedDistance, FiniteDifferenceGradientNoiseFclVersusAnalytic) {
  struct Row {
    std::string name;
    double step;
    double normal_error;
    double fd_error;
    int poses;
  };
  std::vector<Row> rows;
  const Box box{Vector3d(0.3, 0.2, 0.5)};
  const Capsule capsule{0.1, 0.4};
  const Sphere sphere{0.25};
  // Exact φ and its gradient with respect to B's translation.
  auto reference = [&](const Shape& A, const Isometry3d& X_WA, const Isometry3d& X_WB,
                       double* core_distance, Vector3d* gradient) {
    if (const auto* c = std::get_if<Capsule>(&A)) {
      return CapsuleBoxTruth(*c, X_WA, box, X_WB, core_distance, gradient);
    }
    *core_distance = PointBoxDistance(box, X_WB, X_WA.translation(), gradient);
    return *core_distance - std::get<Sphere>(A).radius;
  };
  auto measure = [&](const Shape& A, bool separated, double step, Row* row) {
    test::Random rng(707);
    row->poses = 0;
    row->normal_error = row->fd_error = 0.0;
    for (int k = 0; k < 2000 && row->poses < 40; ++k) {
      const Isometry3d X_WA = RandomPose(&rng, 0.5);
      const Isometry3d X_WB = RandomPose(&rng, 0.5);
      // Smooth poses only: clearly separated, or penetrating with A's core (segment or
      // centre) clearly outside the box, where the reference is smooth.
      double core = 0;
      Vector3d g_true;
      const double truth = reference(A, X_WA, X_WB, &core, &g_true);
      if (separated ? truth < 0.02 : (truth > -0.02 || core < 0.02)) continue;
      ++row->poses;
      Vector3d g_fd;
      for (int i = 0; i < 3; ++i) {
        Isometry3d X_plus = X_WB, X_minus = X_WB;
        X_plus.translation()(i) += step;
        X_minus.translation()(i) -= step;
        g_fd(i) = (SignedDistance(A, X_WA, box, X_plus).distance -
                   SignedDistance(A, X_WA, box, X_minus).distance) /
                  (2 * step);
      }
      const SignedDistanceResult r = SignedDistance(A, X_WA, box, X_WB);
      row->normal_error = std::max(row->normal_error, (r.normal_W - g_true).cwiseAbs().maxCoeff());
      row->fd_error = std::max(row->fd_error, (g_fd - g_true).cwiseAbs().maxCoeff());
    }
  };
  for (const bool separated : {true, false}) {
    const std::string where = separated ? " separated" : " penetrating";
    for (const double step : {1e-4, 1e-6, 1e-8}) {
      Row fcl{"FCL capsule-box" + where, step, 0, 0, 0};
      measure(capsule, separated, step, &fcl);
      rows.push_back(fcl);
      Row exact{"analytic sphere-box" + where, step, 0, 0, 0};
      measure(sphere, separated, step, &exact);
      rows.push_back(exact);
    }
  }
  std::cout
      << "[ measured ] max error against the true gradient of phi wrt p_B, 40 smooth poses:\n"
      << "             pair / class                      |n - grad|   h       |FD(h) - grad|\n";
  for (const Row& row : rows) {
    std::cout << "             " << std::left << std::setw(33) << row.name << " " << std::setw(12)
              << row.normal_error << " " << std::setw(7) << row.step << " " << row.fd_error << "\n";
    EXPECT_TRUE(std::isfinite(row.fd_error) && std::isfinite(row.normal_error));
    EXPECT_GE(row.poses, 20);
    RecordProperty(row.name + " h=" + std::to_string(row.step),
                   std::to_string(row.normal_error) + " " + std::to_string(row.fd_error));
    // Only the analytic answer is asserted smooth: truncation error O(h²) at h = 1e-4,
    // round-off O(eps/h) at h = 1e-8.
    if (row.name.rfind("analytic", 0) == 0) {
      EXPECT_LT(row.normal_error, 1e-9);
      EXPECT_LT(row.fd_error, row.step >= 1e-4 ? 1e-4 : (row.step >= 1e-6 ? 1e-7 : 1e-6));
    }
  }
}

}  // namespace
}  // namespace idto
