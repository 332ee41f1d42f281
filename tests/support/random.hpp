#pragma once

/// @file
/// Seeded random numbers so that every test run sees the same states.

#include <cstdint>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace idto::test {

/// A deterministic generator; each test constructs its own with a fixed seed.
class Random {
 public:
  explicit Random(std::uint32_t seed = 12345) : engine_(seed) {}

  double Uniform(double lo = -1.0, double hi = 1.0) {
    return std::uniform_real_distribution<double>(lo, hi)(engine_);
  }
  double Normal(double mean = 0.0, double stddev = 1.0) {
    return std::normal_distribution<double>(mean, stddev)(engine_);
  }
  Eigen::VectorXd Vector(Eigen::Index n, double lo = -1.0, double hi = 1.0) {
    Eigen::VectorXd x(n);
    for (Eigen::Index i = 0; i < n; ++i) x(i) = Uniform(lo, hi);
    return x;
  }
  Eigen::MatrixXd Matrix(Eigen::Index rows, Eigen::Index cols, double lo = -1.0, double hi = 1.0) {
    Eigen::MatrixXd x(rows, cols);
    for (Eigen::Index j = 0; j < cols; ++j)
      for (Eigen::Index i = 0; i < rows; ++i) x(i, j) = Uniform(lo, hi);
    return x;
  }
  /// A unit quaternion uniformly distributed on SO(3).
  Eigen::Quaterniond Quaternion() {
    Eigen::Vector4d c(Normal(), Normal(), Normal(), Normal());
    c.normalize();
    return Eigen::Quaterniond(c(0), c(1), c(2), c(3));
  }
  std::mt19937& engine() { return engine_; }

 private:
  std::mt19937 engine_;
};

}  // namespace idto::test
