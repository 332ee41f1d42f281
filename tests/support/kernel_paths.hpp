#pragma once

/// @file
/// Runs a test on both paths of the dense block kernels (src/math/block_kernels.hpp): the
/// baseline Eigen expressions and the AVX2/FMA kernels. The AVX2 instance is skipped, with the
/// reason, on a CPU without AVX2 and FMA.

#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "math/block_kernels.hpp"

namespace idto::test {

enum class KernelPath { kPortable, kAvx2 };

inline std::string KernelPathName(KernelPath path) {
  return path == KernelPath::kAvx2 ? "Avx2" : "Portable";
}

inline std::string KernelPathParamName(const ::testing::TestParamInfo<KernelPath>& info) {
  return KernelPathName(info.param);
}

/// The paths this CPU can run: the portable one, and the AVX2 one where it has AVX2 and FMA.
inline std::vector<KernelPath> AvailableKernelPaths() {
  std::vector<KernelPath> paths = {KernelPath::kPortable};
  if (internal::Avx2KernelsAvailable()) paths.push_back(KernelPath::kAvx2);
  return paths;
}

/// Selects a path for its lifetime, then restores the previous one.
class ScopedKernelPath {
 public:
  explicit ScopedKernelPath(KernelPath path) : was_enabled_(internal::UseAvx2Kernels()) {
    internal::SetAvx2KernelsEnabledForTesting(path == KernelPath::kAvx2);
  }
  ~ScopedKernelPath() { internal::SetAvx2KernelsEnabledForTesting(was_enabled_); }
  ScopedKernelPath(const ScopedKernelPath&) = delete;
  ScopedKernelPath& operator=(const ScopedKernelPath&) = delete;

 private:
  bool was_enabled_;
};

/// A test parameterized by the path: runs on it, and is skipped (with the reason) for the AVX2
/// path on a CPU without AVX2 and FMA.
class KernelPathTest : public ::testing::TestWithParam<KernelPath> {
 protected:
  void SetUp() override {
    if (GetParam() == KernelPath::kAvx2 && !internal::Avx2KernelsAvailable()) {
      GTEST_SKIP() << "this CPU has no AVX2 and FMA: only the portable kernels exist here";
    }
    path_.emplace(GetParam());
  }
  void TearDown() override { path_.reset(); }

 private:
  std::optional<ScopedKernelPath> path_;
};

}  // namespace idto::test

/// Instantiates a KernelPathTest suite for both paths.
#define IDTO_INSTANTIATE_KERNEL_PATHS(suite)                                                   \
  INSTANTIATE_TEST_SUITE_P(                                                                    \
      Kernels, suite,                                                                          \
      ::testing::Values(::idto::test::KernelPath::kPortable, ::idto::test::KernelPath::kAvx2), \
      ::idto::test::KernelPathParamName)
