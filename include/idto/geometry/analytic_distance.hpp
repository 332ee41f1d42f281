#pragma once

/// @file
/// The analytic signed-distance pairs of signed_distance.hpp as templates on the scalar type, so
/// that the same code gives the value (double) and exact derivatives (a dual-number or
/// automatic-differentiation scalar): the contact derivatives differentiate the pair geometry
/// through it, and the tests use Eigen's AutoDiffScalar on it as the oracle. Conventions, pair
/// support and every tie-break are those documented in signed_distance.hpp; SignedDistance (the
/// validated double entry point) calls this code for every analytic pair.
///
/// Derivatives. Wherever the answer is smooth (a unique deepest feature, the centres not
/// coincident, not on a tie of the documented tie-breaks) the derivative obtained through a
/// non-double Scalar is the exact derivative of (distance, normal_W, p_WA, p_WB). At a tie it
/// is the one-sided derivative of the branch the tie-break picks.

#include <Eigen/Core>

#include "idto/geometry/shape.hpp"
#include "idto/math/scalar.hpp"
#include "idto/math/spatial.hpp"

namespace idto {

/// Result of an analytic signed-distance query on Scalar; fields as SignedDistanceResult
/// (distance in m, normal_W unit from A to B, witnesses p_WA on A and p_WB on B, world frame).
template <typename Scalar>
struct SignedDistanceResultTpl {
  Scalar distance{0.0};
  Vector3<Scalar> normal_W{Vector3<Scalar>::UnitZ()};
  Vector3<Scalar> p_WA{Vector3<Scalar>::Zero()};
  Vector3<Scalar> p_WB{Vector3<Scalar>::Zero()};
};

/// True when the pair (A, B), in either order, has an analytic answer (SignedDistanceIsExact).
bool IsAnalyticPair(const Shape& A, const Shape& B);

/// The analytic signed distance between shape A at pose X_WA and shape B at pose X_WB (rotation
/// R and origin p of each shape frame in the world). Returns false, leaving *result unchanged,
/// when the pair is not analytic (see IsAnalyticPair). Does not validate its arguments (the
/// double entry point SignedDistance does). Allocation-free.
template <typename Scalar>
bool AnalyticSignedDistance(const Shape& A, const RigidTransformTpl<Scalar>& X_WA, const Shape& B,
                            const RigidTransformTpl<Scalar>& X_WB,
                            SignedDistanceResultTpl<Scalar>* result);

extern template bool AnalyticSignedDistance<double>(const Shape&, const RigidTransformTpl<double>&,
                                                    const Shape&, const RigidTransformTpl<double>&,
                                                    SignedDistanceResultTpl<double>*);

}  // namespace idto
