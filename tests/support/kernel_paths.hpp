#pragma once

/// @file
/// Runs a test on both paths of the dense block kernels (src/math/block_kernels.hpp): the
/// baseline Eigen expressions and the AVX2/FMA kernels. The AVX2 instance is skipped, with the
/// reason, on a CPU without AVX2 and FMA.

#include <string>

#include <gtest/gtest.h>

#include "math/block_kernels.hpp"

namespace idto::test {

enum class KernelPath { kPortable, kAvx2 };

class KernelPathTest : public ::testing::TestWithParam<KernelPath> {
 protected:
  void SetUp() override {
    was_enabled_ = internal::UseAvx2Kernels();
    if (GetParam() == KernelPath::kAvx2 && !internal::Avx2KernelsAvailable()) {
      GTEST_SKIP() << "this CPU has no AVX2 and FMA: only the portable kernels exist here";
    }
    internal::SetAvx2KernelsEnabledForTesting(GetParam() == KernelPath::kAvx2);
  }
  void TearDown() override { internal::SetAvx2KernelsEnabledForTesting(was_enabled_); }

 private:
  bool was_enabled_{false};
};

inline std::string KernelPathName(const ::testing::TestParamInfo<KernelPath>& info) {
  return info.param == KernelPath::kAvx2 ? "Avx2" : "Portable";
}

}  // namespace idto::test

/// Instantiates a KernelPathTest suite for both paths.
#define IDTO_INSTANTIATE_KERNEL_PATHS(suite)                                                   \
  INSTANTIATE_TEST_SUITE_P(                                                                    \
      Kernels, suite,                                                                          \
      ::testing::Values(::idto::test::KernelPath::kPortable, ::idto::test::KernelPath::kAvx2), \
      ::idto::test::KernelPathName)
