#include "idto/geometry/signed_distance.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include <fcl/fcl.h>

#include "idto/core/errors.hpp"

namespace idto {
namespace {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;

constexpr std::string_view kSignedDistance = "idto::SignedDistance";
constexpr std::string_view kSignedDistanceFcl = "idto::SignedDistanceFcl";

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

// Below this squared length a direction is treated as undefined (its square root would lose
// all relative accuracy in the subnormal range).
constexpr double kMinSquaredNorm = 1e-290;
// Relative size of a height difference below which a deepest segment/edge/face of a shape
// against a half-space is treated as parallel to the plane (see the header).
constexpr double kTieTolerance = 1e-12;
// sin² of the angle below which two capsule axes are treated as (nearly) parallel: below it the
// closed form for crossing lines loses accuracy as eps/sin²θ and the overlap rule is used.
constexpr double kParallelSin2 = 1e-15;
// Shapes are handed to FCL scaled to unit size; these tolerances are therefore relative.
// GJK distance converges to ~1e-11 with 1e-12. FCL's libccd EPA (used in penetration) aborts
// the process on a failed assertion for capsules at tolerances of 1e-8 and below (measured on
// FCL 0.7.0), so it stays at FCL's default of 1e-6.
constexpr double kFclDistanceTolerance = 1e-12;
constexpr double kFclPenetrationTolerance = 1e-6;
// Witness points closer than this (relative) do not define a normal.
constexpr double kFclMinWitnessGap = 1e-12;

SignedDistanceResult Flip(SignedDistanceResult r) {
  r.normal_W = -r.normal_W;
  std::swap(r.p_WA, r.p_WB);
  return r;
}

// ---------------------------------------------------------------------------------------------
// Argument checks. Names are built only on failure so that a valid call allocates nothing.

void CheckDimension(std::string_view where, std::string_view shape_arg, const char* field,
                    double value, bool allow_zero) {
  const bool ok = std::isfinite(value) && (allow_zero ? value >= 0.0 : value > 0.0);
  if (ok) return;
  std::string name(shape_arg);
  name.append(".").append(field);
  ThrowInvalidArgument(
      where, name, FormatValue(value),
      allow_zero ? "a finite non-negative length [m]" : "a finite positive length [m]");
}

void CheckShape(std::string_view where, std::string_view arg, const Shape& shape) {
  switch (shape.index()) {
    case kSphereIndex:
      CheckDimension(where, arg, "radius", std::get<Sphere>(shape).radius, false);
      break;
    case kCapsuleIndex: {
      const auto& capsule = std::get<Capsule>(shape);
      CheckDimension(where, arg, "radius", capsule.radius, false);
      CheckDimension(where, arg, "length", capsule.length, true);
      break;
    }
    case kCylinderIndex: {
      const auto& cylinder = std::get<Cylinder>(shape);
      CheckDimension(where, arg, "radius", cylinder.radius, false);
      CheckDimension(where, arg, "length", cylinder.length, false);
      break;
    }
    case kBoxIndex: {
      const Vector3d& size = std::get<Box>(shape).size;
      CheckDimension(where, arg, "size(0)", size.x(), false);
      CheckDimension(where, arg, "size(1)", size.y(), false);
      CheckDimension(where, arg, "size(2)", size.z(), false);
      break;
    }
    default:
      break;  // a half-space has no parameters
  }
}

void CheckPose(std::string_view where, std::string_view arg, const Isometry3d& X) {
  // Fast path (a third of a sphere–sphere query): finite translation, unit orthogonal first two
  // columns and a third column equal to their cross product (right-handed). NaN fails `<=`.
  const auto R = X.linear();
  const Vector3d c0 = R.col(0);
  const Vector3d c1 = R.col(1);
  const double error =
      std::max({std::abs(c0.squaredNorm() - 1.0), std::abs(c1.squaredNorm() - 1.0),
                std::abs(c0.dot(c1)), (c0.cross(c1) - R.col(2)).cwiseAbs().maxCoeff()});
  if (error <= 1e-6 && X.translation().allFinite()) return;
  CheckFinite(where, arg, X.matrix().topRows<3>());
  const Matrix3d R_full = R;
  const double orthonormality_error =
      (R_full.transpose() * R_full - Matrix3d::Identity()).cwiseAbs().maxCoeff();
  ThrowInvalidArgument(
      where, arg,
      "not a rigid transform (max |R^T R - I| = " + FormatValue(orthonormality_error) +
          ", det R = " + FormatValue(R_full.determinant()) + ")",
      "a linear part that is a rotation matrix");
}

void CheckArguments(std::string_view where, const Shape& A, const Isometry3d& X_WA, const Shape& B,
                    const Isometry3d& X_WB) {
  CheckShape(where, "A", A);
  CheckShape(where, "B", B);
  CheckPose(where, "X_WA", X_WA);
  CheckPose(where, "X_WB", X_WB);
}

// ---------------------------------------------------------------------------------------------
// Analytic pairs. Each computes (A, B) with A of lower variant index, normal from A to B.

// Two spheres (also the core of every pair of "swept spheres": sphere, capsule).
SignedDistanceResult SpherePair(const Vector3d& c_A, double r_A, const Vector3d& c_B, double r_B,
                                const Vector3d& fallback_normal_W) {
  SignedDistanceResult result;
  const Vector3d d = c_B - c_A;
  const double d2 = d.squaredNorm();
  if (d2 > kMinSquaredNorm) {
    const double len = std::sqrt(d2);
    result.normal_W = d / len;
    result.distance = len - r_A - r_B;
  } else {
    // Coincident centres: any normal gives the same (most negative) distance.
    result.normal_W = fallback_normal_W;
    result.distance = d.dot(fallback_normal_W) - r_A - r_B;
  }
  result.p_WA = c_A + r_A * result.normal_W;
  result.p_WB = c_B - r_B * result.normal_W;
  return result;
}

// A point p_WA (on A's surface, deepest towards the plane) against a half-space B: the normal
// is minus the plane's outward normal, the witness on B is the projection of p_WA.
SignedDistanceResult PointHalfSpace(const Vector3d& p_WA, const Isometry3d& X_WB) {
  const Vector3d n_B = X_WB.linear().col(2);
  const double height = n_B.dot(p_WA - X_WB.translation());
  SignedDistanceResult result;
  result.distance = height;
  result.normal_W = -n_B;
  result.p_WA = p_WA;
  result.p_WB = p_WA - height * n_B;
  return result;
}

SignedDistanceResult SphereHalfSpace(const Sphere& sphere, const Isometry3d& X_WA,
                                     const Isometry3d& X_WB) {
  const Vector3d n_B = X_WB.linear().col(2);
  return PointHalfSpace(X_WA.translation() - sphere.radius * n_B, X_WB);
}

// Closest point to p on the segment of a capsule (z axis of X_WC, half length h).
Vector3d ClosestOnSegment(const Vector3d& p, const Isometry3d& X_WC, double h) {
  const Vector3d u = X_WC.linear().col(2);
  const double t = std::clamp(u.dot(p - X_WC.translation()), -h, h);
  return X_WC.translation() + t * u;
}

SignedDistanceResult SphereCapsule(const Sphere& sphere, const Isometry3d& X_WA,
                                   const Capsule& capsule, const Isometry3d& X_WB) {
  const Vector3d s = ClosestOnSegment(X_WA.translation(), X_WB, 0.5 * capsule.length);
  return SpherePair(X_WA.translation(), sphere.radius, s, capsule.radius, -X_WB.linear().col(0));
}

// Sphere against a convex solid B described by the point q_B of B's surface nearest to the
// sphere centre and B's outward normal n_B there (both in B's frame), and the signed distance
// phi_c of the centre to B.
SignedDistanceResult SphereAgainstSurface(const Vector3d& c_W, double radius,
                                          const Isometry3d& X_WB, const Vector3d& q_B,
                                          const Vector3d& n_B, double phi_c) {
  SignedDistanceResult result;
  const Vector3d n_out_W = X_WB.linear() * n_B;
  result.normal_W = -n_out_W;
  result.distance = phi_c - radius;
  result.p_WA = c_W - radius * n_out_W;
  result.p_WB = X_WB * q_B;
  return result;
}

SignedDistanceResult SphereCylinder(const Sphere& sphere, const Isometry3d& X_WA,
                                    const Cylinder& cylinder, const Isometry3d& X_WB) {
  const Vector3d c_W = X_WA.translation();
  const Vector3d c = X_WB.inverse(Eigen::Isometry) * c_W;
  const double R = cylinder.radius;
  const double h = 0.5 * cylinder.length;
  const double rho2 = c.x() * c.x() + c.y() * c.y();
  const double rho = std::sqrt(rho2);
  if (rho > R || std::abs(c.z()) > h) {
    // Outside: the nearest point clamps the radial and axial coordinates.
    Vector3d q = c;
    if (rho > R) q.head<2>() *= R / rho;
    q.z() = std::clamp(c.z(), -h, h);
    const Vector3d v = c - q;
    const double len2 = v.squaredNorm();
    // (R/ρ may round to 1 just outside the side: then treat the centre as on the surface.)
    if (len2 > kMinSquaredNorm) {
      const double len = std::sqrt(len2);
      return SphereAgainstSurface(c_W, sphere.radius, X_WB, q, v / len, len);
    }
  }
  // Inside (or on the surface): the nearest of side, +z cap, −z cap, in that order on ties.
  const double depth_side = R - rho;
  const double depth_top = h - c.z();
  const double depth_bottom = h + c.z();
  if (depth_side <= depth_top && depth_side <= depth_bottom) {
    Vector3d n = Vector3d::UnitX();
    if (rho2 > kMinSquaredNorm) n = Vector3d(c.x() / rho, c.y() / rho, 0.0);
    const Vector3d q(R * n.x(), R * n.y(), c.z());
    return SphereAgainstSurface(c_W, sphere.radius, X_WB, q, n, -depth_side);
  }
  if (depth_top <= depth_bottom) {
    return SphereAgainstSurface(c_W, sphere.radius, X_WB, Vector3d(c.x(), c.y(), h),
                                Vector3d::UnitZ(), -depth_top);
  }
  return SphereAgainstSurface(c_W, sphere.radius, X_WB, Vector3d(c.x(), c.y(), -h),
                              -Vector3d::UnitZ(), -depth_bottom);
}

SignedDistanceResult SphereBox(const Sphere& sphere, const Isometry3d& X_WA, const Box& box,
                               const Isometry3d& X_WB) {
  const Vector3d c_W = X_WA.translation();
  const Vector3d c = X_WB.inverse(Eigen::Isometry) * c_W;
  const Vector3d e = 0.5 * box.size;
  if ((c.cwiseAbs().array() > e.array()).any()) {
    const Vector3d q = c.cwiseMax(-e).cwiseMin(e);
    const Vector3d v = c - q;
    const double len2 = v.squaredNorm();
    if (len2 > kMinSquaredNorm) {
      const double len = std::sqrt(len2);
      return SphereAgainstSurface(c_W, sphere.radius, X_WB, q, v / len, len);
    }
  }
  // Inside (or on the surface): nearest face; ties to the lower axis, then to the + face.
  int axis = 0;
  double depth = e.x() - std::abs(c.x());
  for (int i = 1; i < 3; ++i) {
    const double depth_i = e(i) - std::abs(c(i));
    if (depth_i < depth) {
      depth = depth_i;
      axis = i;
    }
  }
  const double sign = c(axis) >= 0.0 ? 1.0 : -1.0;
  Vector3d q = c;
  q(axis) = sign * e(axis);
  return SphereAgainstSurface(c_W, sphere.radius, X_WB, q, sign * Vector3d::Unit(axis), -depth);
}

SignedDistanceResult CapsuleHalfSpace(const Capsule& capsule, const Isometry3d& X_WA,
                                      const Isometry3d& X_WB) {
  const Vector3d n_B = X_WB.linear().col(2);
  const Vector3d u = X_WA.linear().col(2);
  const double h = 0.5 * capsule.length;
  // Height of the +h end minus the centre's; the deeper end is the one going down.
  const double dh = h * u.dot(n_B);
  const double tie = kTieTolerance * (capsule.length + capsule.radius);
  Vector3d p = X_WA.translation();
  if (2.0 * std::abs(dh) > tie) p -= (dh > 0.0 ? h : -h) * u;
  return PointHalfSpace(p - capsule.radius * n_B, X_WB);
}

SignedDistanceResult CylinderHalfSpace(const Cylinder& cylinder, const Isometry3d& X_WA,
                                       const Isometry3d& X_WB) {
  const Vector3d n_B = X_WB.linear().col(2);
  const Vector3d u = X_WA.linear().col(2);
  const double h = 0.5 * cylinder.length;
  const double R = cylinder.radius;
  const double tie = kTieTolerance * std::max(cylinder.length, 2.0 * R);
  Vector3d p = X_WA.translation();
  // Axial part: the lower cap (or the mid-plane when the axis lies in the plane's direction).
  const double un = u.dot(n_B);
  if (2.0 * h * std::abs(un) > tie) p -= (un > 0.0 ? h : -h) * u;
  // Radial part: the lowest rim point (or the cap's centre when the cap is parallel).
  const Vector3d down_perp = -(n_B - un * u);
  const double s2 = down_perp.squaredNorm();
  if (s2 > kMinSquaredNorm && 2.0 * R * std::sqrt(s2) > tie) p += (R / std::sqrt(s2)) * down_perp;
  return PointHalfSpace(p, X_WB);
}

SignedDistanceResult BoxHalfSpace(const Box& box, const Isometry3d& X_WA, const Isometry3d& X_WB) {
  const Vector3d n_B = X_WB.linear().col(2);
  const Vector3d s = X_WA.linear().transpose() * n_B;  // plane normal in the box frame
  const Vector3d e = 0.5 * box.size;
  const double tie = kTieTolerance * box.size.maxCoeff();
  // The deepest vertex has coordinates −sign(s_i) e_i; a zero sign (within the tie) keeps the
  // centroid of the deepest edge or face.
  Vector3d offset = Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    if (2.0 * e(i) * std::abs(s(i)) > tie) offset(i) = s(i) > 0.0 ? -e(i) : e(i);
  }
  return PointHalfSpace(X_WA * offset, X_WB);
}

// Closest points between segments P(s) = p_A + s u_A, |s| <= h_A and Q(t) = p_B + t u_B,
// |t| <= h_B (u unit). Returns (s, t).
std::pair<double, double> ClosestSegmentParameters(const Vector3d& p_A, const Vector3d& u_A,
                                                   double h_A, const Vector3d& p_B,
                                                   const Vector3d& u_B, double h_B) {
  const Vector3d r = p_A - p_B;
  const double b = u_A.dot(u_B);
  const double c = u_A.dot(r);
  const double f = u_B.dot(r);
  // 1 − b² computed from the cross product keeps its relative accuracy at small angles.
  const double denom = u_A.cross(u_B).squaredNorm();
  double s = 0.0;
  if (denom > kParallelSin2) {
    // Minimizer of |r + s u_A − t u_B|² over the lines, then Ericson's clamping sequence.
    s = std::clamp((b * f - c) / denom, -h_A, h_A);
  } else {
    // (Nearly) parallel: B's extent projected on A's axis is [lo, hi]. Over its overlap with
    // [−h_A, h_A] the gap P(s) − Q(b s + f) = w0 + s v is affine, v = u_A − b u_B being tiny.
    const double s0 = -c - b * h_B;
    const double s1 = -c + b * h_B;
    const double lo = std::max(std::min(s0, s1), -h_A);
    const double hi = std::min(std::max(s0, s1), h_A);
    if (lo <= hi) {
      const Vector3d v = u_A - b * u_B;
      const Vector3d w0 = r - f * u_B;
      const double v2 = v.squaredNorm();
      // The gap changes by at most |v|(hi − lo) over the overlap: when that is round-off, the
      // axes are parallel and the middle of the overlap is the (deterministic) witness.
      const double tie = kTieTolerance * (hi - lo + w0.norm());
      if (v2 * (hi - lo) * (hi - lo) <= tie * tie) {
        s = 0.5 * (lo + hi);
      } else {
        s = std::clamp(-w0.dot(v) / v2, lo, hi);
      }
    } else {
      s = hi < -h_A ? -h_A : h_A;  // no overlap: A's end nearer to B
    }
  }
  double t = b * s + f;
  if (t < -h_B || t > h_B) {
    t = std::clamp(t, -h_B, h_B);
    s = std::clamp(b * t - c, -h_A, h_A);
  }
  return {s, t};
}

SignedDistanceResult CapsuleCapsule(const Capsule& capsule_A, const Isometry3d& X_WA,
                                    const Capsule& capsule_B, const Isometry3d& X_WB) {
  const Vector3d u_A = X_WA.linear().col(2);
  const Vector3d u_B = X_WB.linear().col(2);
  const auto [s, t] = ClosestSegmentParameters(X_WA.translation(), u_A, 0.5 * capsule_A.length,
                                               X_WB.translation(), u_B, 0.5 * capsule_B.length);
  const Vector3d s_A = X_WA.translation() + s * u_A;
  const Vector3d s_B = X_WB.translation() + t * u_B;
  // Only used when the segments intersect.
  Vector3d fallback = X_WA.linear().col(0);
  const Vector3d w = u_A.cross(u_B);
  const double w2 = w.squaredNorm();
  if (w2 > kParallelSin2) fallback = w / std::sqrt(w2);
  return SpherePair(s_A, capsule_A.radius, s_B, capsule_B.radius, fallback);
}

// ---------------------------------------------------------------------------------------------
// FCL (non-analytic pairs, and the oracle).

double CharacteristicSize(const Shape& shape) {
  switch (shape.index()) {
    case kSphereIndex:
      return 2.0 * std::get<Sphere>(shape).radius;
    case kCapsuleIndex: {
      const auto& capsule = std::get<Capsule>(shape);
      return capsule.length + 2.0 * capsule.radius;
    }
    case kCylinderIndex: {
      const auto& cylinder = std::get<Cylinder>(shape);
      return std::max(cylinder.length, 2.0 * cylinder.radius);
    }
    case kBoxIndex:
      return std::get<Box>(shape).size.maxCoeff();
    default:
      return 1.0;
  }
}

std::shared_ptr<fcl::CollisionGeometryd> MakeFclGeometry(const Shape& shape, double scale) {
  const double k = 1.0 / scale;
  switch (shape.index()) {
    case kSphereIndex:
      return std::make_shared<fcl::Sphered>(k * std::get<Sphere>(shape).radius);
    case kCapsuleIndex: {
      const auto& capsule = std::get<Capsule>(shape);
      return std::make_shared<fcl::Capsuled>(k * capsule.radius, k * capsule.length);
    }
    case kCylinderIndex: {
      const auto& cylinder = std::get<Cylinder>(shape);
      return std::make_shared<fcl::Cylinderd>(k * cylinder.radius, k * cylinder.length);
    }
    case kBoxIndex:
      return std::make_shared<fcl::Boxd>(k * std::get<Box>(shape).size);
    default:
      throw std::logic_error("idto: a half-space must never reach FCL");
  }
}

SignedDistanceResult FclSignedDistance(const Shape& A, const Isometry3d& X_WA, const Shape& B,
                                       const Isometry3d& X_WB) {
  // Scale to unit size and put A's origin at the origin: FCL's tolerances are absolute.
  const double scale = std::max(CharacteristicSize(A), CharacteristicSize(B));
  const auto geometry_A = MakeFclGeometry(A, scale);
  const auto geometry_B = MakeFclGeometry(B, scale);
  fcl::Transform3d tf_A = fcl::Transform3d::Identity();
  tf_A.linear() = X_WA.linear();
  fcl::Transform3d tf_B = fcl::Transform3d::Identity();
  tf_B.linear() = X_WB.linear();
  tf_B.translation() = (X_WB.translation() - X_WA.translation()) / scale;

  Vector3d p_A, p_B;  // witnesses in the scaled frame
  double sign = 1.0;
  bool have_witnesses = false;
  try {
    // Separated: GJK distance. FCL's own GJK is accurate on curved shapes; on box–box it is
    // not (errors of 1e-2 measured) while libccd's is exact there.
    const bool box_box = A.index() == kBoxIndex && B.index() == kBoxIndex;
    fcl::DistanceRequestd request(true, false, 0.0, 0.0, kFclDistanceTolerance,
                                  box_box ? fcl::GST_LIBCCD : fcl::GST_INDEP);
    fcl::DistanceResultd result;
    fcl::distance(geometry_A.get(), tf_A, geometry_B.get(), tf_B, request, result);
    if (result.min_distance > 0.0) {
      p_A = result.nearest_points[0];
      p_B = result.nearest_points[1];
      have_witnesses = (p_B - p_A).norm() > kFclMinWitnessGap;
    }
    if (!have_witnesses) {
      // Penetrating or touching: FCL's signed distance (libccd GJK + EPA).
      fcl::DistanceRequestd signed_request(true, true, 0.0, 0.0, kFclPenetrationTolerance,
                                           fcl::GST_LIBCCD);
      fcl::DistanceResultd signed_result;
      fcl::distance(geometry_A.get(), tf_A, geometry_B.get(), tf_B, signed_request, signed_result);
      p_A = signed_result.nearest_points[0];
      p_B = signed_result.nearest_points[1];
      sign = signed_result.min_distance < 0.0 ? -1.0 : 1.0;
      have_witnesses = (p_B - p_A).norm() > kFclMinWitnessGap;
    }
    SignedDistanceResult out;
    out.exact = false;
    if (have_witnesses) {
      const Vector3d gap = p_B - p_A;
      const double len = gap.norm();
      out.normal_W = sign * gap / len;
      out.distance = sign * len;
    } else {
      // Touching: the witnesses coincide and define no normal; take the contact normal of
      // FCL's collision query (libccd MPR), else the direction between the shape origins.
      fcl::CollisionRequestd collision_request(1, true);
      collision_request.gjk_solver_type = fcl::GST_LIBCCD;
      fcl::CollisionResultd collision_result;
      fcl::collide(geometry_A.get(), tf_A, geometry_B.get(), tf_B, collision_request,
                   collision_result);
      Vector3d n = tf_B.translation();
      if (collision_result.numContacts() > 0) n = collision_result.getContact(0).normal;
      const double n2 = n.squaredNorm();
      out.normal_W = n2 > kMinSquaredNorm ? Vector3d(n / std::sqrt(n2)) : Vector3d::UnitZ();
      out.distance = (p_B - p_A).dot(out.normal_W);
    }
    out.distance *= scale;
    out.p_WA = X_WA.translation() + scale * p_A;
    out.p_WB = X_WA.translation() + scale * p_B;
    return out;
  } catch (const std::exception& e) {
    throw std::runtime_error("idto::SignedDistance: FCL failed on the pair (" + ShapeName(A) +
                             ", " + ShapeName(B) + "): " + e.what());
  }
}

bool IsAnalyticCanonical(std::size_t a, std::size_t b) {
  if (a == kSphereIndex) return true;  // sphere with anything
  if (b == kHalfSpaceIndex) return a != kHalfSpaceIndex;
  return a == kCapsuleIndex && b == kCapsuleIndex;
}

// A has the lower (or equal) variant index.
SignedDistanceResult Canonical(const Shape& A, const Isometry3d& X_WA, const Shape& B,
                               const Isometry3d& X_WB) {
  const std::size_t a = A.index();
  const std::size_t b = B.index();
  if (a == kSphereIndex) {
    const auto& sphere = std::get<Sphere>(A);
    switch (b) {
      case kSphereIndex:
        return SpherePair(X_WA.translation(), sphere.radius, X_WB.translation(),
                          std::get<Sphere>(B).radius, Vector3d::UnitZ());
      case kCapsuleIndex:
        return SphereCapsule(sphere, X_WA, std::get<Capsule>(B), X_WB);
      case kCylinderIndex:
        return SphereCylinder(sphere, X_WA, std::get<Cylinder>(B), X_WB);
      case kBoxIndex:
        return SphereBox(sphere, X_WA, std::get<Box>(B), X_WB);
      default:
        return SphereHalfSpace(sphere, X_WA, X_WB);
    }
  }
  if (b == kHalfSpaceIndex) {
    switch (a) {
      case kCapsuleIndex:
        return CapsuleHalfSpace(std::get<Capsule>(A), X_WA, X_WB);
      case kCylinderIndex:
        return CylinderHalfSpace(std::get<Cylinder>(A), X_WA, X_WB);
      case kBoxIndex:
        return BoxHalfSpace(std::get<Box>(A), X_WA, X_WB);
      default:
        ThrowInvalidArgument(kSignedDistance, "(A, B)", "(half_space, half_space)",
                             "at most one half_space: the distance between two half-spaces is "
                             "not defined");
    }
  }
  if (a == kCapsuleIndex && b == kCapsuleIndex) {
    return CapsuleCapsule(std::get<Capsule>(A), X_WA, std::get<Capsule>(B), X_WB);
  }
  return FclSignedDistance(A, X_WA, B, X_WB);
}

}  // namespace

SignedDistanceResult SignedDistance(const Shape& A, const Isometry3d& X_WA, const Shape& B,
                                    const Isometry3d& X_WB) {
  CheckArguments(kSignedDistance, A, X_WA, B, X_WB);
  if (A.index() <= B.index()) return Canonical(A, X_WA, B, X_WB);
  return Flip(Canonical(B, X_WB, A, X_WA));
}

bool SignedDistanceIsExact(const Shape& A, const Shape& B) {
  const std::size_t a = std::min(A.index(), B.index());
  const std::size_t b = std::max(A.index(), B.index());
  return IsAnalyticCanonical(a, b);
}

SignedDistanceResult SignedDistanceFcl(const Shape& A, const Isometry3d& X_WA, const Shape& B,
                                       const Isometry3d& X_WB) {
  CheckArguments(kSignedDistanceFcl, A, X_WA, B, X_WB);
  if (A.index() == kHalfSpaceIndex || B.index() == kHalfSpaceIndex) {
    ThrowInvalidArgument(kSignedDistanceFcl, A.index() == kHalfSpaceIndex ? "A" : "B", "half_space",
                         "a sphere, capsule, cylinder or box (a half-space is never handed to "
                         "FCL: FCL 0.7 crashes on sphere-half-space distance)");
  }
  return FclSignedDistance(A, X_WA, B, X_WB);
}

std::vector<InscribedSphere> InscribedSpheres(const Box& box,
                                              const InscribedSpheresOptions& options) {
  constexpr std::string_view kWhere = "idto::InscribedSpheres";
  CheckShape(kWhere, "box", Shape(box));
  const int n = options.num_per_axis;
  if (n < 2 || n > 100) {
    ThrowInvalidArgument(kWhere, "options.num_per_axis", std::to_string(n),
                         "an integer from 2 to 100");
  }
  const double fraction = options.radius_fraction;
  if (!(fraction > 0.0 && fraction <= 0.5)) {
    ThrowInvalidArgument(kWhere, "options.radius_fraction", FormatValue(fraction),
                         "a number in (0, 0.5]");
  }
  const double smallest = box.size.minCoeff();
  const double radius = fraction * smallest;
  // Grid-sphere centres span [−(e − r), e − r] on each axis so the outermost ones touch the
  // faces.
  const Vector3d reach = 0.5 * box.size - Vector3d::Constant(radius);
  std::vector<InscribedSphere> spheres;
  spheres.reserve(n * n * n - (n - 2) * (n - 2) * (n - 2) + 1);
  auto coordinate = [&](int axis, int k) {
    return -reach(axis) + 2.0 * reach(axis) * static_cast<double>(k) / (n - 1);
  };
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const bool on_boundary =
            i == 0 || i == n - 1 || j == 0 || j == n - 1 || k == 0 || k == n - 1;
        if (!on_boundary) continue;
        InscribedSphere sphere;
        sphere.sphere.radius = radius;
        sphere.X_BoxSphere.translation() =
            Vector3d(coordinate(0, i), coordinate(1, j), coordinate(2, k));
        spheres.push_back(sphere);
      }
    }
  }
  if (options.center_sphere) {
    InscribedSphere sphere;
    sphere.sphere.radius = 0.5 * smallest;
    spheres.push_back(sphere);
  }
  return spheres;
}

}  // namespace idto
