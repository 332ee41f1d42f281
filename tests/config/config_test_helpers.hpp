#pragma once

// Shared by the tests of tests/config/: a small valid configuration and loaders of YAML text.

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "idto/config/config.hpp"

namespace idto::test {

inline std::string FixturePath(const std::string& name) {
  return std::string(IDTO_TEST_DATA_DIR) + "/config/" + name;
}

inline const std::vector<std::string> kShareDirs = {IDTO_SOURCE_DIR};

/// A small valid configuration (the acrobot, nq = nv = 2); tests replace one piece of it.
inline const std::string kBase = R"(name: base
scene:
  models:
    - urdf: acrobot.urdf
problem:
  time_step: 0.05
  horizon: 1.0
  q_init: [0, 0]
  weights:
    Qq: {default: 0.1, elbow: 0.2}
    R: 0.01
solver:
  max_iterations: 10
)";

/// kBase with `from` replaced by `to` (which must occur).
inline std::string With(const std::string& from, const std::string& to) {
  std::string text = kBase;
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

/// Loads `text` as the file "test.yaml" of the fixture folder.
inline ExampleConfig LoadText(const std::string& text) {
  return LoadExampleConfigString(text, "test.yaml", FixturePath(""), kShareDirs);
}

/// A callable that loads `text`, for EXPECT_THAT(..., ThrowsMessage<FileError>(...)).
inline auto Loading(const std::string& text) {
  return [text]() { LoadText(text); };
}

}  // namespace idto::test
