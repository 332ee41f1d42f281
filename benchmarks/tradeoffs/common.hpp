#pragma once

/// @file
/// Shared pieces of idto-tradeoffs: the run context, loading examples, solving, timing and the
/// task measures every study reports.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "idto/config/config.hpp"
#include "idto/problem/problem_definition.hpp"
#include "idto/solver/solver_options.hpp"
#include "idto/solver/solver_summary.hpp"
#include "idto/solver/trajectory_optimizer.hpp"

namespace idto::tradeoffs {

/// Where and how the studies run.
struct Context {
  bool quick{false};                    ///< smaller sweeps, fewer iterations (smoke test)
  int threads{2};                       ///< solver threads wherever threads are not swept
  std::vector<std::string> share_dirs;  ///< where examples/<name>/<name>.yaml are found
  std::string data_dir;                 ///< scratch folder for gnuplot data and scripts
  std::string figure_dir;               ///< where the PNG figures go
  std::string figure_link_prefix;       ///< how tradeoffs.md links a figure ("figures/")
  bool gnuplot{false};                  ///< false: tables only (gnuplot missing)
  int repeats{3};                       ///< solves per timed configuration (see SolveRepeated)
};

/// The example configuration `name` (examples/<name>/<name>.yaml over the share folders).
ExampleConfig LoadExample(const Context& context, const std::string& name);

/// The example configuration `name` with the one occurrence of `old_text` in its YAML text
/// replaced by `new_text` before parsing (for changes the nominal trajectory depends on, such
/// as the number of steps). Throws when `old_text` does not occur exactly once.
ExampleConfig LoadEditedExample(const Context& context, const std::string& name,
                                const std::string& old_text, const std::string& new_text);
/// As above with several (old_text, new_text) replacements, applied in order.
ExampleConfig LoadEditedExample(const Context& context, const std::string& name,
                                const std::vector<std::pair<std::string, std::string>>& edits);

/// One solve and what it produced.
struct SolveResult {
  SolverSummary summary;
  Trajectory solution;
};

/// Solves `problem` on the config's model from the config's initial guess.
SolveResult Solve(const ExampleConfig& config, const ProblemDefinition& problem,
                  const SolverOptions& options);

/// Solves `repeats` times (the solves are deterministic) and keeps, per iteration and phase,
/// the smallest time measured, and the smallest solve time: the timings least disturbed by other
/// work on the machine. Falls back to the first solve's timings if the logs differ in length.
SolveResult SolveRepeated(const ExampleConfig& config, const ProblemDefinition& problem,
                          const SolverOptions& options, int repeats);

/// Mean seconds per iteration over the whole log (accepted and rejected steps).
double MeanIterationSeconds(const SolverSummary& summary);
/// Median seconds of the iterations that computed derivatives (the iteration's full cost: a
/// rejected step only re-solves the dogleg and evaluates one trial cost).
double MedianFullIterationSeconds(const SolverSummary& summary);
/// Median seconds of the derivative phase over the iterations that computed derivatives.
double MedianDerivativeSeconds(const SolverSummary& summary);

/// How fast a solve got close to where it ended: the first iteration from which the cost stays
/// within `relative` of the final cost, and the seconds spent until then.
struct Convergence {
  int iterations{0};
  double seconds{0.0};
};
Convergence ConvergedWithin(const SolverSummary& summary, double relative);
/// "12 (0.034 s)": ConvergedWithin(summary, 0.01) as text.
std::string ConvergenceText(const SolverSummary& summary);

/// The cost L(q) of a trajectory with the problem's own weights (no penalty override), so
/// solutions of different constraint methods are compared on one scale.
double PlainCost(const ExampleConfig& config, const ProblemDefinition& problem,
                 const std::vector<Eigen::VectorXd>& q);

/// max_k max_i |tau_k(i)| over the unactuated DoFs i.
double MaxUnactuatedForce(const ExampleConfig& config, const ProblemDefinition& problem,
                          const Trajectory& solution);

/// An example's task measure: what the example asks for, measured on a solution.
struct TaskMeasure {
  std::string name;  ///< e.g. "spinner angle gained (rad)"
  double value{0.0};
  bool success{false};    ///< the example's task_success criterion (see TaskCriterion)
  std::string criterion;  ///< that criterion in words
};

/// The task measure of the spinner (angle gained; success: >= 1.5 rad and max |tau_spinner| <
/// 1e-3 N m, as idto-run), the hopper and quadruped (base x gained; success: >= 0.5 m / >= 20%
/// of the nominal, unactuated forces small) and, for any other example, the final error
/// max_i |q_N(i) - qbar_N(i)| (success: < 1e-2).
TaskMeasure MeasureTask(const ExampleConfig& config, const ProblemDefinition& problem,
                        const Trajectory& solution);

/// Normal contact impulse along a trajectory: sum over k = 1..N and evaluated pairs of
/// f_n(q_k, v_k) dt, in total and from pairs that were apart (phi > 0): force at a distance.
struct ContactImpulse {
  double total{0.0};        ///< N s
  double at_distance{0.0};  ///< N s, pairs with phi > 0
};
ContactImpulse MeasureContactImpulse(const ExampleConfig& config, const ProblemDefinition& problem,
                                     const Trajectory& solution);

}  // namespace idto::tradeoffs
