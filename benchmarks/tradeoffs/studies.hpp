#pragma once

/// @file
/// The studies of docs/tradeoffs.md. Each measures one knob (or a pair), writes its figure and
/// returns its section text and the findings the summary ranks.

#include <string>
#include <vector>

#include "common.hpp"
#include "report.hpp"

namespace idto::tradeoffs {

struct StudyResult {
  std::string id;        ///< short name (also the figure's suffix): "sensitivity", ...
  std::string title;     ///< section heading
  std::string markdown;  ///< section body
  std::vector<Finding> findings;
  /// Measured effects that are not a speed/accuracy pair (the summary lists them as text).
  std::vector<std::string> notes;
};

/// The paper's Table 4: spinner constraint violation after 500 iterations over k x v_s.
StudyResult RunSensitivityStudy(const Context& context);
/// Smoothing sigma: force at a distance, convergence, task and phantom contact impulse.
StudyResult RunSmoothingStudy(const Context& context);
/// Analytic derivatives vs forward and central differences: gradient error, convergence, time
/// per iteration.
StudyResult RunDerivativeStudy(const Context& context);
/// Penalty weights vs Lagrange multipliers: time, violation, cost, task.
StudyResult RunConstraintStudy(const Context& context);
/// Contact pruning tolerance: evaluation time and force error; solver time and answer.
StudyResult RunPruningStudy(const Context& context);
/// Threads and horizon: time per iteration.
StudyResult RunScalingStudy(const Context& context);

}  // namespace idto::tradeoffs
