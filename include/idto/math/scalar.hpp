#pragma once

/// @file
/// Scalar-generic helpers for the templated kernels (design.md §2 "Templated kernels"): Eigen
/// aliases on a Scalar, a non-deduced parameter wrapper and the cast of the Model's double
/// constants into the kernel's Scalar (a no-op returning a reference for double).

#include <type_traits>

#include <Eigen/Core>

/// Forces a small kernel helper inline where the compiler would call it: a call returns its
/// value through memory, and reading back 16 bytes written as two 8-byte stores stalls on store
/// forwarding (measured on the RNEA derivatives' forward pass).
#if defined(__GNUC__) || defined(__clang__)
#define IDTO_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define IDTO_ALWAYS_INLINE inline
#endif

namespace idto {

template <typename Scalar>
using Vector3 = Eigen::Matrix<Scalar, 3, 1>;
template <typename Scalar>
using Vector6 = Eigen::Matrix<Scalar, 6, 1>;
template <typename Scalar>
using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;
template <typename Scalar>
using Matrix6 = Eigen::Matrix<Scalar, 6, 6>;
template <typename Scalar>
using VectorX = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
template <typename Scalar>
using MatrixX = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

namespace internal {
template <typename T>
struct TypeIdentity {
  using type = T;
};
}  // namespace internal

/// T in a function parameter that does not take part in template argument deduction (the
/// kernels deduce Scalar from their DataTpl<Scalar>* argument only, so Eigen expressions and
/// vectors of any storage convert to the Eigen::Ref parameters).
template <typename T>
using NonDeduced = typename internal::TypeIdentity<T>::type;

/// Read-only reference to a vector of Scalar, as the kernels take q, v and a.
template <typename Scalar>
using ConstVectorRef = NonDeduced<Eigen::Ref<const VectorX<Scalar>>>;

/// x (a double constant: number, Eigen object or spatial type with cast<>()) in Scalar. For
/// Scalar = double it returns x itself by reference: no copy in the double kernels.
template <typename Scalar, typename T>
decltype(auto) CastTo(const T& x) {
  if constexpr (std::is_same_v<Scalar, double>) {
    return (x);
  } else if constexpr (std::is_arithmetic_v<T>) {
    return Scalar(x);
  } else {
    return x.template cast<Scalar>();
  }
}

}  // namespace idto
