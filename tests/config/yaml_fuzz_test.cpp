// A short fixed-seed mutation fuzz of the shipped example configurations (the long run is in
// heavy/).

#include <gtest/gtest.h>

#include <iostream>

#include "config/yaml_fuzz.hpp"

namespace idto {
namespace {

TEST(YamlFuzz, ShortRunEndsCleanly) {
  const int loaded = testing_yaml_fuzz::RunYamlFuzz(20261124u, 240);
  // Some mutants are harmless (a comment edited, a value within range): both outcomes occur.
  std::cout << loaded
            << " of 240 mutants loaded (each solved one iteration when steps x nq <= 4000); the "
               "others were refused "
               "with a FileError naming the mutant\n";
  EXPECT_GT(loaded, 0);
  EXPECT_LT(loaded, 240);
}

}  // namespace
}  // namespace idto
