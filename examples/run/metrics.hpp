#pragma once

/// @file
/// Task measures of the examples run by idto-run: physical quantities that say whether the
/// optimized trajectory does what the example asks, and a boolean `task_success` with its
/// criterion. Keyed by the example's name (ExampleConfig::name); add a new example's measure to
/// the registry in metrics.cpp.

#include <string>
#include <vector>

#include "idto/config/config.hpp"
#include "idto/solver/trajectory_optimizer.hpp"

namespace idto::examples {

/// One named measure: a number, or an array of numbers.
struct Metric {
  std::string name;            ///< JSON key, with its unit as a suffix (e.g. "angle_error_rad")
  std::vector<double> values;  ///< one entry for a scalar
  bool is_array{false};        ///< written as a JSON array even with one entry
};

/// The measures of one solved example.
struct TaskResult {
  std::vector<Metric> metrics;
  bool task_success{false};
  std::string criterion;  ///< the success criterion in words, e.g. "|q_N - pi| < 1e-3 rad"
};

/// Evaluates the task of `config` on `solution` (q, v, tau for k = 0..N). Examples without a
/// registered measure get the generic one: "final_error" = max_i |q_N(i) - qbar_N(i)| over every
/// coordinate, with task_success when it is below 1e-2.
TaskResult EvaluateTask(const ExampleConfig& config, const Trajectory& solution);

/// True when `example_name` has a registered task measure.
bool HasTaskMeasure(const std::string& example_name);

/// Largest |tau_k(i)| over k = 0..N-1 and the unactuated DoFs i of the problem, N m or N (0 when
/// there are none).
double MaxUnactuatedEffort(const ExampleConfig& config, const Trajectory& solution);

}  // namespace idto::examples
