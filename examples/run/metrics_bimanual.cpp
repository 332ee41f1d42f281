#include "run/metrics_bimanual.hpp"

// The box is the scene's floating joint "box_root_joint" (models/box.urdf attached with a
// floating base), q = [qw qx qy qz x y z], v = [ω, v] in the world frame. Its target is the last
// nominal configuration q̄_N. Every bi-manual task is judged on the last configuration q_N and on
// the generalized forces left on the box's unactuated DoFs (the "ghost" forces that no contact
// explains), measured against the box's weight.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace idto::examples {
namespace {

constexpr char kBoxJoint[] = "box_root_joint";
constexpr double kBoxMass = 0.55;  // kg, models/box.urdf
constexpr double kGravity = 9.81;  // m/s^2

// Bounds shared by the three tasks (see the examples' README files for their justification).
constexpr double kPositionTolerance = 0.02;     // m: 13 % of the 15 cm side
constexpr double kOrientationTolerance = 0.1;   // rad: 5.7 degrees
constexpr double kGhostForceFraction = 0.1;     // of the box's weight, m g = 5.4 N
constexpr double kGhostTorqueTolerance = 0.04;  // N m: 10 % of m g times the half side 7.5 cm
constexpr double kLiftFraction = 0.75;          // of the nominal height gain

Metric Scalar(const std::string& name, double value) { return Metric{name, {value}, false}; }

Metric Array(const std::string& name, const Eigen::Vector3d& x) {
  return Metric{name, {x(0), x(1), x(2)}, true};
}

Eigen::Quaterniond BoxQuaternion(const Eigen::VectorXd& q, int start) {
  return Eigen::Quaterniond(q(start), q(start + 1), q(start + 2), q(start + 3)).normalized();
}

enum class BoxTask { kMove, kLift, kBalance };

TaskResult EvaluateBoxTask(const ExampleConfig& config, const Trajectory& solution, BoxTask task) {
  TaskResult result;
  const Model& model = config.model;
  if (!model.HasJoint(kBoxJoint) ||
      model.joint_type(model.GetJointIndex(kBoxJoint)) != JointType::kFloating ||
      solution.q.empty()) {
    result.metrics = {Scalar("max_unactuated_effort", MaxUnactuatedEffort(config, solution))};
    result.task_success = false;
    result.criterion = "the scene has no floating joint 'box_root_joint' (no box to measure)";
    return result;
  }
  const JointIndex box = model.GetJointIndex(kBoxJoint);
  const int iq = model.position_start(box);
  const int iv = model.velocity_start(box);
  const Eigen::VectorXd& q_0 = solution.q.front();
  const Eigen::VectorXd& q_N = solution.q.back();
  const Eigen::VectorXd& q_target = config.problem.q_nom.back();

  const Eigen::Vector3d p_N = q_N.segment<3>(iq + 4);
  const Eigen::Vector3d p_target = q_target.segment<3>(iq + 4);
  const double position_error = (p_N - p_target).norm();
  const double orientation_error =
      BoxQuaternion(q_N, iq).angularDistance(BoxQuaternion(q_target, iq));
  const double height_gained = p_N.z() - q_0(iq + 6);
  const double height_target = p_target.z() - q_0(iq + 6);

  // Generalized forces on the box's DoFs, k = 0..N-1: torques (rows 0-2), forces (rows 3-5).
  double max_torque = 0.0;
  double max_force = 0.0;
  const int N = static_cast<int>(solution.q.size()) - 1;
  for (int k = 0; k < N && k < static_cast<int>(solution.tau.size()); ++k) {
    max_torque = std::max(max_torque, solution.tau[k].segment<3>(iv).norm());
    max_force = std::max(max_force, solution.tau[k].segment<3>(iv + 3).norm());
  }
  const double force_tolerance = kGhostForceFraction * kBoxMass * kGravity;
  const bool feasible = max_force < force_tolerance && max_torque < kGhostTorqueTolerance;
  const bool oriented = orientation_error < kOrientationTolerance;

  result.metrics = {Array("box_final_position_m", p_N),
                    Array("box_target_position_m", p_target),
                    Scalar("box_position_error_m", position_error),
                    Scalar("box_orientation_error_rad", orientation_error),
                    Scalar("box_height_gained_m", height_gained),
                    Scalar("max_unactuated_force_N", max_force),
                    Scalar("max_unactuated_torque_Nm", max_torque),
                    Scalar("max_unactuated_effort", MaxUnactuatedEffort(config, solution))};
  const std::string feasibility =
      "max_k |f_box,k| < 0.54 N (10 % of the box's weight) and max_k |tau_box,k| < 0.04 N m "
      "(unactuated generalized forces)";
  switch (task) {
    case BoxTask::kMove:
    case BoxTask::kBalance:
      result.task_success = position_error < kPositionTolerance && oriented && feasible;
      result.criterion =
          "|p_box,N - p_target| < 2 cm and box orientation error < 0.1 rad and " + feasibility;
      break;
    case BoxTask::kLift: {
      const double fraction = height_target > 0.0 ? height_gained / height_target : 0.0;
      result.metrics.push_back(Scalar("box_height_target_m", height_target));
      result.metrics.push_back(Scalar("box_height_fraction", fraction));
      result.task_success =
          height_target > 0.0 && fraction >= kLiftFraction && oriented && feasible;
      result.criterion =
          "box height gained >= 75 % of the nominal gain and box orientation error < 0.1 rad "
          "and " +
          feasibility;
      break;
    }
  }
  return result;
}

}  // namespace

TaskResult BimanualMoveTask(const ExampleConfig& config, const Trajectory& solution) {
  return EvaluateBoxTask(config, solution, BoxTask::kMove);
}

TaskResult BimanualLiftTask(const ExampleConfig& config, const Trajectory& solution) {
  return EvaluateBoxTask(config, solution, BoxTask::kLift);
}

TaskResult BimanualBalanceTask(const ExampleConfig& config, const Trajectory& solution) {
  return EvaluateBoxTask(config, solution, BoxTask::kBalance);
}

}  // namespace idto::examples
