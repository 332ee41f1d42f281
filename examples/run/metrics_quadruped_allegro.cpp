#include "run/metrics_quadruped_allegro.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Geometry>

#include "idto/geometry/shape.hpp"
#include "idto/math/quaternion.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/data.hpp"

namespace idto::examples {
namespace {

Metric Scalar(const std::string& name, double value) { return Metric{name, {value}, false}; }

/// The floating joint named `preferred` when there is one, otherwise the model's first floating
/// joint; -1 when the model has none.
int FindFloatingJoint(const Model& model, const std::string& preferred) {
  if (model.floating_joints().empty()) return -1;
  if (model.HasJoint(preferred)) {
    const JointIndex j = model.GetJointIndex(preferred);
    if (model.joint_type(j) == JointType::kFloating) return j;
  }
  return model.floating_joints().front();
}

/// Unit quaternion of the floating joint whose q coordinates start at `qs` ([qw qx qy qz]).
Eigen::Quaterniond BaseQuaternion(const Eigen::VectorXd& q, int qs) {
  return QuaternionFromWxyz(q.data() + qs).normalized();
}

/// Largest norms over k = 0..N-1 of the angular (first three) and linear (last three) entries of
/// tau_k at a floating joint's velocities, which start at `vs` ([torque; force], N m and N).
void MaxFloatingEffort(const Trajectory& solution, int vs, double* max_torque, double* max_force) {
  *max_torque = 0.0;
  *max_force = 0.0;
  const int N = static_cast<int>(solution.q.size()) - 1;
  for (int k = 0; k < N && k < static_cast<int>(solution.tau.size()); ++k) {
    *max_torque = std::max(*max_torque, solution.tau[k].segment<3>(vs).norm());
    *max_force = std::max(*max_force, solution.tau[k].segment<3>(vs + 3).norm());
  }
}

/// How far the unactuated generalized forces alone would move the floating joint (velocities
/// from `vs`): the system, rigid with its joints locked (composite inertia M_bb of the joint's
/// 6 x 6 block of M(q_init)), free and at rest, pushed by tau_k for k = 0..N-1, would turn by
/// |theta| and move by |x|, x_k = M_bb^-1 dt^2 sum_{i<k} sum_{j<=i} tau_j. Returns the largest
/// |theta_k| (rad) and |x_k| (m) over k. Small values mean the motion comes from contact.
void PhantomMotion(const ExampleConfig& config, const Trajectory& solution, int vs,
                   double* max_rotation, double* max_displacement) {
  const Model& model = config.model;
  Data data(model);
  const Eigen::MatrixXd& M = MassMatrix(model, config.problem.q_init, &data);
  const Eigen::Matrix<double, 6, 6> M_bb = M.block<6, 6>(vs, vs);
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> M_bb_ldlt(M_bb);
  const double dt = config.problem.time_step;
  Eigen::Matrix<double, 6, 1> impulse = Eigen::Matrix<double, 6, 1>::Zero();  // sum tau dt
  Eigen::Matrix<double, 6, 1> moment = Eigen::Matrix<double, 6, 1>::Zero();   // sum impulse dt
  *max_rotation = 0.0;
  *max_displacement = 0.0;
  const int N = static_cast<int>(solution.q.size()) - 1;
  for (int k = 0; k < N && k < static_cast<int>(solution.tau.size()); ++k) {
    impulse += dt * solution.tau[k].segment<6>(vs);
    moment += dt * impulse;
    const Eigen::Matrix<double, 6, 1> x = M_bb_ldlt.solve(moment);
    *max_rotation = std::max(*max_rotation, x.head<3>().norm());
    *max_displacement = std::max(*max_displacement, x.tail<3>().norm());
  }
}

TaskResult NoFloatingBase(const char* example) {
  TaskResult result;
  result.task_success = false;
  result.criterion = std::string(example) + ": the model has no floating joint to measure";
  return result;
}

}  // namespace

TaskResult QuadrupedTask(const ExampleConfig& config, const Trajectory& solution) {
  constexpr double kMinDistanceFraction = 0.2;  // of the nominal distance
  constexpr double kMaxTilt = 0.3;              // rad
  constexpr double kMinHeightFraction = 2.0 / 3.0;
  constexpr double kMaxPhantomFraction = 0.1;  // of the nominal distance
  constexpr double kMaxPhantomRotation = 0.1;  // rad
  const Model& model = config.model;
  const int base = FindFloatingJoint(model, "body_root_joint");
  if (base < 0 || solution.q.empty()) return NoFloatingBase("quadruped");
  const int qs = model.position_start(base);
  const int vs = model.velocity_start(base);
  const int N = static_cast<int>(solution.q.size()) - 1;

  // Forward: the horizontal direction from the initial to the last nominal base position.
  const Eigen::Vector3d p_init = config.problem.q_init.segment<3>(qs + 4);
  const Eigen::Vector3d p_goal = config.problem.q_nom.back().segment<3>(qs + 4);
  Eigen::Vector3d forward(p_goal.x() - p_init.x(), p_goal.y() - p_init.y(), 0.0);
  const double nominal_distance = forward.norm();
  forward = nominal_distance > 0.0 ? Eigen::Vector3d(forward / nominal_distance)
                                   : Eigen::Vector3d::UnitX();

  const Eigen::Vector3d p_0 = solution.q.front().segment<3>(qs + 4);
  const Eigen::Vector3d p_N = solution.q.back().segment<3>(qs + 4);
  const double distance = (p_N - p_0).dot(forward);
  const double horizon = N * config.problem.time_step;
  double max_tilt = 0.0;
  for (const Eigen::VectorXd& q : solution.q) {
    const double zz = BaseQuaternion(q, qs).toRotationMatrix()(2, 2);
    max_tilt = std::max(max_tilt, std::acos(std::clamp(zz, -1.0, 1.0)));
  }
  double max_torque = 0.0;
  double max_force = 0.0;
  MaxFloatingEffort(solution, vs, &max_torque, &max_force);
  double phantom_rotation = 0.0;
  double phantom_displacement = 0.0;
  PhantomMotion(config, solution, vs, &phantom_rotation, &phantom_displacement);

  TaskResult result;
  result.metrics = {Scalar("base_distance_m", distance),
                    Scalar("nominal_distance_m", nominal_distance),
                    Scalar("mean_forward_speed_m_s", horizon > 0.0 ? distance / horizon : 0.0),
                    Scalar("final_base_height_m", p_N.z()),
                    Scalar("max_tilt_rad", max_tilt),
                    Scalar("max_base_force_N", max_force),
                    Scalar("max_base_torque_Nm", max_torque),
                    Scalar("max_unactuated_effort", MaxUnactuatedEffort(config, solution)),
                    Scalar("phantom_displacement_m", phantom_displacement),
                    Scalar("phantom_rotation_rad", phantom_rotation)};
  result.task_success = distance >= kMinDistanceFraction * nominal_distance &&
                        max_tilt < kMaxTilt && p_N.z() >= kMinHeightFraction * p_0.z() &&
                        phantom_displacement <= kMaxPhantomFraction * nominal_distance &&
                        phantom_rotation <= kMaxPhantomRotation;
  result.criterion =
      "base moves forward >= 20% of the nominal distance, max tilt < 0.3 rad, final height >= "
      "2/3 of the initial one; the base's unactuated forces alone would move the robot by <= 10% "
      "of the nominal distance and turn it by <= 0.1 rad";
  return result;
}

TaskResult AllegroTask(const ExampleConfig& config, const Trajectory& solution) {
  constexpr double kMaxOrientationError = 0.1;      // rad
  constexpr double kMaxDrift = 0.02;                // m
  constexpr double kMaxPhantomFraction = 0.25;      // of the target rotation
  constexpr double kMaxPhantomDisplacement = 0.01;  // m
  const Model& model = config.model;
  const int ball = FindFloatingJoint(model, "ball_root_joint");
  if (ball < 0 || solution.q.empty()) return NoFloatingBase("allegro");
  const int qs = model.position_start(ball);
  const int vs = model.velocity_start(ball);

  const Eigen::Quaterniond R_init = BaseQuaternion(config.problem.q_init, qs);
  const Eigen::Quaterniond R_target = BaseQuaternion(config.problem.q_nom.back(), qs);
  const Eigen::Quaterniond R_0 = BaseQuaternion(solution.q.front(), qs);
  const Eigen::Quaterniond R_N = BaseQuaternion(solution.q.back(), qs);
  const double rotation = R_0.angularDistance(R_N);
  const double target_rotation = R_init.angularDistance(R_target);
  const double error = R_N.angularDistance(R_target);
  const Eigen::Vector3d p_0 = solution.q.front().segment<3>(qs + 4);
  double drift = 0.0;
  for (const Eigen::VectorXd& q : solution.q) {
    drift = std::max(drift, (q.segment<3>(qs + 4) - p_0).norm());
  }
  double max_torque = 0.0;
  double max_force = 0.0;
  MaxFloatingEffort(solution, vs, &max_torque, &max_force);
  double phantom_rotation = 0.0;
  double phantom_displacement = 0.0;
  PhantomMotion(config, solution, vs, &phantom_rotation, &phantom_displacement);

  TaskResult result;
  result.metrics = {Scalar("ball_rotation_rad", rotation),
                    Scalar("target_rotation_rad", target_rotation),
                    Scalar("orientation_error_rad", error),
                    Scalar("ball_drift_m", drift),
                    Scalar("max_ball_force_N", max_force),
                    Scalar("max_ball_torque_Nm", max_torque),
                    Scalar("max_unactuated_effort", MaxUnactuatedEffort(config, solution)),
                    Scalar("phantom_rotation_rad", phantom_rotation),
                    Scalar("phantom_displacement_m", phantom_displacement)};
  result.task_success = error < kMaxOrientationError && drift < kMaxDrift &&
                        phantom_rotation <= kMaxPhantomFraction * target_rotation &&
                        phantom_displacement <= kMaxPhantomDisplacement;
  result.criterion =
      "ball orientation error < 0.1 rad, ball centre within 2 cm of its start at every step; the "
      "ball's unactuated forces alone would turn it by <= 25% of the target rotation and move "
      "it by <= 1 cm";
  return result;
}

}  // namespace idto::examples
