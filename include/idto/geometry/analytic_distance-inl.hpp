#pragma once

/// @file
/// Definitions of the Scalar-templated analytic signed-distance pairs (include to instantiate
/// them with a scalar other than double). Each pair computes (A, B) with A of the lower variant
/// index of idto::Shape and the normal from A to B; AnalyticSignedDistance swaps and flips.

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>
#include <variant>

#include "idto/geometry/analytic_distance.hpp"

namespace idto {
namespace internal {

// Below this squared length a direction is treated as undefined (its square root would lose
// all relative accuracy in the subnormal range).
constexpr double kMinSquaredNorm = 1e-290;
// Relative size of a height difference below which a deepest segment/edge/face of a shape
// against a half-space is treated as parallel to the plane (see signed_distance.hpp).
constexpr double kTieTolerance = 1e-12;
// sin² of the angle below which two capsule axes are treated as (nearly) parallel: below it the
// closed form for crossing lines loses accuracy as eps/sin²θ and the overlap rule is used.
constexpr double kParallelSin2 = 1e-15;

template <typename S>
inline S Clamp(const S& x, const S& lo, const S& hi) {
  if (x < lo) return lo;
  if (x > hi) return hi;
  return x;
}

template <typename S>
inline SignedDistanceResultTpl<S> FlipResult(SignedDistanceResultTpl<S> r) {
  r.normal_W = -r.normal_W;
  std::swap(r.p_WA, r.p_WB);
  return r;
}

// Two spheres (also the core of every pair of "swept spheres": sphere, capsule).
template <typename S>
SignedDistanceResultTpl<S> SpherePair(const Vector3<S>& c_A, double r_A, const Vector3<S>& c_B,
                                      double r_B, const Vector3<S>& fallback_normal_W) {
  using std::sqrt;
  SignedDistanceResultTpl<S> result;
  const Vector3<S> d = c_B - c_A;
  const S d2 = d.squaredNorm();
  if (d2 > kMinSquaredNorm) {
    const S len = sqrt(d2);
    result.normal_W = d / len;
    result.distance = len - S(r_A + r_B);
  } else {
    // Coincident centres: any normal gives the same (most negative) distance.
    result.normal_W = fallback_normal_W;
    result.distance = d.dot(fallback_normal_W) - S(r_A + r_B);
  }
  result.p_WA = c_A + S(r_A) * result.normal_W;
  result.p_WB = c_B - S(r_B) * result.normal_W;
  return result;
}

// A point p_WA (on A's surface, deepest towards the plane) against a half-space B: the normal
// is minus the plane's outward normal, the witness on B is the projection of p_WA.
template <typename S>
SignedDistanceResultTpl<S> PointHalfSpace(const Vector3<S>& p_WA,
                                          const RigidTransformTpl<S>& X_WB) {
  const Vector3<S> n_B = X_WB.R.col(2);
  const S height = n_B.dot(p_WA - X_WB.p);
  SignedDistanceResultTpl<S> result;
  result.distance = height;
  result.normal_W = -n_B;
  result.p_WA = p_WA;
  result.p_WB = p_WA - height * n_B;
  return result;
}

template <typename S>
SignedDistanceResultTpl<S> SphereHalfSpace(const Sphere& sphere, const RigidTransformTpl<S>& X_WA,
                                           const RigidTransformTpl<S>& X_WB) {
  return PointHalfSpace<S>(X_WA.p - S(sphere.radius) * X_WB.R.col(2), X_WB);
}

// Closest point to p on the segment of a capsule (z axis of X_WC, half length h).
template <typename S>
Vector3<S> ClosestOnSegment(const Vector3<S>& p, const RigidTransformTpl<S>& X_WC, double h) {
  const Vector3<S> u = X_WC.R.col(2);
  const S t = Clamp<S>(u.dot(p - X_WC.p), S(-h), S(h));
  return X_WC.p + t * u;
}

template <typename S>
SignedDistanceResultTpl<S> SphereCapsule(const Sphere& sphere, const RigidTransformTpl<S>& X_WA,
                                         const Capsule& capsule, const RigidTransformTpl<S>& X_WB) {
  const Vector3<S> s = ClosestOnSegment<S>(X_WA.p, X_WB, 0.5 * capsule.length);
  return SpherePair<S>(X_WA.p, sphere.radius, s, capsule.radius, -X_WB.R.col(0));
}

// Sphere against a convex solid B described by the point q_B of B's surface nearest to the
// sphere centre and B's outward normal n_B there (both in B's frame), and the signed distance
// phi_c of the centre to B.
template <typename S>
SignedDistanceResultTpl<S> SphereAgainstSurface(const Vector3<S>& c_W, double radius,
                                                const RigidTransformTpl<S>& X_WB,
                                                const Vector3<S>& q_B, const Vector3<S>& n_B,
                                                const S& phi_c) {
  SignedDistanceResultTpl<S> result;
  const Vector3<S> n_out_W = X_WB.R * n_B;
  result.normal_W = -n_out_W;
  result.distance = phi_c - S(radius);
  result.p_WA = c_W - S(radius) * n_out_W;
  result.p_WB = X_WB * q_B;
  return result;
}

template <typename S>
SignedDistanceResultTpl<S> SphereCylinder(const Sphere& sphere, const RigidTransformTpl<S>& X_WA,
                                          const Cylinder& cylinder,
                                          const RigidTransformTpl<S>& X_WB) {
  using std::abs;
  using std::sqrt;
  const Vector3<S>& c_W = X_WA.p;
  const Vector3<S> c = X_WB.R.transpose() * (c_W - X_WB.p);
  const double R = cylinder.radius;
  const double h = 0.5 * cylinder.length;
  const S rho2 = c.x() * c.x() + c.y() * c.y();
  const S rho = sqrt(rho2);
  if (rho > R || abs(c.z()) > h) {
    // Outside: the nearest point clamps the radial and axial coordinates.
    Vector3<S> q = c;
    if (rho > R) q.template head<2>() *= S(R) / rho;
    q.z() = Clamp<S>(c.z(), S(-h), S(h));
    const Vector3<S> v = c - q;
    const S len2 = v.squaredNorm();
    // (R/ρ may round to 1 just outside the side: then treat the centre as on the surface.)
    if (len2 > kMinSquaredNorm) {
      const S len = sqrt(len2);
      return SphereAgainstSurface<S>(c_W, sphere.radius, X_WB, q, v / len, len);
    }
  }
  // Inside (or on the surface): the nearest of side, +z cap, −z cap, in that order on ties.
  const S depth_side = S(R) - rho;
  const S depth_top = S(h) - c.z();
  const S depth_bottom = S(h) + c.z();
  if (depth_side <= depth_top && depth_side <= depth_bottom) {
    Vector3<S> n = Vector3<S>::UnitX();
    if (rho2 > kMinSquaredNorm) n = Vector3<S>(c.x() / rho, c.y() / rho, S(0.0));
    const Vector3<S> q(S(R) * n.x(), S(R) * n.y(), c.z());
    return SphereAgainstSurface<S>(c_W, sphere.radius, X_WB, q, n, -depth_side);
  }
  if (depth_top <= depth_bottom) {
    return SphereAgainstSurface<S>(c_W, sphere.radius, X_WB, Vector3<S>(c.x(), c.y(), S(h)),
                                   Vector3<S>::UnitZ(), -depth_top);
  }
  return SphereAgainstSurface<S>(c_W, sphere.radius, X_WB, Vector3<S>(c.x(), c.y(), S(-h)),
                                 -Vector3<S>::UnitZ(), -depth_bottom);
}

template <typename S>
SignedDistanceResultTpl<S> SphereBox(const Sphere& sphere, const RigidTransformTpl<S>& X_WA,
                                     const Box& box, const RigidTransformTpl<S>& X_WB) {
  using std::abs;
  using std::sqrt;
  const Vector3<S>& c_W = X_WA.p;
  const Vector3<S> c = X_WB.R.transpose() * (c_W - X_WB.p);
  const Eigen::Vector3d e = 0.5 * box.size;
  bool outside = false;
  for (int i = 0; i < 3; ++i) outside = outside || abs(c(i)) > e(i);
  if (outside) {
    Vector3<S> q;
    for (int i = 0; i < 3; ++i) q(i) = Clamp<S>(c(i), S(-e(i)), S(e(i)));
    const Vector3<S> v = c - q;
    const S len2 = v.squaredNorm();
    if (len2 > kMinSquaredNorm) {
      const S len = sqrt(len2);
      return SphereAgainstSurface<S>(c_W, sphere.radius, X_WB, q, v / len, len);
    }
  }
  // Inside (or on the surface): nearest face; ties to the lower axis, then to the + face.
  int axis = 0;
  S depth = S(e.x()) - abs(c.x());
  for (int i = 1; i < 3; ++i) {
    const S depth_i = S(e(i)) - abs(c(i));
    if (depth_i < depth) {
      depth = depth_i;
      axis = i;
    }
  }
  const double sign = c(axis) >= 0.0 ? 1.0 : -1.0;
  Vector3<S> q = c;
  q(axis) = S(sign * e(axis));
  const Vector3<S> n = (sign * Eigen::Vector3d::Unit(axis)).template cast<S>();
  return SphereAgainstSurface<S>(c_W, sphere.radius, X_WB, q, n, -depth);
}

template <typename S>
SignedDistanceResultTpl<S> CapsuleHalfSpace(const Capsule& capsule,
                                            const RigidTransformTpl<S>& X_WA,
                                            const RigidTransformTpl<S>& X_WB) {
  using std::abs;
  const Vector3<S> n_B = X_WB.R.col(2);
  const Vector3<S> u = X_WA.R.col(2);
  const double h = 0.5 * capsule.length;
  // Height of the +h end minus the centre's; the deeper end is the one going down.
  const S dh = S(h) * u.dot(n_B);
  const double tie = kTieTolerance * (capsule.length + capsule.radius);
  Vector3<S> p = X_WA.p;
  if (2.0 * abs(dh) > tie) p -= S(dh > 0.0 ? h : -h) * u;
  return PointHalfSpace<S>(p - S(capsule.radius) * n_B, X_WB);
}

template <typename S>
SignedDistanceResultTpl<S> CylinderHalfSpace(const Cylinder& cylinder,
                                             const RigidTransformTpl<S>& X_WA,
                                             const RigidTransformTpl<S>& X_WB) {
  using std::abs;
  using std::sqrt;
  const Vector3<S> n_B = X_WB.R.col(2);
  const Vector3<S> u = X_WA.R.col(2);
  const double h = 0.5 * cylinder.length;
  const double R = cylinder.radius;
  const double tie = kTieTolerance * std::max(cylinder.length, 2.0 * R);
  Vector3<S> p = X_WA.p;
  // Axial part: the lower cap (or the mid-plane when the axis lies in the plane's direction).
  const S un = u.dot(n_B);
  if (2.0 * h * abs(un) > tie) p -= S(un > 0.0 ? h : -h) * u;
  // Radial part: the lowest rim point (or the cap's centre when the cap is parallel).
  const Vector3<S> down_perp = -(n_B - un * u);
  const S s2 = down_perp.squaredNorm();
  if (s2 > kMinSquaredNorm && 2.0 * R * sqrt(s2) > tie) p += (S(R) / sqrt(s2)) * down_perp;
  return PointHalfSpace<S>(p, X_WB);
}

template <typename S>
SignedDistanceResultTpl<S> BoxHalfSpace(const Box& box, const RigidTransformTpl<S>& X_WA,
                                        const RigidTransformTpl<S>& X_WB) {
  using std::abs;
  const Vector3<S> n_B = X_WB.R.col(2);
  const Vector3<S> s = X_WA.R.transpose() * n_B;  // plane normal in the box frame
  const Eigen::Vector3d e = 0.5 * box.size;
  const double tie = kTieTolerance * box.size.maxCoeff();
  // The deepest vertex has coordinates −sign(s_i) e_i; a zero sign (within the tie) keeps the
  // centroid of the deepest edge or face.
  Vector3<S> offset = Vector3<S>::Zero();
  for (int i = 0; i < 3; ++i) {
    if (2.0 * e(i) * abs(s(i)) > tie) offset(i) = S(s(i) > 0.0 ? -e(i) : e(i));
  }
  return PointHalfSpace<S>(X_WA * offset, X_WB);
}

// Closest points between segments P(s) = p_A + s u_A, |s| <= h_A and Q(t) = p_B + t u_B,
// |t| <= h_B (u unit). Returns (s, t).
template <typename S>
std::pair<S, S> ClosestSegmentParameters(const Vector3<S>& p_A, const Vector3<S>& u_A, double h_A,
                                         const Vector3<S>& p_B, const Vector3<S>& u_B, double h_B) {
  using std::sqrt;
  const Vector3<S> r = p_A - p_B;
  const S b = u_A.dot(u_B);
  const S c = u_A.dot(r);
  const S f = u_B.dot(r);
  // 1 − b² computed from the cross product keeps its relative accuracy at small angles.
  const S denom = u_A.cross(u_B).squaredNorm();
  S s(0.0);
  if (denom > kParallelSin2) {
    // Minimizer of |r + s u_A − t u_B|² over the lines, then Ericson's clamping sequence.
    s = Clamp<S>((b * f - c) / denom, S(-h_A), S(h_A));
  } else {
    // (Nearly) parallel: B's extent projected on A's axis is [lo, hi]. Over its overlap with
    // [−h_A, h_A] the gap P(s) − Q(b s + f) = w0 + s v is affine, v = u_A − b u_B being tiny.
    const S s0 = -c - b * h_B;
    const S s1 = -c + b * h_B;
    const S lo = s0 < s1 ? (s0 > -h_A ? s0 : S(-h_A)) : (s1 > -h_A ? s1 : S(-h_A));
    const S hi = s0 > s1 ? (s0 < h_A ? s0 : S(h_A)) : (s1 < h_A ? s1 : S(h_A));
    if (lo <= hi) {
      const Vector3<S> v = u_A - b * u_B;
      const Vector3<S> w0 = r - f * u_B;
      const S v2 = v.squaredNorm();
      // The gap changes by at most |v|(hi − lo) over the overlap: when that is round-off, the
      // axes are parallel and the middle of the overlap is the (deterministic) witness.
      const S tie = kTieTolerance * (hi - lo + w0.norm());
      if (v2 * (hi - lo) * (hi - lo) <= tie * tie) {
        s = 0.5 * (lo + hi);
      } else {
        s = Clamp<S>(-w0.dot(v) / v2, lo, hi);
      }
    } else {
      s = S(hi < -h_A ? -h_A : h_A);  // no overlap: A's end nearer to B
    }
  }
  S t = b * s + f;
  if (t < -h_B || t > h_B) {
    t = Clamp<S>(t, S(-h_B), S(h_B));
    s = Clamp<S>(b * t - c, S(-h_A), S(h_A));
  }
  return {s, t};
}

template <typename S>
SignedDistanceResultTpl<S> CapsuleCapsule(const Capsule& capsule_A,
                                          const RigidTransformTpl<S>& X_WA,
                                          const Capsule& capsule_B,
                                          const RigidTransformTpl<S>& X_WB) {
  using std::sqrt;
  const Vector3<S> u_A = X_WA.R.col(2);
  const Vector3<S> u_B = X_WB.R.col(2);
  const auto [s, t] = ClosestSegmentParameters<S>(X_WA.p, u_A, 0.5 * capsule_A.length, X_WB.p, u_B,
                                                  0.5 * capsule_B.length);
  const Vector3<S> s_A = X_WA.p + s * u_A;
  const Vector3<S> s_B = X_WB.p + t * u_B;
  // Only used when the segments intersect.
  Vector3<S> fallback = X_WA.R.col(0);
  const Vector3<S> w = u_A.cross(u_B);
  const S w2 = w.squaredNorm();
  if (w2 > kParallelSin2) fallback = w / sqrt(w2);
  return SpherePair<S>(s_A, capsule_A.radius, s_B, capsule_B.radius, fallback);
}

// Variant indices, in the order of idto::Shape.
constexpr std::size_t kSphereIndex = 0;
constexpr std::size_t kCapsuleIndex = 1;
constexpr std::size_t kCylinderIndex = 2;
constexpr std::size_t kBoxIndex = 3;
constexpr std::size_t kHalfSpaceIndex = 4;
static_assert(std::is_same_v<std::variant_alternative_t<kSphereIndex, Shape>, Sphere>);
static_assert(std::is_same_v<std::variant_alternative_t<kCapsuleIndex, Shape>, Capsule>);
static_assert(std::is_same_v<std::variant_alternative_t<kCylinderIndex, Shape>, Cylinder>);
static_assert(std::is_same_v<std::variant_alternative_t<kBoxIndex, Shape>, Box>);
static_assert(std::is_same_v<std::variant_alternative_t<kHalfSpaceIndex, Shape>, HalfSpace>);

// A has the lower (or equal) variant index. False when the pair is not analytic.
template <typename S>
bool CanonicalAnalytic(const Shape& A, const RigidTransformTpl<S>& X_WA, const Shape& B,
                       const RigidTransformTpl<S>& X_WB, SignedDistanceResultTpl<S>* out) {
  const std::size_t a = A.index();
  const std::size_t b = B.index();
  if (a == kSphereIndex) {
    const auto& sphere = std::get<Sphere>(A);
    switch (b) {
      case kSphereIndex:
        *out = SpherePair<S>(X_WA.p, sphere.radius, X_WB.p, std::get<Sphere>(B).radius,
                             Vector3<S>::UnitZ());
        return true;
      case kCapsuleIndex:
        *out = SphereCapsule<S>(sphere, X_WA, std::get<Capsule>(B), X_WB);
        return true;
      case kCylinderIndex:
        *out = SphereCylinder<S>(sphere, X_WA, std::get<Cylinder>(B), X_WB);
        return true;
      case kBoxIndex:
        *out = SphereBox<S>(sphere, X_WA, std::get<Box>(B), X_WB);
        return true;
      default:
        *out = SphereHalfSpace<S>(sphere, X_WA, X_WB);
        return true;
    }
  }
  if (b == kHalfSpaceIndex) {
    switch (a) {
      case kCapsuleIndex:
        *out = CapsuleHalfSpace<S>(std::get<Capsule>(A), X_WA, X_WB);
        return true;
      case kCylinderIndex:
        *out = CylinderHalfSpace<S>(std::get<Cylinder>(A), X_WA, X_WB);
        return true;
      case kBoxIndex:
        *out = BoxHalfSpace<S>(std::get<Box>(A), X_WA, X_WB);
        return true;
      default:
        return false;  // two half-spaces
    }
  }
  if (a == kCapsuleIndex && b == kCapsuleIndex) {
    *out = CapsuleCapsule<S>(std::get<Capsule>(A), X_WA, std::get<Capsule>(B), X_WB);
    return true;
  }
  return false;
}

}  // namespace internal

template <typename Scalar>
bool AnalyticSignedDistance(const Shape& A, const RigidTransformTpl<Scalar>& X_WA, const Shape& B,
                            const RigidTransformTpl<Scalar>& X_WB,
                            SignedDistanceResultTpl<Scalar>* result) {
  if (A.index() <= B.index()) return internal::CanonicalAnalytic(A, X_WA, B, X_WB, result);
  if (!internal::CanonicalAnalytic(B, X_WB, A, X_WA, result)) return false;
  *result = internal::FlipResult(*result);
  return true;
}

}  // namespace idto
