// The long fixed-seed mutation fuzz of the shipped example configurations (label "heavy").

#include <gtest/gtest.h>

#include <iostream>

#include "config/yaml_fuzz.hpp"

namespace idto {
namespace {

TEST(YamlFuzzHeavy, LongRunEndsCleanly) {
  const int loaded = testing_yaml_fuzz::RunYamlFuzz(3000u, 3000);
  std::cout << loaded
            << " of 3000 mutants loaded (each solved one iteration when steps x nq <= 4000); the "
               "others were refused "
               "with a FileError naming the mutant\n";
  EXPECT_GT(loaded, 0);
}

}  // namespace
}  // namespace idto
