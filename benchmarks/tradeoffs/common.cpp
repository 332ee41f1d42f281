#include "common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "idto/contact/contact_engine.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/multibody/data.hpp"

namespace idto::tradeoffs {
namespace {

double Median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

int FindJoint(const Model& model, JointType type) {
  for (JointIndex j = 1; j <= model.num_joints(); ++j) {
    if (model.joint_type(j) == type) return j;
  }
  return 0;
}

}  // namespace

ExampleConfig LoadExample(const Context& context, const std::string& name) {
  const std::string path = FindExampleConfig(name, context.share_dirs);
  return LoadExampleConfig(path, context.share_dirs);
}

ExampleConfig LoadEditedExample(const Context& context, const std::string& name,
                                const std::string& old_text, const std::string& new_text) {
  return LoadEditedExample(context, name, {{old_text, new_text}});
}

ExampleConfig LoadEditedExample(const Context& context, const std::string& name,
                                const std::vector<std::pair<std::string, std::string>>& edits) {
  const std::string path = FindExampleConfig(name, context.share_dirs);
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  for (const auto& [old_text, new_text] : edits) {
    const size_t at = text.find(old_text);
    if (at == std::string::npos || text.find(old_text, at + 1) != std::string::npos) {
      throw std::runtime_error(path + ": expected exactly one '" + old_text + "' to replace");
    }
    text.replace(at, old_text.size(), new_text);
  }
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  return LoadExampleConfigString(text, path, base_dir, context.share_dirs);
}

SolveResult Solve(const ExampleConfig& config, const ProblemDefinition& problem,
                  const SolverOptions& options) {
  ExampleConfig for_guess = config;
  for_guess.problem = problem;
  const std::vector<Eigen::VectorXd> guess = MakeInitialGuess(for_guess);
  TrajectoryOptimizer optimizer(config.model, problem, options);
  SolveResult result;
  result.summary = optimizer.Solve(guess, &result.solution);
  return result;
}

SolveResult SolveRepeated(const ExampleConfig& config, const ProblemDefinition& problem,
                          const SolverOptions& options, int repeats) {
  SolveResult best = Solve(config, problem, options);
  for (int r = 1; r < repeats; ++r) {
    const SolveResult again = Solve(config, problem, options);
    if (again.summary.log.size() != best.summary.log.size()) break;
    best.summary.solve_time = std::min(best.summary.solve_time, again.summary.solve_time);
    for (size_t i = 0; i < best.summary.log.size(); ++i) {
      IterationSummary& a = best.summary.log[i];
      const IterationSummary& b = again.summary.log[i];
      a.time_derivatives = std::min(a.time_derivatives, b.time_derivatives);
      a.time_cost = std::min(a.time_cost, b.time_cost);
      a.time_hessian = std::min(a.time_hessian, b.time_hessian);
      a.time_factorization = std::min(a.time_factorization, b.time_factorization);
      a.time_multipliers = std::min(a.time_multipliers, b.time_multipliers);
      a.time_total = std::min(a.time_total, b.time_total);
    }
  }
  return best;
}

double MeanIterationSeconds(const SolverSummary& summary) {
  if (summary.log.empty()) return std::nan("");
  double total = 0.0;
  for (const IterationSummary& it : summary.log) total += it.time_total;
  return total / static_cast<double>(summary.log.size());
}

double MedianFullIterationSeconds(const SolverSummary& summary) {
  // Full: the iteration formed its gradient and Hessian (not a retry after a rejected step).
  // With trial derivatives its derivatives may have come with the previous trial point.
  std::vector<double> times;
  for (const IterationSummary& it : summary.log) {
    if (it.time_hessian > 0.0) times.push_back(it.time_total);
  }
  return Median(times);
}

double MedianDerivativeSeconds(const SolverSummary& summary) {
  std::vector<double> times;
  for (const IterationSummary& it : summary.log) {
    if (it.time_derivatives > 0.0) times.push_back(it.time_derivatives);
  }
  return Median(times);
}

Convergence ConvergedWithin(const SolverSummary& summary, double relative) {
  Convergence c;
  c.iterations = static_cast<int>(summary.log.size());
  const double tolerance = relative * std::abs(summary.final_cost);
  // Walk back from the end while the cost at the start of the iteration is already close.
  for (int i = static_cast<int>(summary.log.size()) - 1; i >= 0; --i) {
    if (std::abs(summary.log[i].cost - summary.final_cost) > tolerance) break;
    c.iterations = i;
  }
  for (int i = 0; i < c.iterations; ++i) c.seconds += summary.log[i].time_total;
  return c;
}

std::string ConvergenceText(const SolverSummary& summary) {
  const Convergence c = ConvergedWithin(summary, 0.01);
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%d (%.3g s)", c.iterations, c.seconds);
  return buffer;
}

double PlainCost(const ExampleConfig& config, const ProblemDefinition& problem,
                 const std::vector<Eigen::VectorXd>& q) {
  SolverOptions options;
  options.constraint_method = ConstraintMethod::kNone;  // L with R as given: no override
  TrajectoryOptimizer optimizer(config.model, problem, options);
  return optimizer.EvalCost(q);
}

double MaxUnactuatedForce(const ExampleConfig& config, const ProblemDefinition& problem,
                          const Trajectory& solution) {
  double worst = 0.0;
  const std::vector<int> unactuated = problem.UnactuatedDofs(config.model);
  // tau_N is zero by convention: only k < N carries the constraint.
  for (size_t k = 0; k + 1 < solution.tau.size(); ++k) {
    for (int d : unactuated) worst = std::max(worst, std::abs(solution.tau[k](d)));
  }
  return worst;
}

TaskMeasure MeasureTask(const ExampleConfig& config, const ProblemDefinition& problem,
                        const Trajectory& solution) {
  TaskMeasure m;
  const Model& model = config.model;
  const Eigen::VectorXd& q_0 = solution.q.front();
  const Eigen::VectorXd& q_N = solution.q.back();
  const double effort = MaxUnactuatedForce(config, problem, solution);
  if (config.name == "spinner") {
    const int s = problem.UnactuatedDofs(model).front();
    m.name = "spinner angle gained (rad)";
    m.value = q_N(s) - q_0(s);
    m.success = m.value >= 1.5 && effort < 1e-3;
    m.criterion = "angle gained >= 1.5 rad and max_k |tau_spinner,k| < 1e-3 N m (idto-run's)";
    return m;
  }
  const int planar = FindJoint(model, JointType::kPlanar);
  const int floating = FindJoint(model, JointType::kFloating);
  if (config.name == "hopper" && planar > 0) {
    const int x = model.position_start(planar);
    m.name = "base x gained (m)";
    m.value = q_N(x) - q_0(x);
    m.success = m.value >= 0.5 && effort < 1e-2;
    m.criterion =
        "x gained >= 0.5 m and max_k |tau_base,k| < 1e-2 (the distance and effort parts of "
        "idto-run's criterion; its airborne and pitch parts are not checked here)";
    return m;
  }
  if ((config.name == "quadruped" || config.name == "quadruped_hills") && floating > 0) {
    const int x = model.position_start(floating) + 4;  // [qw qx qy qz x y z]
    const double nominal = problem.q_nom.back()(x) - problem.q_nom.front()(x);
    m.name = "base x gained (m)";
    m.value = q_N(x) - q_0(x);
    m.success = m.value >= 0.2 * nominal;
    m.criterion =
        "x gained >= 20% of the nominal (the distance part of idto-run's criterion; its tilt, "
        "height and phantom-motion parts are not checked here)";
    return m;
  }
  m.name = "final error max_i |q_N(i) - qbar_N(i)|";
  m.value = (q_N - problem.q_nom.back()).cwiseAbs().maxCoeff();
  m.success = m.value < 1e-2;
  m.criterion = "final error < 1e-2";
  return m;
}

ContactImpulse MeasureContactImpulse(const ExampleConfig& config, const ProblemDefinition& problem,
                                     const Trajectory& solution) {
  ContactImpulse impulse;
  if (!problem.enable_contact || config.model.geometries().size() < 2) return impulse;
  const ContactEngine engine(config.model, problem.contact);
  ContactData contact = engine.MakeData(config.model);
  Data data(config.model);
  for (size_t k = 1; k < solution.q.size(); ++k) {
    ForwardKinematics(config.model, solution.q[k], solution.v[k], &data);
    engine.Evaluate(config.model, data, &contact);
    for (int i = 0; i < contact.num_active; ++i) {
      const ContactResult& r = contact.results[i];
      const double j = r.force.fn * problem.time_step;
      impulse.total += j;
      if (r.phi > 0.0) impulse.at_distance += j;
    }
  }
  return impulse;
}

}  // namespace idto::tradeoffs
