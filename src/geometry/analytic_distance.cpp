#include "idto/geometry/analytic_distance.hpp"

#include <algorithm>

#include "idto/geometry/analytic_distance-inl.hpp"

namespace idto {

bool IsAnalyticPair(const Shape& A, const Shape& B) {
  const std::size_t a = std::min(A.index(), B.index());
  const std::size_t b = std::max(A.index(), B.index());
  if (a == internal::kSphereIndex) return true;  // sphere with anything
  if (b == internal::kHalfSpaceIndex) return a != internal::kHalfSpaceIndex;
  return a == internal::kCapsuleIndex && b == internal::kCapsuleIndex;
}

template bool AnalyticSignedDistance<double>(const Shape&, const RigidTransformTpl<double>&,
                                             const Shape&, const RigidTransformTpl<double>&,
                                             SignedDistanceResultTpl<double>*);

}  // namespace idto
