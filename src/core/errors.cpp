#include "idto/core/errors.hpp"

#include <iomanip>
#include <limits>
#include <utility>

namespace idto {

FileError::FileError(std::string file, std::string element, const std::string& what)
    : std::runtime_error(what), file_(std::move(file)), element_(std::move(element)) {}

std::string FormatValue(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  std::ostringstream out;
  out << std::setprecision(std::numeric_limits<double>::max_digits10 - 2) << value;
  return out.str();
}

void ThrowInvalidArgument(std::string_view where, std::string_view argument, std::string_view found,
                          std::string_view expected) {
  std::string message;
  message.append(where).append(": ").append(argument).append(" is ").append(found);
  message.append("; expected ").append(expected);
  throw InvalidArgument(message);
}

void ThrowFileError(std::string_view file, std::string_view element, std::string_view problem) {
  std::string message;
  message.append(file);
  if (!element.empty()) message.append(": ").append(element);
  message.append(": ").append(problem);
  throw FileError(std::string(file), std::string(element), message);
}

void CheckSize(std::string_view where, std::string_view argument, Eigen::Index found,
               Eigen::Index expected, std::string_view expected_name) {
  if (found == expected) return;
  std::string found_text = "of size " + std::to_string(found);
  std::string expected_text = "size " + std::to_string(expected);
  if (!expected_name.empty()) expected_text.append(" (").append(expected_name).append(")");
  ThrowInvalidArgument(where, argument, found_text, expected_text);
}

void CheckFinite(std::string_view where, std::string_view argument, double value) {
  if (!std::isfinite(value)) {
    ThrowInvalidArgument(where, argument, FormatValue(value), "a finite number");
  }
}

void CheckPositive(std::string_view where, std::string_view argument, double value) {
  if (!(std::isfinite(value) && value > 0.0)) {
    ThrowInvalidArgument(where, argument, FormatValue(value), "a finite positive number");
  }
}

void CheckNonNegative(std::string_view where, std::string_view argument, double value) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    ThrowInvalidArgument(where, argument, FormatValue(value), "a finite non-negative number");
  }
}

}  // namespace idto
