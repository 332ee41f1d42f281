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
#include "support/allocation_counter.hpp"
#include "support/eigen_matchers.hpp"
#include "support/finite_difference.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kExactTol = 1e-12;

// ---------------------------------------------------------------------------------------------
// Independent references (hand-derived; written differently from the library's code).

// Signed distance from a world point to a shape (negative inside).
double PointSdf(const Shape& shape, const Isometry3d& X_WS, const Vector3d& p_W) {
  const Vector3d p = X_WS.inverse() * p_W;
  if (const auto* s = std::get_if<Sphere>(&shape)) return p.norm() - s->radius;
  if (const auto* c = std::get_if<Capsule>(&shape)) {
    const double h = 0.5 * c->length;
    const Vector3d a(0, 0, -h), b(0, 0, h);
    double d;
    if (p.z() > h) {
      d = (p - b).norm();
    } else if (p.z() < -h) {
      d = (p - a).norm();
    } else {
      d = std::hypot(p.x(), p.y());
    }
    return d - c->radius;
  }
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    const double dr = std::hypot(p.x(), p.y()) - c->radius;
    const double dz = std::abs(p.z()) - 0.5 * c->length;
    return std::hypot(std::max(dr, 0.0), std::max(dz, 0.0)) + std::min(std::max(dr, dz), 0.0);
  }
  if (const auto* b = std::get_if<Box>(&shape)) {
    const Vector3d q = p.cwiseAbs() - 0.5 * b->size;
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
  }
  return p.z();  // half-space
}

// Distance from point p to segment [a, b] by the cross-product formula.
double PointSegmentDistance(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d ab = b - a;
  const double L2 = ab.squaredNorm();
  if (L2 == 0.0) return (p - a).norm();
  const double t = (p - a).dot(ab) / L2;
  if (t <= 0.0) return (p - a).norm();
  if (t >= 1.0) return (p - b).norm();
  return (p - a).cross(ab).norm() / std::sqrt(L2);
}

std::pair<Vector3d, Vector3d> Endpoints(const Capsule& c, const Isometry3d& X) {
  return {X * Vector3d(0, 0, -0.5 * c.length), X * Vector3d(0, 0, 0.5 * c.length)};
}

// Segment–segment distance: the minimum over the four endpoint–segment distances and, when the
// lines' common perpendicular meets both segments, the line–line distance.
double SegmentSegmentDistance(const Vector3d& a0, const Vector3d& a1, const Vector3d& b0,
                              const Vector3d& b1) {
  double d = std::min({PointSegmentDistance(a0, b0, b1), PointSegmentDistance(a1, b0, b1),
                       PointSegmentDistance(b0, a0, a1), PointSegmentDistance(b1, a0, a1)});
  const Vector3d u = a1 - a0, v = b1 - b0, w = a0 - b0;
  const Vector3d n = u.cross(v);
  if (n.squaredNorm() > 1e-12 * u.squaredNorm() * v.squaredNorm()) {
    // Parameters of the common perpendicular's feet (Cramer's rule).
    const double s = (v.cross(w)).dot(n) / n.squaredNorm();
    const double t = (u.cross(w)).dot(n) / n.squaredNorm();
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) d = std::min(d, std::abs(w.dot(n)) / n.norm());
  }
  return d;
}

double Height(const Isometry3d& X_WH, const Vector3d& p_W) {
  return X_WH.linear().col(2).dot(p_W - X_WH.translation());
}

// Exact reference for every analytic pair.
double Reference(const Shape& A, const Isometry3d& X_WA, const Shape& B, const Isometry3d& X_WB) {
  if (A.index() > B.index()) return Reference(B, X_WB, A, X_WA);
  if (const auto* s = std::get_if<Sphere>(&A)) {
    return PointSdf(B, X_WB, X_WA.translation()) - s->radius;
  }
  if (const auto* c = std::get_if<Capsule>(&A)) {
    const auto [a0, a1] = Endpoints(*c, X_WA);
    if (std::holds_alternative<HalfSpace>(B)) {
      return std::min(Height(X_WB, a0), Height(X_WB, a1)) - c->radius;
    }
    const auto& cb = std::get<Capsule>(B);
    const auto [b0, b1] = Endpoints(cb, X_WB);
    return SegmentSegmentDistance(a0, a1, b0, b1) - c->radius - cb.radius;
  }
  if (const auto* c = std::get_if<Cylinder>(&A)) {
    // Lowest rim point of each cap: cap centre height minus R·|n_perp|.
    const Vector3d n = X_WB.linear().col(2);
    const Vector3d u = X_WA.linear().col(2);
    const double sin_angle = n.cross(u).norm();
    const double h = 0.5 * c->length;
    return std::min(Height(X_WB, X_WA * Vector3d(0, 0, h)),
                    Height(X_WB, X_WA * Vector3d(0, 0, -h))) -
           c->radius * sin_angle;
  }
  const auto& box = std::get<Box>(A);
  double d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 8; ++i) {
    const Vector3d corner(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    d = std::min(d, Height(X_WB, X_WA * (0.5 * box.size.cwiseProduct(corner))));
  }
  return d;
}

// Distance from a world point to a box (zero inside) and, outside, the unit direction from the
// point to its nearest box point: the gradient of that distance with respect to the box's
// translation.
double PointBoxDistance(const Box& b, const Isometry3d& X_WB, const Vector3d& p_W,
                        Vector3d* direction_W = nullptr) {
  const Vector3d p = X_WB.inverse() * p_W;
  const Vector3d e = 0.5 * b.size;
  const Vector3d q = p.cwiseMax(-e).cwiseMin(e);
  const double d = (q - p).norm();
  if (direction_W != nullptr && d > 0) *direction_W = X_WB.linear() * (q - p) / d;
  return d;
}

// Capsule–box truth for poses where the capsule's segment is outside the box. The distance
// g(t) from the segment point at t to the box is convex and C¹ there; its minimizer is found by
// bisection on the sign of g'(t), which converges to machine precision (a search on g itself
// would only reach sqrt(eps) in t). By the envelope theorem, the gradient of φ with respect to
// the box's translation is the direction from the nearest segment point to the box.
double CapsuleBoxTruth(const Capsule& c, const Isometry3d& X_WA, const Box& b,
                       const Isometry3d& X_WB, double* segment_distance,
                       Vector3d* gradient_B = nullptr) {
  const Vector3d u = X_WA.linear().col(2);
  auto point = [&](double t) { return Vector3d(X_WA * Vector3d(0, 0, t)); };
  auto slope = [&](double t) {
    Vector3d n = Vector3d::Zero();
    PointBoxDistance(b, X_WB, point(t), &n);
    return -n.dot(u);  // d/dt |p(t) − q(p(t))|
  };
  double lo = -0.5 * c.length, hi = 0.5 * c.length, t = 0;
  if (slope(lo) >= 0) {
    t = lo;
  } else if (slope(hi) <= 0) {
    t = hi;
  } else {
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (slope(mid) < 0 ? lo : hi) = mid;
    }
    t = 0.5 * (lo + hi);
  }
  Vector3d n = Vector3d::Zero();
  *segment_distance = PointBoxDistance(b, X_WB, point(t), &n);
  if (gradient_B != nullptr) *gradient_B = n;
  return *segment_distance - c.radius;
}

// ---------------------------------------------------------------------------------------------
// Helpers.

Isometry3d RandomPose(test::Random* rng, double range) {
  Isometry3d X = Isometry3d::Identity();
  X.linear() = rng->Quaternion().toRotationMatrix();
  X.translation() = rng->Vector(3, -range, range);
  return X;
}

Isometry3d Translation(double x, double y, double z) {
  Isometry3d X = Isometry3d::Identity();
  X.translation() = Vector3d(x, y, z);
  return X;
}

Shape RandomShape(test::Random* rng, std::size_t index) {
  switch (index) {
    case 0:
      return Sphere{rng->Uniform(0.05, 0.5)};
    case 1:
      return Capsule{rng->Uniform(0.05, 0.3), rng->Uniform(0.0, 0.8)};
    case 2:
      return Cylinder{rng->Uniform(0.05, 0.4), rng->Uniform(0.05, 0.8)};
    case 3:
      return Box{
          Vector3d(rng->Uniform(0.05, 0.8), rng->Uniform(0.05, 0.8), rng->Uniform(0.05, 0.8))};
    default:
      return HalfSpace{};
  }
}

bool AllFinite(const SignedDistanceResult& r) {
  return std::isfinite(r.distance) && r.normal_W.allFinite() && r.p_WA.allFinite() &&
         r.p_WB.allFinite();
}

// Checks the invariants every answer satisfies: finite, unit normal, the identity
// (p_WB − p_WA)·n = φ, and witnesses on the surfaces (within `surface_tol`).
void ExpectConsistent(const Shape& A, const Isometry3d& X_WA, const Shape& B,
                      const Isometry3d& X_WB, const SignedDistanceResult& r, double surface_tol) {
  ASSERT_TRUE(AllFinite(r));
  EXPECT_NEAR(r.normal_W.norm(), 1.0, 1e-14);
  const double scale = 1.0 + std::abs(r.distance);
  EXPECT_NEAR((r.p_WB - r.p_WA).dot(r.normal_W), r.distance, kExactTol * scale);
  EXPECT_NEAR(PointSdf(A, X_WA, r.p_WA), 0.0, surface_tol);
  EXPECT_NEAR(PointSdf(B, X_WB, r.p_WB), 0.0, surface_tol);
}

struct PairCase {
  std::size_t a;
  std::size_t b;
  const char* name;
};

const std::vector<PairCase> kAnalyticPairs = {
    {0, 0, "sphere-sphere"},   {0, 4, "sphere-half_space"},   {0, 1, "sphere-capsule"},
    {0, 2, "sphere-cylinder"}, {0, 3, "sphere-box"},          {1, 4, "capsule-half_space"},
    {1, 1, "capsule-capsule"}, {2, 4, "cylinder-half_space"}, {3, 4, "box-half_space"},
};

const std::vector<PairCase> kFclPairs = {
    {1, 2, "capsule-cylinder"}, {1, 3, "capsule-box"}, {2, 2, "cylinder-cylinder"},
    {2, 3, "cylinder-box"},     {3, 3, "box-box"},
};

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

// ---------------------------------------------------------------------------------------------
// Documented degenerate and extreme cases.

TEST(SignedDistance, ConcentricSpheresUseWorldZ) {
  const Isometry3d X = Translation(0.3, -0.2, 1.0);
  const SignedDistanceResult r = SignedDistance(Sphere{0.5}, X, Sphere{0.2}, X);
  ASSERT_TRUE(AllFinite(r));
  EXPECT_DOUBLE_EQ(r.distance, -0.7);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitZ(), 0.0);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0.3, -0.2, 1.5), 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WB, Vector3d(0.3, -0.2, 0.8), 1e-15);
}

TEST(SignedDistance, ExactTouchingGivesZero) {
  const Isometry3d I = Isometry3d::Identity();
  EXPECT_EQ(SignedDistance(Sphere{0.5}, I, Sphere{0.25}, Translation(0.75, 0, 0)).distance, 0.0);
  EXPECT_EQ(SignedDistance(Sphere{0.5}, Translation(0, 0, 0.5), HalfSpace{}, I).distance, 0.0);
  EXPECT_EQ(SignedDistance(Box{Vector3d(1, 1, 1)}, I, Sphere{0.5}, Translation(1, 0, 0)).distance,
            0.0);
  EXPECT_EQ(SignedDistance(Box{Vector3d(1, 2, 3)}, Translation(0, 0, 1.5), HalfSpace{}, I).distance,
            0.0);
  EXPECT_EQ(SignedDistance(Cylinder{0.5, 2}, Translation(0, 0, 1), HalfSpace{}, I).distance, 0.0);
  EXPECT_EQ(SignedDistance(Capsule{0.5, 1}, I, Capsule{0.5, 1}, Translation(1, 0, 0)).distance,
            0.0);
  // FCL at exact contact: finite, with a normal, distance ~0.
  const SignedDistanceResult r =
      SignedDistance(Box{Vector3d(1, 1, 1)}, I, Box{Vector3d(1, 1, 1)}, Translation(1, 0.2, 0.1));
  ASSERT_TRUE(AllFinite(r));
  EXPECT_NEAR(r.distance, 0.0, 1e-9);
  EXPECT_NEAR(r.normal_W.norm(), 1.0, 1e-14);
}

TEST(SignedDistance, SphereCentreOnBoxFaceEdgeAndCorner) {
  const Box box{Vector3d(2.0, 1.0, 0.5)};
  const Isometry3d I = Isometry3d::Identity();
  const Sphere sphere{0.1};
  struct Case {
    Vector3d centre;
    Vector3d normal_from_box;  // documented tie-break: lower axis first, + before −
  };
  const std::vector<Case> cases = {
      {Vector3d(1.0, 0.1, 0.0), Vector3d::UnitX()},      // +x face
      {Vector3d(0.2, -0.5, 0.1), -Vector3d::UnitY()},    // −y face
      {Vector3d(1.0, 0.5, 0.0), Vector3d::UnitX()},      // edge: x wins
      {Vector3d(0.0, -0.5, -0.25), -Vector3d::UnitY()},  // edge: y wins over z
      {Vector3d(-1.0, -0.5, 0.25), -Vector3d::UnitX()},  // corner
      {Vector3d(0.0, 0.0, 0.0), Vector3d::UnitZ()},      // centre: nearest face is ±z, + wins
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.centre.transpose());
    const SignedDistanceResult r =
        SignedDistance(box, I, sphere, Translation(c.centre.x(), c.centre.y(), c.centre.z()));
    ASSERT_TRUE(AllFinite(r));
    EXPECT_NEAR(r.distance, PointSdf(box, I, c.centre) - 0.1, 1e-15);
    EXPECT_EIGEN_NEAR(r.normal_W, c.normal_from_box, 0.0);
    ExpectConsistent(box, I, sphere, Translation(c.centre.x(), c.centre.y(), c.centre.z()), r,
                     1e-15);
  }
}

TEST(SignedDistance, SphereCentreOnCylinderAxisAndCapsuleSegment) {
  const Isometry3d I = Isometry3d::Identity();
  // Cylinder: centre on the axis, the side nearest -> as if displaced along +x.
  SignedDistanceResult r = SignedDistance(Sphere{0.1}, Translation(0, 0, 0.2), Cylinder{0.3, 2}, I);
  ASSERT_TRUE(AllFinite(r));
  EXPECT_DOUBLE_EQ(r.distance, -0.4);
  EXPECT_EIGEN_NEAR(r.normal_W, -Vector3d::UnitX(), 0.0);
  EXPECT_EIGEN_NEAR(r.p_WB, Vector3d(0.3, 0, 0.2), 1e-15);
  // Cylinder: centre on the axis, the +z cap nearest.
  r = SignedDistance(Sphere{0.1}, Translation(0, 0, 0.9), Cylinder{0.3, 2}, I);
  EXPECT_NEAR(r.distance, -0.2, 1e-15);
  EXPECT_EIGEN_NEAR(r.normal_W, -Vector3d::UnitZ(), 0.0);
  // Capsule: centre on the segment.
  r = SignedDistance(Sphere{0.1}, Translation(0, 0, 0.3), Capsule{0.2, 1}, I);
  ASSERT_TRUE(AllFinite(r));
  EXPECT_DOUBLE_EQ(r.distance, -0.3);
  EXPECT_EIGEN_NEAR(r.normal_W, -Vector3d::UnitX(), 0.0);
  ExpectConsistent(Sphere{0.1}, Translation(0, 0, 0.3), Capsule{0.2, 1}, I, r, 1e-15);
}

TEST(SignedDistance, CapsuleCapsuleDegenerateConfigurations) {
  const Capsule capsule{0.1, 1.0};
  const Isometry3d I = Isometry3d::Identity();
  // Parallel, overlapping over z in [0.2, 0.5]: witnesses at the middle of the overlap.
  SignedDistanceResult r = SignedDistance(capsule, I, capsule, Translation(0.5, 0.0, 0.7));
  EXPECT_NEAR(r.distance, 0.3, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0.1, 0, 0.35), 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WB, Vector3d(0.4, 0, 0.35), 1e-15);
  // Anti-parallel (B flipped) gives the same.
  Isometry3d X_flip = Translation(0.5, 0.0, 0.7);
  X_flip.linear() = Eigen::AngleAxisd(M_PI, Vector3d::UnitX()).toRotationMatrix();
  r = SignedDistance(capsule, I, capsule, X_flip);
  EXPECT_NEAR(r.distance, 0.3, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0.1, 0, 0.35), 1e-15);
  // Parallel without overlap: nearest ends.
  r = SignedDistance(capsule, I, capsule, Translation(0.0, 0.3, 1.4));
  EXPECT_NEAR(r.distance, std::hypot(0.3, 0.4) - 0.2, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0, 0.6 * 0.1, 0.5 + 0.8 * 0.1), 1e-15);
  // Crossing segments: normal along axis_A × axis_B = z × x = +y.
  Isometry3d X_cross = Translation(0.0, 0.0, 0.1);
  X_cross.linear() = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()).toRotationMatrix();
  r = SignedDistance(capsule, I, capsule, X_cross);
  ASSERT_TRUE(AllFinite(r));
  EXPECT_DOUBLE_EQ(r.distance, -0.2);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitY(), 1e-15);
  const SignedDistanceResult swapped = SignedDistance(capsule, X_cross, capsule, I);
  EXPECT_EIGEN_NEAR(swapped.normal_W, -Vector3d::UnitY(), 1e-15);
  // Collinear and overlapping: +x of A.
  r = SignedDistance(capsule, I, capsule, Translation(0.0, 0.0, 0.4));
  ASSERT_TRUE(AllFinite(r));
  EXPECT_DOUBLE_EQ(r.distance, -0.2);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitX(), 0.0);
  // Zero-length capsules are spheres.
  r = SignedDistance(Capsule{0.2, 0.0}, I, Capsule{0.3, 0.0}, Translation(0, 1, 0));
  EXPECT_NEAR(r.distance, 0.5, 1e-15);
}

TEST(SignedDistance, ShapesParallelToAHalfSpaceUseTheCentroidOfTheDeepestFeature) {
  const Isometry3d I = Isometry3d::Identity();
  // Box resting on a face, rotated about z: witness at the centre of the bottom face.
  Isometry3d X_box = Translation(0.4, -0.3, 0.45);
  X_box.linear() = Eigen::AngleAxisd(0.7, Vector3d::UnitZ()).toRotationMatrix();
  SignedDistanceResult r = SignedDistance(Box{Vector3d(1, 2, 1)}, X_box, HalfSpace{}, I);
  EXPECT_NEAR(r.distance, -0.05, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0.4, -0.3, -0.05), 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WB, Vector3d(0.4, -0.3, 0.0), 1e-15);
  EXPECT_EIGEN_NEAR(r.normal_W, -Vector3d::UnitZ(), 0.0);
  // Box on an edge (rotated 45° about x): witness at the middle of the bottom edge.
  X_box.linear() = Eigen::AngleAxisd(M_PI / 4, Vector3d::UnitX()).toRotationMatrix();
  X_box.translation() = Vector3d(0, 0, 1.0);
  r = SignedDistance(Box{Vector3d(1, 1, 1)}, X_box, HalfSpace{}, I);
  EXPECT_NEAR(r.distance, 1.0 - std::sqrt(0.5), 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(0, 0, 1.0 - std::sqrt(0.5)), 1e-15);
  // Upright cylinder: centre of the lower cap. Lying cylinder: middle of the lowest line.
  r = SignedDistance(Cylinder{0.3, 1.0}, Translation(1, 2, 0.4), HalfSpace{}, I);
  EXPECT_NEAR(r.distance, -0.1, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(1, 2, -0.1), 1e-15);
  Isometry3d X_lying = Translation(1, 2, 0.25);
  X_lying.linear() = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitX()).toRotationMatrix();
  r = SignedDistance(Cylinder{0.3, 1.0}, X_lying, HalfSpace{}, I);
  EXPECT_NEAR(r.distance, -0.05, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WA, Vector3d(1, 2, -0.05), 1e-15);
  // Lying capsule: middle of the segment.
  r = SignedDistance(HalfSpace{}, I, Capsule{0.1, 1.0}, X_lying);
  EXPECT_NEAR(r.distance, 0.15, 1e-15);
  EXPECT_EIGEN_NEAR(r.p_WB, Vector3d(1, 2, 0.15), 1e-15);
  EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitZ(), 0.0);
}

TEST(SignedDistance, HalfSpaceWitnessUnderSymmetricTilts) {
  // Round-off tilts (below the 1e-12 tie tolerance) keep the witness at the face centroid;
  // real tilts move it to the lower edge, on either side: the documented jump.
  const Box box{Vector3d(1, 1, 1)};
  const Isometry3d I = Isometry3d::Identity();
  for (const double tilt : {1e-15, -1e-15, 1e-9, -1e-9}) {
    Isometry3d X = Translation(0, 0, 0.6);
    X.linear() = Eigen::AngleAxisd(tilt, Vector3d::UnitX()).toRotationMatrix();
    const SignedDistanceResult r = SignedDistance(box, X, HalfSpace{}, I);
    EXPECT_NEAR(r.distance, Reference(box, X, HalfSpace{}, I), 1e-15);
    if (std::abs(tilt) < 1e-12) {
      EXPECT_EIGEN_NEAR(r.p_WA.head<2>(), Eigen::Vector2d::Zero(), 1e-15);
    } else {
      EXPECT_NEAR(std::abs(r.p_WA.y()), 0.5, 1e-9);
      EXPECT_NEAR(r.p_WA.x(), 0.0, 1e-15);
    }
  }
}

TEST(SignedDistance, NearlyParallelCapsules) {
  const Capsule capsule{0.1, 1.0};
  const Isometry3d I = Isometry3d::Identity();
  for (const double angle : {1e-3, 1e-5, 1e-7, 3e-8, 1e-8, 1e-10, 1e-14, 1e-17, 0.0}) {
    SCOPED_TRACE(angle);
    // Offset so that the segments do not cross: exact at every angle.
    Isometry3d X = Translation(0.5, 0.0, 0.3);
    X.linear() = Eigen::AngleAxisd(angle, Vector3d::UnitY()).toRotationMatrix();
    SignedDistanceResult r = SignedDistance(capsule, I, capsule, X);
    ASSERT_TRUE(AllFinite(r));
    EXPECT_NEAR(r.distance, Reference(capsule, I, capsule, X), kExactTol);
    ExpectConsistent(capsule, I, capsule, X, r, kExactTol);
    // Witness: middle of the overlap z in [-0.2, 0.5] while parallel up to round-off.
    if (angle < 1e-12) {
      EXPECT_NEAR(r.p_WA.z(), 0.15, 1e-12);
    }
    // Crossing at the middle: documented error bound 1e-16 × size / angle, capped at 1e-8.
    X.translation() = Vector3d(0.0, 0.05, 0.0);
    r = SignedDistance(capsule, I, capsule, X);
    ASSERT_TRUE(AllFinite(r));
    EXPECT_NEAR(r.distance, Reference(capsule, I, capsule, X),
                angle > 0 ? std::min(1e-8, std::max(kExactTol, 1e-16 / angle)) : kExactTol);
  }
}

TEST(SignedDistance, FclPairsNearContactStayFinite) {
  const Isometry3d I = Isometry3d::Identity();
  const Box box{Vector3d(1, 1, 1)};
  const Capsule capsule{0.1, 0.5};
  for (const double gap : {1e-3, 1e-9, 1e-13, 0.0, -1e-13, -1e-9, -1e-3}) {
    SCOPED_TRACE(gap);
    // Capsule lying on the box's top face, and standing on it.
    Isometry3d X_lying = Translation(0.1, 0.0, 0.6 + gap);
    X_lying.linear() = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitX()).toRotationMatrix();
    for (const Isometry3d& X : {X_lying, Translation(0.1, 0.2, 0.85 + gap)}) {
      const SignedDistanceResult r = SignedDistance(box, I, capsule, X);
      ASSERT_TRUE(AllFinite(r));
      EXPECT_NEAR(r.distance, gap, 2e-6);
      EXPECT_NEAR(r.normal_W.norm(), 1.0, 1e-14);
      if (std::abs(gap) >= 1e-3) {
        EXPECT_EIGEN_NEAR(r.normal_W, Vector3d::UnitZ(), 1e-5);
      }
    }
  }
}

TEST(SignedDistance, TinyAndHugeShapesKeepRelativeAccuracy) {
  for (const double scale : {1e-6, 1e-3, 1.0, 1e3, 1e6}) {
    SCOPED_TRACE(scale);
    test::Random rng(808);
    for (int k = 0; k < 50; ++k) {
      for (const auto& pairs : {kAnalyticPairs, kFclPairs}) {
        for (const PairCase& pair : pairs) {
          Shape A = RandomShape(&rng, pair.a);
          Shape B = RandomShape(&rng, pair.b);
          auto scale_shape = [scale](Shape* s) {
            std::visit(
                [scale](auto& shape) {
                  using T = std::decay_t<decltype(shape)>;
                  if constexpr (std::is_same_v<T, Sphere>) {
                    shape.radius *= scale;
                  } else if constexpr (std::is_same_v<T, Capsule> || std::is_same_v<T, Cylinder>) {
                    shape.radius *= scale;
                    shape.length *= scale;
                  } else if constexpr (std::is_same_v<T, Box>) {
                    shape.size *= scale;
                  }
                },
                *s);
          };
          scale_shape(&A);
          scale_shape(&B);
          Isometry3d X_WA = RandomPose(&rng, 0.6);
          Isometry3d X_WB = RandomPose(&rng, 0.6);
          X_WA.translation() *= scale;
          X_WB.translation() *= scale;
          const SignedDistanceResult r = SignedDistance(A, X_WA, B, X_WB);
          ASSERT_TRUE(AllFinite(r)) << pair.name;
          EXPECT_NEAR(r.normal_W.norm(), 1.0, 1e-14);
          if (r.exact) {
            EXPECT_NEAR(r.distance, Reference(A, X_WA, B, X_WB), kExactTol * scale) << pair.name;
          } else {
            // Scale invariance of the FCL path: the same answer as at unit scale, scaled.
            EXPECT_NEAR(PointSdf(A, X_WA, r.p_WA), 0.0, 1e-5 * scale) << pair.name;
            EXPECT_NEAR(PointSdf(B, X_WB, r.p_WB), 0.0, 1e-5 * scale) << pair.name;
          }
        }
      }
    }
  }
}

TEST(SignedDistance, AnalyticPairsAllocateNothing) {
  if (!test::AllocationCountingAvailable()) GTEST_SKIP() << "malloc counting unavailable";
  for (const PairCase& pair : kAnalyticPairs) {
    test::Random rng(1001 + pair.a * 7 + pair.b);
    std::vector<Shape> A, B;
    std::vector<Isometry3d> X_WA, X_WB;
    for (int k = 0; k < 50; ++k) {
      A.push_back(RandomShape(&rng, pair.a));
      B.push_back(RandomShape(&rng, pair.b));
      X_WA.push_back(RandomPose(&rng, 0.6));
      X_WB.push_back(RandomPose(&rng, 0.6));
    }
    double sum = 0;
    test::ScopedAllocationCounter counter;
    for (int k = 0; k < 50; ++k) {
      sum += SignedDistance(A[k], X_WA[k], B[k], X_WB[k]).distance;
      sum += SignedDistance(B[k], X_WB[k], A[k], X_WA[k]).distance;
    }
    EXPECT_EQ(counter.count(), 0) << pair.name;
    EXPECT_TRUE(std::isfinite(sum));
  }
  // The FCL path does allocate (its shapes): this also shows the counter counts.
  const Isometry3d I = Isometry3d::Identity();
  test::ScopedAllocationCounter counter;
  const double phi =
      SignedDistance(Capsule{0.1, 0.2}, I, Box{Vector3d::Ones()}, Translation(2, 0, 0)).distance;
  EXPECT_GT(counter.count(), 0);
  EXPECT_NEAR(phi, 2 - 0.5 - 0.1, 1e-9);
}

TEST(SignedDistance, SignedDistanceIsExactTable) {
  const std::vector<Shape> shapes = {Sphere{1}, Capsule{1, 1}, Cylinder{1, 1},
                                     Box{Vector3d::Ones()}, HalfSpace{}};
  // Rows/columns: sphere, capsule, cylinder, box, half-space.
  const bool expected[5][5] = {{true, true, true, true, true},
                               {true, true, false, false, true},
                               {true, false, false, false, true},
                               {true, false, false, false, true},
                               {true, true, true, true, false}};
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      EXPECT_EQ(SignedDistanceIsExact(shapes[i], shapes[j]), expected[i][j])
          << ShapeName(shapes[i]) << "-" << ShapeName(shapes[j]);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Errors.

TEST(SignedDistance, InvalidArgumentsNameTheArgument) {
  const Isometry3d I = Isometry3d::Identity();
  EXPECT_THAT([&] { SignedDistance(HalfSpace{}, I, HalfSpace{}, I); },
              ThrowsMessage<InvalidArgument>(
                  HasSubstr("idto::SignedDistance: (A, B) is (half_space, half_space)")));
  EXPECT_THAT([&] { SignedDistance(Sphere{-1}, I, Sphere{1}, I); },
              ThrowsMessage<InvalidArgument>(HasSubstr("A.radius is -1; expected a finite "
                                                       "positive length")));
  EXPECT_THAT(
      [&] {
        SignedDistance(Sphere{1}, I, Capsule{0.1, -2}, I);
      },
      ThrowsMessage<InvalidArgument>(HasSubstr("B.length is -2")));
  EXPECT_THAT(
      [&] {
        SignedDistance(Sphere{1}, I, Cylinder{0.1, 0.0}, I);
      },
      ThrowsMessage<InvalidArgument>(HasSubstr("B.length is 0")));
  EXPECT_THAT([&] { SignedDistance(Box{Vector3d(1, 0, 1)}, I, HalfSpace{}, I); },
              ThrowsMessage<InvalidArgument>(HasSubstr("A.size(1) is 0")));
  EXPECT_THAT(
      [&] { SignedDistance(Sphere{std::numeric_limits<double>::quiet_NaN()}, I, HalfSpace{}, I); },
      ThrowsMessage<InvalidArgument>(HasSubstr("A.radius is nan")));
  Isometry3d bad = I;
  bad.translation().y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT([&] { SignedDistance(Sphere{1}, I, Sphere{1}, bad); },
              ThrowsMessage<InvalidArgument>(HasSubstr("X_WB(1, 3) is nan")));
  bad = I;
  bad.linear()(0, 0) = 2.0;
  EXPECT_THAT([&] { SignedDistance(Sphere{1}, bad, Sphere{1}, I); },
              ThrowsMessage<InvalidArgument>(HasSubstr("X_WA is not a rigid transform")));
  bad = I;
  bad.linear()(2, 2) = -1.0;  // a reflection
  EXPECT_THAT([&] { SignedDistance(Sphere{1}, bad, Sphere{1}, I); },
              ThrowsMessage<InvalidArgument>(HasSubstr("det R = -1")));
  EXPECT_THAT(
      [&] { SignedDistanceFcl(Sphere{1}, I, HalfSpace{}, I); },
      ThrowsMessage<InvalidArgument>(HasSubstr("idto::SignedDistanceFcl: B is half_space")));
}

// ---------------------------------------------------------------------------------------------
// Inscribed spheres.

TEST(InscribedSpheres, DefaultIsNineSpheresInsideThePapersCube) {
  const Box cube{Vector3d::Constant(0.15)};
  const std::vector<InscribedSphere> spheres = InscribedSpheres(cube);
  ASSERT_EQ(spheres.size(), 9u);
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_DOUBLE_EQ(spheres[i].sphere.radius, 0.0375);
    EXPECT_EIGEN_NEAR(spheres[i].X_BoxSphere.translation().cwiseAbs(), Vector3d::Constant(0.0375),
                      1e-17);
  }
  EXPECT_EIGEN_NEAR(spheres[0].X_BoxSphere.translation(), Vector3d::Constant(-0.0375), 1e-17);
  EXPECT_EIGEN_NEAR(spheres[1].X_BoxSphere.translation(), Vector3d(0.0375, -0.0375, -0.0375),
                    1e-17);
  EXPECT_DOUBLE_EQ(spheres[8].sphere.radius, 0.075);
  EXPECT_EIGEN_NEAR(spheres[8].X_BoxSphere.translation(), Vector3d::Zero(), 0.0);
}

TEST(InscribedSpheres, SpheresAreInsideAndTouchTheFaces) {
  const Box box{Vector3d(0.4, 0.2, 0.3)};
  for (const int n : {2, 3, 4}) {
    InscribedSpheresOptions options;
    options.num_per_axis = n;
    options.radius_fraction = 0.2;
    const auto spheres = InscribedSpheres(box, options);
    EXPECT_EQ(spheres.size(),
              static_cast<std::size_t>(n * n * n - (n - 2) * (n - 2) * (n - 2) + 1));
    // Each sphere is inside: the box's SDF at its centre is at most −radius.
    for (const auto& s : spheres) {
      EXPECT_LE(PointSdf(box, Isometry3d::Identity(), s.X_BoxSphere.translation()),
                -s.sphere.radius + 1e-15);
    }
    // Resting on any face, the spheres touch the plane exactly where the box does, and never
    // go below it when the box is tilted.
    test::Random rng(909);
    for (int k = 0; k < 50; ++k) {
      const Isometry3d X_WBox = RandomPose(&rng, 0.5);
      const double box_distance =
          SignedDistance(box, X_WBox, HalfSpace{}, Isometry3d::Identity()).distance;
      double spheres_distance = std::numeric_limits<double>::infinity();
      for (const auto& s : spheres) {
        spheres_distance = std::min(
            spheres_distance,
            SignedDistance(s.sphere, X_WBox * s.X_BoxSphere, HalfSpace{}, Isometry3d::Identity())
                .distance);
      }
      EXPECT_GE(spheres_distance, box_distance - 1e-15);
    }
    const double flat =
        SignedDistance(box, Translation(0, 0, 0.1), HalfSpace{}, Isometry3d::Identity()).distance;
    double flat_spheres = std::numeric_limits<double>::infinity();
    for (const auto& s : spheres) {
      flat_spheres =
          std::min(flat_spheres, SignedDistance(s.sphere, Translation(0, 0, 0.1) * s.X_BoxSphere,
                                                HalfSpace{}, Isometry3d::Identity())
                                     .distance);
    }
    EXPECT_NEAR(flat_spheres, flat, 1e-15);
  }
}

TEST(InscribedSpheres, InvalidOptionsThrow) {
  InscribedSpheresOptions options;
  options.num_per_axis = 1;
  EXPECT_THAT([&] { InscribedSpheres(Box{Vector3d::Ones()}, options); },
              ThrowsMessage<InvalidArgument>(HasSubstr("options.num_per_axis is 1")));
  options = {};
  options.radius_fraction = 0.6;
  EXPECT_THAT([&] { InscribedSpheres(Box{Vector3d::Ones()}, options); },
              ThrowsMessage<InvalidArgument>(HasSubstr("options.radius_fraction is 0.6")));
  EXPECT_THAT(
      [&] { InscribedSpheres(Box{Vector3d(1, -1, 1)}); },
      ThrowsMessage<InvalidArgument>(HasSubstr("idto::InscribedSpheres: box.size(1) is -1")));
}

}  // namespace
}  // namespace idto
