#include "run/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "run/metrics_bimanual.hpp"
#include "run/metrics_quadruped_allegro.hpp"
#include "run/metrics_spinner_hopper.hpp"

namespace idto::examples {
namespace {

using TaskFunction = std::function<TaskResult(const ExampleConfig&, const Trajectory&)>;

Metric Scalar(const std::string& name, double value) { return Metric{name, {value}, false}; }

Metric Array(const std::string& name, const Eigen::VectorXd& x) {
  return Metric{name, std::vector<double>(x.data(), x.data() + x.size()), true};
}

TaskResult GenericTask(const ExampleConfig& config, const Trajectory& solution);

/// Pendulum swing-up: the final angle must be pi (upright).
TaskResult PendulumTask(const ExampleConfig& config, const Trajectory& solution) {
  if (config.model.nq() != 1) return GenericTask(config, solution);
  constexpr double kTolerance = 1e-3;
  const double angle = solution.q.back()(0);
  const double error = std::abs(angle - M_PI);
  TaskResult result;
  result.metrics = {Scalar("final_angle_rad", angle), Scalar("angle_error_rad", error),
                    Scalar("final_velocity_rad_s", solution.v.back()(0))};
  result.task_success = error < kTolerance;
  result.criterion = "|q_N - pi| < 1e-3 rad";
  return result;
}

/// Acrobot swing-up: both links upright at the end, q_N = (pi, 0), with the passive shoulder
/// unactuated along the whole trajectory.
TaskResult AcrobotTask(const ExampleConfig& config, const Trajectory& solution) {
  if (config.model.nq() != 2) return GenericTask(config, solution);
  constexpr double kAngleTolerance = 1e-2;
  constexpr double kEffortTolerance = 1e-3;
  const Eigen::VectorXd& q = solution.q.back();
  const Eigen::Vector2d target(M_PI, 0.0);
  const double error = (q.head<2>() - target).norm();
  const double effort = MaxUnactuatedEffort(config, solution);
  TaskResult result;
  result.metrics = {Array("final_angles_rad", q.head<2>()), Scalar("error_rad", error),
                    Array("final_velocities_rad_s", solution.v.back().head<2>()),
                    Scalar("max_shoulder_torque_Nm", effort)};
  result.task_success = error < kAngleTolerance && effort < kEffortTolerance;
  result.criterion =
      "|q_N - (pi, 0)| < 1e-2 rad and max_k |tau_shoulder,k| < 1e-3 N m (the shoulder is "
      "passive)";
  return result;
}

/// Any other example: the final configuration must reach the final nominal configuration.
TaskResult GenericTask(const ExampleConfig& config, const Trajectory& solution) {
  constexpr double kTolerance = 1e-2;
  const Eigen::VectorXd& q = solution.q.back();
  const Eigen::VectorXd& q_nom = config.problem.q_nom.back();
  const double error = q.size() > 0 ? (q - q_nom).cwiseAbs().maxCoeff() : 0.0;
  TaskResult result;
  result.metrics = {Scalar("final_error", error),
                    Scalar("max_unactuated_effort", MaxUnactuatedEffort(config, solution))};
  result.task_success = error < kTolerance;
  result.criterion = "max_i |q_N(i) - qbar_N(i)| < 1e-2 (generic: no task measure registered)";
  return result;
}

// How far the plan goes past the problem's joint limits (its own bounds, or the model's):
// position (rad or m), velocity, and effort relative to the limit.
struct LimitExcess {
  double position{0.0}, velocity{0.0}, effort_relative{0.0};
};

LimitExcess MeasureLimitExcess(const ExampleConfig& config, const Trajectory& solution) {
  const Model& model = config.model;
  const LimitPenalties& l = config.problem.limits;
  const Eigen::VectorXd& lo = l.q_lower.size() ? l.q_lower : model.position_lower_limits();
  const Eigen::VectorXd& hi = l.q_upper.size() ? l.q_upper : model.position_upper_limits();
  const Eigen::VectorXd& v_max = l.v_max.size() ? l.v_max : model.velocity_limits();
  const Eigen::VectorXd& tau_max = l.tau_max.size() ? l.tau_max : model.effort_limits();
  LimitExcess e;
  for (const Eigen::VectorXd& q : solution.q) {
    for (int i = 0; i < q.size(); ++i)
      e.position = std::max({e.position, q(i) - hi(i), lo(i) - q(i)});
  }
  for (const Eigen::VectorXd& v : solution.v) {
    for (int i = 0; i < v.size(); ++i) e.velocity = std::max(e.velocity, std::abs(v(i)) - v_max(i));
  }
  const int N = static_cast<int>(solution.q.size()) - 1;
  for (int k = 0; k < N && k < static_cast<int>(solution.tau.size()); ++k) {
    for (int i = 0; i < model.nv(); ++i) {
      if (!std::isfinite(tau_max(i)) || tau_max(i) <= 0.0) continue;
      e.effort_relative =
          std::max(e.effort_relative, (std::abs(solution.tau[k](i)) - tau_max(i)) / tau_max(i));
    }
  }
  return e;
}

// An example with joint limits: the base example's task, and every joint within its limits to
// 0.01 rad (or m), 0.1 rad/s and 2% of the effort limit.
TaskFunction WithLimits(TaskFunction base) {
  return [base](const ExampleConfig& config, const Trajectory& solution) {
    TaskResult result = base(config, solution);
    const LimitExcess e = MeasureLimitExcess(config, solution);
    result.metrics.push_back(Scalar("max_position_limit_excess", e.position));
    result.metrics.push_back(Scalar("max_velocity_limit_excess", e.velocity));
    result.metrics.push_back(Scalar("max_effort_limit_excess_relative", e.effort_relative));
    const bool within = e.position <= 0.01 && e.velocity <= 0.1 && e.effort_relative <= 0.02;
    result.task_success = result.task_success && within;
    result.criterion += "; joints within their limits to 0.01 rad, 0.1 rad/s, 2% of effort";
    return result;
  };
}

const std::map<std::string, TaskFunction>& Registry() {
  static const std::map<std::string, TaskFunction> registry = {
      {"pendulum", PendulumTask},
      {"acrobot", AcrobotTask},
      {"quadruped", QuadrupedTask},
      {"quadruped_hills", QuadrupedTask},
      {"allegro", AllegroTask},
      {"quadruped_limits", WithLimits(QuadrupedTask)},
      {"allegro_limits", WithLimits(AllegroTask)},
      {"bimanual", BimanualMoveTask},
      {"bimanual_lift", BimanualLiftTask},
      {"bimanual_balance", BimanualBalanceTask},
      {"spinner", SpinnerTask},
      {"hopper", HopperTask},
  };
  return registry;
}

}  // namespace

bool HasTaskMeasure(const std::string& example_name) { return Registry().count(example_name) > 0; }

double MaxUnactuatedEffort(const ExampleConfig& config, const Trajectory& solution) {
  const Model& model = config.model;
  std::vector<int> dofs;
  if (config.problem.unactuated_dofs.has_value()) {
    dofs = *config.problem.unactuated_dofs;
  } else {
    for (int i = 0; i < model.nv(); ++i) {
      if (model.is_base_velocity()[i]) dofs.push_back(i);
    }
  }
  double effort = 0.0;
  const int N = static_cast<int>(solution.q.size()) - 1;
  for (int k = 0; k < N && k < static_cast<int>(solution.tau.size()); ++k) {
    for (int i : dofs) effort = std::max(effort, std::abs(solution.tau[k](i)));
  }
  return effort;
}

TaskResult EvaluateTask(const ExampleConfig& config, const Trajectory& solution) {
  const auto& registry = Registry();
  const auto it = registry.find(config.name);
  return it != registry.end() ? it->second(config, solution) : GenericTask(config, solution);
}

}  // namespace idto::examples
