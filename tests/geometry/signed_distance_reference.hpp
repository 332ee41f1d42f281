// Independent references and helpers of the signed-distance tests (signed_distance_test.cpp and
// signed_distance_edge_cases_test.cpp): hand-derived formulas written differently from the
// library's code.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "idto/geometry/signed_distance.hpp"
#include "support/random.hpp"

namespace idto {
namespace sd_test {

using Eigen::Isometry3d;
using Eigen::Vector3d;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

inline constexpr double kExactTol = 1e-12;

// ---------------------------------------------------------------------------------------------
// Independent references (hand-derived; written differently from the library's code).

// Signed distance from a world point to a shape (negative inside).
inline double PointSdf(const Shape& shape, const Isometry3d& X_WS, const Vector3d& p_W) {
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
inline double PointSegmentDistance(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d ab = b - a;
  const double L2 = ab.squaredNorm();
  if (L2 == 0.0) return (p - a).norm();
  const double t = (p - a).dot(ab) / L2;
  if (t <= 0.0) return (p - a).norm();
  if (t >= 1.0) return (p - b).norm();
  return (p - a).cross(ab).norm() / std::sqrt(L2);
}

inline std::pair<Vector3d, Vector3d> Endpoints(const Capsule& c, const Isometry3d& X) {
  return {X * Vector3d(0, 0, -0.5 * c.length), X * Vector3d(0, 0, 0.5 * c.length)};
}

// Segment–segment distance: the minimum over the four endpoint–segment distances and, when the
// lines' common perpendicular meets both segments, the line–line distance.
inline double SegmentSegmentDistance(const Vector3d& a0, const Vector3d& a1, const Vector3d& b0,
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

inline double Height(const Isometry3d& X_WH, const Vector3d& p_W) {
  return X_WH.linear().col(2).dot(p_W - X_WH.translation());
}

// Exact reference for every analytic pair.
inline double Reference(const Shape& A, const Isometry3d& X_WA, const Shape& B,
                        const Isometry3d& X_WB) {
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
inline double PointBoxDistance(const Box& b, const Isometry3d& X_WB, const Vector3d& p_W,
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
inline double CapsuleBoxTruth(const Capsule& c, const Isometry3d& X_WA, const Box& b,
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

inline Isometry3d RandomPose(test::Random* rng, double range) {
  Isometry3d X = Isometry3d::Identity();
  X.linear() = rng->Quaternion().toRotationMatrix();
  X.translation() = rng->Vector(3, -range, range);
  return X;
}

inline Isometry3d Translation(double x, double y, double z) {
  Isometry3d X = Isometry3d::Identity();
  X.translation() = Vector3d(x, y, z);
  return X;
}

inline Shape RandomShape(test::Random* rng, std::size_t index) {
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

inline bool AllFinite(const SignedDistanceResult& r) {
  return std::isfinite(r.distance) && r.normal_W.allFinite() && r.p_WA.allFinite() &&
         r.p_WB.allFinite();
}

// Checks the invariants every answer satisfies: finite, unit normal, the identity
// (p_WB − p_WA)·n = φ, and witnesses on the surfaces (within `surface_tol`).
inline void ExpectConsistent(const Shape& A, const Isometry3d& X_WA, const Shape& B,
                             const Isometry3d& X_WB, const SignedDistanceResult& r,
                             double surface_tol) {
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

inline const std::vector<PairCase> kAnalyticPairs = {
    {0, 0, "sphere-sphere"},   {0, 4, "sphere-half_space"},   {0, 1, "sphere-capsule"},
    {0, 2, "sphere-cylinder"}, {0, 3, "sphere-box"},          {1, 4, "capsule-half_space"},
    {1, 1, "capsule-capsule"}, {2, 4, "cylinder-half_space"}, {3, 4, "box-half_space"},
};

inline const std::vector<PairCase> kFclPairs = {
    {1, 2, "capsule-cylinder"}, {1, 3, "capsule-box"}, {2, 2, "cylinder-cylinder"},
    {2, 3, "cylinder-box"},     {3, 3, "box-box"},
};

}  // namespace sd_test
}  // namespace idto
