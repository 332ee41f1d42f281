// A short fixed-seed mutation fuzz of the shipped URDF files (the long run is in heavy/).

#include <gtest/gtest.h>

#include "parsers/urdf_fuzz.hpp"

namespace idto {
namespace {

TEST(UrdfFuzz, ShortRunEndsCleanly) {
  const int loaded = testing_urdf_fuzz::RunUrdfFuzz(20261123u, 600);
  // Some mutants are harmless (a changed value within range): the fuzzer reaches both outcomes.
  EXPECT_GT(loaded, 0);
  EXPECT_LT(loaded, 600);
}

}  // namespace
}  // namespace idto
