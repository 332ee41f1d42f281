#pragma once

/// @file
/// Exception types and argument checks (design.md §7).
///
/// Bad input throws: `idto::InvalidArgument` (a `std::invalid_argument`) for sizes, NaN/Inf,
/// negative weights, non-positive time steps and invalid options; `idto::FileError` (a
/// `std::runtime_error`) for missing or malformed files. Every message names the function (or
/// file), the argument (or element/key), the value found and what was expected.

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include <Eigen/Core>

namespace idto {

/// A caller passed an invalid argument (size, value, option).
class InvalidArgument : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A file could not be read or is malformed. `file()` and `element()` name where.
class FileError : public std::runtime_error {
 public:
  FileError(std::string file, std::string element, const std::string& what);
  const std::string& file() const { return file_; }
  const std::string& element() const { return element_; }

 private:
  std::string file_;
  std::string element_;
};

/// Throws InvalidArgument with the message "`where`: `argument` is `found`; expected `expected`".
[[noreturn]] void ThrowInvalidArgument(std::string_view where, std::string_view argument,
                                       std::string_view found, std::string_view expected);

/// Throws FileError with the message "`file`: `element`: `problem`".
[[noreturn]] void ThrowFileError(std::string_view file, std::string_view element,
                                 std::string_view problem);

/// Formats a double for messages (full precision, "nan"/"inf" spelled out).
std::string FormatValue(double value);

/// Checks that a vector or matrix argument has `expected` rows (and, for matrices, cols).
void CheckSize(std::string_view where, std::string_view argument, Eigen::Index found,
               Eigen::Index expected, std::string_view expected_name = {});

/// Checks that `value` is finite.
void CheckFinite(std::string_view where, std::string_view argument, double value);

/// Checks that `value` is finite and strictly positive.
void CheckPositive(std::string_view where, std::string_view argument, double value);

/// Checks that `value` is finite and non-negative.
void CheckNonNegative(std::string_view where, std::string_view argument, double value);

/// Checks that every entry of `x` is finite; the message names the first bad index and value.
template <typename Derived>
void CheckFinite(std::string_view where, std::string_view argument,
                 const Eigen::DenseBase<Derived>& x) {
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      const double value = static_cast<double>(x(i, j));
      if (!std::isfinite(value)) {
        std::ostringstream name;
        name << argument << "(" << i;
        if (x.cols() > 1) name << ", " << j;
        name << ")";
        ThrowInvalidArgument(where, name.str(), FormatValue(value), "a finite number");
      }
    }
  }
}

/// Checks that every entry of `x` is finite and non-negative.
template <typename Derived>
void CheckNonNegative(std::string_view where, std::string_view argument,
                      const Eigen::DenseBase<Derived>& x) {
  CheckFinite(where, argument, x);
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      const double value = static_cast<double>(x(i, j));
      if (value < 0.0) {
        std::ostringstream name;
        name << argument << "(" << i;
        if (x.cols() > 1) name << ", " << j;
        name << ")";
        ThrowInvalidArgument(where, name.str(), FormatValue(value), "a non-negative number");
      }
    }
  }
}

}  // namespace idto
