// The long fixed-seed mutation fuzz of the shipped URDF files (label "heavy").

#include <gtest/gtest.h>

#include "parsers/urdf_fuzz.hpp"

namespace idto {
namespace {

TEST(UrdfFuzzHeavy, LongRunEndsCleanly) {
  const int loaded = testing_urdf_fuzz::RunUrdfFuzz(12000u, 12000);
  EXPECT_GT(loaded, 0);
}

}  // namespace
}  // namespace idto
