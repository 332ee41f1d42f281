#include "run/metrics_closed_loop.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Geometry>

#include "idto/geometry/shape.hpp"

namespace idto::examples {
namespace {

using ClosedLoopFunction =
    std::function<TaskResult(const ExampleConfig&, const mpc::ClosedLoopLog&)>;

Metric Scalar(const std::string& name, double value) { return Metric{name, {value}, false}; }

double Duration(const mpc::ClosedLoopLog& log) {
  return log.t.size() >= 2 ? log.t.back() - log.t.front() : 0.0;
}

/// Position index of the floating joint `name` (-1 when absent or not floating).
int FloatingStart(const Model& model, const std::string& name) {
  if (!model.HasJoint(name)) return -1;
  const JointIndex j = model.GetJointIndex(name);
  return model.joint_type(j) == JointType::kFloating ? model.position_start(j) : -1;
}

Eigen::Quaterniond Quaternion(const Eigen::VectorXd& q, int qs) {
  return Eigen::Quaterniond(q(qs), q(qs + 1), q(qs + 2), q(qs + 3)).normalized();
}

/// Angle between the body's z axis and the world's.
double Tilt(const Eigen::VectorXd& q, int qs) {
  const double c = (Quaternion(q, qs) * Eigen::Vector3d::UnitZ()).z();
  return std::acos(std::clamp(c, -1.0, 1.0));
}

TaskResult NotEvaluated(const std::string& why) {
  TaskResult r;
  r.task_success = false;
  r.criterion = "[not evaluated: " + why + "]";
  return r;
}

/// Pendulum: upright at the end of the run.
TaskResult PendulumClosedLoop(const ExampleConfig& config, const mpc::ClosedLoopLog& log) {
  constexpr double kTolerance = 0.05;  // rad
  if (config.model.nq() != 1 || log.q.empty()) return NotEvaluated("needs one DoF and a log");
  const double error = std::abs(log.q.back()(0) - M_PI);
  TaskResult r;
  r.metrics = {Scalar("final_angle_error_rad", error)};
  r.task_success = error < kTolerance;
  r.criterion = "|q(T) - pi| < 0.05 rad";
  return r;
}

/// Spinner: keeps turning, at least 3 rad per 5 s on average.
TaskResult SpinnerClosedLoop(const ExampleConfig& config, const mpc::ClosedLoopLog& log) {
  constexpr double kMinRate = 3.0 / 5.0;  // rad/s: the 3 rad in 5 s
  const std::vector<int> unactuated = ControllerProblem(config).UnactuatedDofs(config.model);
  if (unactuated.size() != 1 || config.model.nq() != config.model.nv() || log.q.size() < 2) {
    return NotEvaluated("needs one unactuated DoF, nq = nv and a log");
  }
  const int s = unactuated[0];
  const double gained = log.q.back()(s) - log.q.front()(s);
  const double duration = Duration(log);
  TaskResult r;
  r.metrics = {Scalar("spinner_angle_gained_rad", gained),
               Scalar("mean_spinner_rate_rad_s", duration > 0 ? gained / duration : 0.0)};
  r.task_success = duration > 0 && gained >= kMinRate * duration;
  r.criterion = "spinner angle gained >= 0.6 rad/s x duration (3 rad in 5 s)";
  return r;
}

/// Hopper: hops forward: the base gains >= 0.5 m, with >= 2 flight phases (no contact force on
/// any robot body for >= 20 ms), without falling (pitch within 1 rad of the start, base height
/// above half the start's at every log entry).
TaskResult HopperClosedLoop(const ExampleConfig& config, const mpc::ClosedLoopLog& log) {
  constexpr double kMinDistance = 0.5;     // m
  constexpr int kMinFlights = 2;           // flight phases
  constexpr double kMinFlightTime = 0.02;  // s
  constexpr double kMaxPitchChange = 1.0;  // rad
  const Model& model = config.model;
  JointIndex base = 0;
  for (JointIndex j = 1; j <= model.num_joints(); ++j) {
    if (model.joint_type(j) == JointType::kPlanar) base = j;
  }
  if (base == 0 || log.q.size() < 2) return NotEvaluated("needs a planar base and a log");
  const int x = model.position_start(base);  // x, height, pitch
  const Eigen::VectorXd& q_0 = log.q.front();
  double max_pitch_change = 0.0;
  double min_height = std::numeric_limits<double>::infinity();
  int flights = 0;
  double flight_start = -1.0;
  double airborne_time = 0.0;
  for (size_t k = 0; k < log.q.size(); ++k) {
    max_pitch_change = std::max(max_pitch_change, std::abs(log.q[k](x + 2) - q_0(x + 2)));
    min_height = std::min(min_height, log.q[k](x + 1));
    const bool airborne = log.contact[k].tail(log.contact[k].size() - 1).maxCoeff() <= 0.0;
    if (airborne && flight_start < 0.0) flight_start = log.t[k];
    if ((!airborne || k + 1 == log.q.size()) && flight_start >= 0.0) {
      const double length = log.t[k] - flight_start;
      if (length >= kMinFlightTime) {
        ++flights;
        airborne_time += length;
      }
      flight_start = -1.0;
    }
  }
  const double distance = log.q.back()(x) - q_0(x);
  TaskResult r;
  r.metrics = {Scalar("base_distance_m", distance),
               Scalar("mean_forward_speed_m_s", distance / std::max(Duration(log), 1e-12)),
               Scalar("flight_phases", flights),
               Scalar("airborne_time_s", airborne_time),
               Scalar("max_pitch_change_rad", max_pitch_change),
               Scalar("min_base_height_m", min_height)};
  r.task_success = distance >= kMinDistance && flights >= kMinFlights &&
                   max_pitch_change < kMaxPitchChange && min_height > 0.5 * q_0(x + 1);
  r.criterion =
      "base x gained >= 0.5 m, >= 2 flight phases of >= 20 ms (no contact force on the robot), "
      "|pitch - pitch_0| < 1 rad and height > half the initial one throughout";
  return r;
}

/// Far end (largest x) of the world's cylinders named "hill*" where they meet the ground z = 0
/// (their axes along y); -inf when there are none.
double HillsEnd(const Model& model) {
  double end = -std::numeric_limits<double>::infinity();
  for (const GeometryInstance& g : model.geometries()) {
    if (g.body != kWorldBody || g.name.rfind("hill", 0) != 0) continue;
    const Cylinder* c = std::get_if<Cylinder>(&g.shape);
    if (c == nullptr) continue;
    const Eigen::Vector3d p = g.X_BG.translation();
    if (std::abs(p.z()) < c->radius) {
      end = std::max(end, p.x() + std::sqrt(c->radius * c->radius - p.z() * p.z()));
    }
  }
  return end;
}

/// Quadruped: walks forward at >= 0.3 m/s on average over the run without falling (tilt below
/// 0.5 rad, base height above 2/3 of the start's at every log entry). With hills in the scene,
/// the base must also end past the last hill.
TaskResult QuadrupedClosedLoop(const ExampleConfig& config, const mpc::ClosedLoopLog& log) {
  constexpr double kMinSpeed = 0.3;  // m/s
  constexpr double kMaxTilt = 0.5;   // rad
  constexpr double kMinHeightFraction = 2.0 / 3.0;
  const int qs = FloatingStart(config.model, "body_root_joint");
  if (qs < 0 || log.q.size() < 2) return NotEvaluated("needs body_root_joint and a log");
  double max_tilt = 0.0;
  double min_height = std::numeric_limits<double>::infinity();
  for (const Eigen::VectorXd& q : log.q) {
    max_tilt = std::max(max_tilt, Tilt(q, qs));
    min_height = std::min(min_height, q(qs + 6));
  }
  const double distance = log.q.back()(qs + 4) - log.q.front()(qs + 4);
  const double speed = distance / std::max(Duration(log), 1e-12);
  const double hills_end = HillsEnd(config.model);
  const bool hills = std::isfinite(hills_end);
  const bool upright =
      max_tilt < kMaxTilt && min_height >= kMinHeightFraction * log.q.front()(qs + 6);
  TaskResult r;
  r.metrics = {Scalar("base_distance_m", distance), Scalar("mean_forward_speed_m_s", speed),
               Scalar("max_tilt_rad", max_tilt), Scalar("min_base_height_m", min_height),
               Scalar("final_base_x_m", log.q.back()(qs + 4))};
  if (hills) {
    r.metrics.push_back(Scalar("hills_end_x_m", hills_end));
    r.task_success = upright && log.q.back()(qs + 4) > hills_end;
    r.criterion =
        "base ends past the last hill (x(T) > its far edge), max tilt < 0.5 rad and height >= "
        "2/3 of the initial one throughout";
  } else {
    r.task_success = upright && speed >= kMinSpeed;
    r.criterion =
        "mean forward speed >= 0.3 m/s, max tilt < 0.5 rad and height >= 2/3 of the initial one "
        "throughout";
  }
  return r;
}

/// Allegro: the ball reaches the controller's target orientation (within 0.2 rad) during the
/// run, without being dropped (its centre within 5 cm of the start throughout).
TaskResult AllegroClosedLoop(const ExampleConfig& config, const mpc::ClosedLoopLog& log) {
  constexpr double kTolerance = 0.2;  // rad (11.5 degrees)
  constexpr double kMaxDrift = 0.05;  // m
  constexpr double kHoldTime = 3.0;   // s: held at the target over the run's last 3 s
  const int qs = FloatingStart(config.model, "ball_root_joint");
  if (qs < 0 || log.q.empty()) return NotEvaluated("needs ball_root_joint and a log");
  const ProblemDefinition& problem = ControllerProblem(config);
  const Eigen::Quaterniond target = Quaternion(problem.q_nom.back(), qs);
  const Eigen::Quaterniond start = Quaternion(log.q.front(), qs);
  const Eigen::Vector3d p_0 = log.q.front().segment<3>(qs + 4);
  const double t_end = log.t.back();
  double reached_at = -1.0;
  double min_error = std::numeric_limits<double>::infinity();
  double hold_error = 0.0;  // the largest error over [t_end − kHoldTime, t_end]
  double drift = 0.0;
  for (size_t k = 0; k < log.q.size(); ++k) {
    const double error = Quaternion(log.q[k], qs).angularDistance(target);
    min_error = std::min(min_error, error);
    if (reached_at < 0.0 && error < kTolerance) reached_at = log.t[k];
    if (log.t[k] >= t_end - kHoldTime - 1e-9) hold_error = std::max(hold_error, error);
    drift = std::max(drift, (log.q[k].segment<3>(qs + 4) - p_0).norm());
  }
  TaskResult r;
  r.metrics = {
      Scalar("target_rotation_rad", start.angularDistance(target)),
      Scalar("min_orientation_error_rad", min_error),
      Scalar("final_orientation_error_rad", Quaternion(log.q.back(), qs).angularDistance(target)),
      Scalar("max_orientation_error_last_3_s_rad", hold_error),
      Scalar("time_to_target_s", reached_at),
      Scalar("max_ball_drift_m", drift)};
  // A run shorter than the hold time cannot show a hold.
  r.task_success =
      reached_at >= 0.0 && t_end >= kHoldTime && hold_error < kTolerance && drift < kMaxDrift;
  r.criterion =
      "ball orientation within 0.2 rad of the 180-degree target throughout the run's last 3 s "
      "(reached and held); ball centre within 5 cm of its start throughout";
  return r;
}

/// Bi-manual lift: the box is >= 5 cm above its start at the end and has been for the last
/// second (held), after any scripted push.
TaskResult LiftClosedLoop(const ExampleConfig& config, const mpc::ClosedLoopLog& log) {
  constexpr double kMinLift = 0.05;  // m
  constexpr double kHoldTime = 1.0;  // s
  const int qs = FloatingStart(config.model, "box_root_joint");
  if (qs < 0 || log.q.size() < 2) return NotEvaluated("needs box_root_joint and a log");
  const double z_0 = log.q.front()(qs + 6);
  const double t_end = log.t.back();
  double max_lift = -std::numeric_limits<double>::infinity();
  double min_lift_held = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < log.q.size(); ++k) {
    const double lift = log.q[k](qs + 6) - z_0;
    max_lift = std::max(max_lift, lift);
    if (log.t[k] >= t_end - kHoldTime) min_lift_held = std::min(min_lift_held, lift);
  }
  TaskResult r;
  r.metrics = {Scalar("max_lift_m", max_lift), Scalar("final_lift_m", log.q.back()(qs + 6) - z_0),
               Scalar("min_lift_last_second_m", min_lift_held)};
  r.task_success = min_lift_held >= kMinLift;
  r.criterion = "box >= 5 cm above its start throughout the last second of the run";
  return r;
}

const std::map<std::string, ClosedLoopFunction>& Registry() {
  static const std::map<std::string, ClosedLoopFunction> registry = {
      {"pendulum", PendulumClosedLoop},
      {"spinner", SpinnerClosedLoop},
      {"hopper", HopperClosedLoop},
      {"quadruped", QuadrupedClosedLoop},
      {"quadruped_hills", QuadrupedClosedLoop},
      {"allegro", AllegroClosedLoop},
      {"bimanual_lift", LiftClosedLoop},
  };
  return registry;
}

}  // namespace

Trajectory ResampleClosedLoop(const mpc::ClosedLoopLog& log, double dt) {
  Trajectory t;
  double next = 0.0;
  for (size_t k = 0; k < log.t.size(); ++k) {
    if (log.t[k] + 1e-9 < next) continue;
    t.q.push_back(log.q[k]);
    t.v.push_back(log.v[k]);
    t.tau.push_back(log.u[k]);
    next += dt;
  }
  return t;
}

TaskResult EvaluateClosedLoopTask(const ExampleConfig& config, const mpc::ClosedLoopLog& log) {
  const auto it = Registry().find(config.name);
  TaskResult r = it != Registry().end()
                     ? it->second(config, log)
                     : EvaluateTask(config, ResampleClosedLoop(log, config.problem.time_step));
  if (!log.failure.empty()) {
    r.metrics.push_back(Scalar("plant_failure_time_s", log.failure_time));
    r.task_success = false;
    r.criterion += " (the plant failed: never a success)";
  }
  return r;
}

}  // namespace idto::examples
