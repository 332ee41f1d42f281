#pragma once

// Helpers shared by the example tests (tests/examples): an example's configuration loaded from
// the source tree, a trajectory at rest, and a task metric by name.

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "idto/config/config.hpp"
#include "idto/solver/trajectory_optimizer.hpp"
#include "run/metrics.hpp"

namespace idto::test {

/// Where examples/NAME/NAME.yaml is looked for: the source tree only, so the tests read the
/// files this checkout ships.
inline const std::vector<std::string> kShareDirs = {IDTO_SOURCE_DIR};

/// examples/NAME/NAME.yaml of the source tree, loaded (throws as LoadExampleConfig does).
inline ExampleConfig LoadExample(const std::string& name) {
  return LoadExampleConfig(FindExampleConfig(name, kShareDirs), kShareDirs);
}

/// The spinner example with the reference implementation's model (models/spinner_reference.urdf,
/// the paper's Table 4 in docs/tradeoffs.md) in place of the example's.
inline ExampleConfig LoadReferenceSpinner() {
  const std::string path = FindExampleConfig("spinner", kShareDirs);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const std::string from = "urdf: spinner.urdf";
  const size_t at = yaml.find(from);
  if (at == std::string::npos) ADD_FAILURE() << path << " has no '" << from << "'";
  if (at != std::string::npos) yaml.replace(at, from.size(), "urdf: spinner_reference.urdf");
  return LoadExampleConfigString(yaml, path, std::string(IDTO_SOURCE_DIR) + "/examples/spinner",
                                 kShareDirs);
}

/// q_init at every one of the N + 1 knots, zero velocities and generalized forces.
inline Trajectory RestingTrajectory(const ExampleConfig& config) {
  const int N = config.problem.num_steps;
  Trajectory t;
  t.q.assign(N + 1, config.problem.q_init);
  t.v.assign(N + 1, Eigen::VectorXd::Zero(config.model.nv()));
  t.tau.assign(N + 1, Eigen::VectorXd::Zero(config.model.nv()));
  return t;
}

/// The first value of the task metric `name` in `result`; a test failure (and NaN) when absent.
inline double MetricValue(const examples::TaskResult& result, const std::string& name) {
  for (const examples::Metric& m : result.metrics) {
    if (m.name == name) return m.values.at(0);
  }
  ADD_FAILURE() << "no metric " << name;
  return std::nan("");
}

}  // namespace idto::test
