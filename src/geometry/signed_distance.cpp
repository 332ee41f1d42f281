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
#include "idto/geometry/analytic_distance-inl.hpp"

namespace idto {
namespace {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;

constexpr std::string_view kSignedDistance = "idto::SignedDistance";
constexpr std::string_view kSignedDistanceFcl = "idto::SignedDistanceFcl";

// Variant indices, in the order of idto::Shape (analytic_distance-inl.hpp).
using internal::kBoxIndex;
using internal::kCapsuleIndex;
using internal::kCylinderIndex;
using internal::kHalfSpaceIndex;
using internal::kSphereIndex;

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
      out.normal_W =
          n2 > internal::kMinSquaredNorm ? Vector3d(n / std::sqrt(n2)) : Vector3d::UnitZ();
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

RigidTransformTpl<double> ToRigidTransform(const Isometry3d& X) {
  return {X.linear(), X.translation()};
}

// A has the lower (or equal) variant index.
SignedDistanceResult Canonical(const Shape& A, const Isometry3d& X_WA, const Shape& B,
                               const Isometry3d& X_WB) {
  if (A.index() == kHalfSpaceIndex && B.index() == kHalfSpaceIndex) {
    ThrowInvalidArgument(kSignedDistance, "(A, B)", "(half_space, half_space)",
                         "at most one half_space: the distance between two half-spaces is "
                         "not defined");
  }
  SignedDistanceResultTpl<double> r;
  if (internal::CanonicalAnalytic<double>(A, ToRigidTransform(X_WA), B, ToRigidTransform(X_WB),
                                          &r)) {
    SignedDistanceResult result;
    result.distance = r.distance;
    result.normal_W = r.normal_W;
    result.p_WA = r.p_WA;
    result.p_WB = r.p_WB;
    return result;
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

bool SignedDistanceIsExact(const Shape& A, const Shape& B) { return IsAnalyticPair(A, B); }

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
