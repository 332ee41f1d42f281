#include "run/metrics_spinner_hopper.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include "idto/contact/contact_engine.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/multibody/data.hpp"

namespace idto::examples {
namespace {

Metric Scalar(const std::string& name, double value) { return Metric{name, {value}, false}; }

/// Pose of geometry g in the world (data holds ForwardKinematics).
Eigen::Isometry3d GeometryPose(const Model& model, const Data& data, GeometryIndex g) {
  const GeometryInstance& geometry = model.geometries()[g];
  return data.X_WB(geometry.body) * geometry.X_BG;
}

/// Signed distance of a contact pair at the configuration in `data`, m.
double PairDistance(const Model& model, const Data& data, const ContactPair& pair) {
  const auto& geometries = model.geometries();
  return SignedDistance(
             geometries[pair.geometry_a].shape, GeometryPose(model, data, pair.geometry_a),
             geometries[pair.geometry_b].shape, GeometryPose(model, data, pair.geometry_b))
      .distance;
}

bool IsGroundPair(const Model& model, const ContactPair& pair) {
  const auto& geometries = model.geometries();
  const bool a_ground = pair.body_a == kWorldBody &&
                        std::holds_alternative<HalfSpace>(geometries[pair.geometry_a].shape);
  const bool b_ground = pair.body_b == kWorldBody &&
                        std::holds_alternative<HalfSpace>(geometries[pair.geometry_b].shape);
  return a_ground != b_ground;
}

}  // namespace

TaskResult SpinnerTask(const ExampleConfig& config, const Trajectory& solution) {
  constexpr double kMinAngleGained = 1.5;     // rad (the nominal asks for 2)
  constexpr double kMaxSpinnerTorque = 1e-3;  // N m (1% of the damping torque at 1 rad/s)
  TaskResult result;
  result.criterion =
      "spinner angle gained q_N - q_0 >= 1.5 rad and max_k |tau_spinner,k| < 1e-3 N m (the "
      "finger turns the passive spinner through contact alone)";
  const Model& model = config.model;
  const std::vector<int> unactuated = config.problem.UnactuatedDofs(model);
  if (unactuated.size() != 1 || model.nq() != model.nv() || solution.q.size() < 2) {
    result.criterion += " [not evaluated: needs one unactuated DoF, nq = nv and a trajectory]";
    return result;
  }
  const int s = unactuated[0];
  const Eigen::VectorXd& q_0 = solution.q.front();
  const Eigen::VectorXd& q_N = solution.q.back();
  const Eigen::VectorXd& q_nom_N = config.problem.q_nom.back();
  const double gained = q_N(s) - q_0(s);
  const double effort = MaxUnactuatedEffort(config, solution);
  double finger_error = 0.0;
  for (int i = 0; i < model.nq(); ++i) {
    if (i != s) finger_error = std::max(finger_error, std::abs(q_N(i) - q_nom_N(i)));
  }
  // Closest approach of the finger to the spinner (negative: penetration), over every contact
  // pair of the scene and every step.
  double min_distance = std::numeric_limits<double>::infinity();
  if (config.problem.enable_contact && model.geometries().size() >= 2) {
    const ContactEngine engine(model, config.problem.contact);
    Data data(model);
    for (const Eigen::VectorXd& q : solution.q) {
      ForwardKinematics(model, q, &data);
      for (const ContactPair& pair : engine.pairs()) {
        min_distance = std::min(min_distance, PairDistance(model, data, pair));
      }
    }
  }
  result.metrics = {Scalar("spinner_angle_gained_rad", gained),
                    Scalar("final_angle_error_rad", std::abs(q_N(s) - q_nom_N(s))),
                    Scalar("max_spinner_torque_Nm", effort),
                    Scalar("finger_final_error_rad", finger_error),
                    Scalar("min_contact_distance_m", min_distance)};
  result.task_success = gained >= kMinAngleGained && effort < kMaxSpinnerTorque;
  return result;
}

TaskResult HopperTask(const ExampleConfig& config, const Trajectory& solution) {
  constexpr double kMinDistance = 0.5;          // m (the nominal asks for 1.0)
  constexpr int kMinAirborneSteps = 2;          // 0.1 s at dt = 0.05 s
  constexpr double kFlightForceFraction = 0.1;  // airborne: ground force < 10% of the weight
  constexpr double kMaxBaseEffort = 1e-2;       // N or N m
  constexpr double kMaxPitchChange = 0.3;       // rad
  TaskResult result;
  result.criterion =
      "base x gained >= 0.5 m; airborne for >= 2 steps (every foot sphere above the ground and "
      "the ground's normal force < 10% of the weight); max_k |tau_base,k| < 1e-2 N (N m); "
      "|pitch_N - pitch_0| < 0.3 rad";
  const Model& model = config.model;
  JointIndex base = 0;
  for (JointIndex j = 1; j <= model.num_joints(); ++j) {
    if (model.joint_type(j) == JointType::kPlanar) {
      base = j;
      break;
    }
  }
  if (base == 0 || solution.q.size() < 2) {
    result.criterion += " [not evaluated: needs a planar base and a trajectory]";
    return result;
  }
  const int x_index = model.position_start(base);  // x, y (here: height), theta
  const Eigen::VectorXd& q_0 = solution.q.front();
  const Eigen::VectorXd& q_N = solution.q.back();
  const double distance = q_N(x_index) - q_0(x_index);
  const double pitch_change = q_N(x_index + 2) - q_0(x_index + 2);
  const double effort = MaxUnactuatedEffort(config, solution);

  // Per step k = 1..N: the ground's normal force at (q_k, v_k) (the force acting in tau_{k-1})
  // and the clearance of the lowest geometry above the ground (its signed distance).
  const double weight = model.total_mass() * model.gravity().norm();
  int airborne_steps = 0;
  double min_force_fraction = std::numeric_limits<double>::infinity();
  double max_clearance = -std::numeric_limits<double>::infinity();
  if (config.problem.enable_contact && model.geometries().size() >= 2) {
    const ContactEngine engine(model, config.problem.contact);
    ContactData contact = engine.MakeData(model);
    Data data(model);
    for (size_t k = 1; k < solution.q.size() && k < solution.v.size(); ++k) {
      ForwardKinematics(model, solution.q[k], solution.v[k], &data);
      engine.Evaluate(model, data, &contact);
      double ground_force = 0.0;
      for (int r = 0; r < contact.num_active; ++r) {
        const ContactResult& c = contact.results[r];
        if (IsGroundPair(model, engine.pairs()[c.pair])) ground_force += c.force.fn;
      }
      double clearance = std::numeric_limits<double>::infinity();
      for (const ContactPair& pair : engine.pairs()) {
        if (IsGroundPair(model, pair)) {
          clearance = std::min(clearance, PairDistance(model, data, pair));
        }
      }
      const double fraction = weight > 0.0 ? ground_force / weight : 0.0;
      min_force_fraction = std::min(min_force_fraction, fraction);
      max_clearance = std::max(max_clearance, clearance);
      if (fraction < kFlightForceFraction && clearance > 0.0) ++airborne_steps;
    }
  }
  result.metrics = {Scalar("base_distance_m", distance),
                    Scalar("final_base_height_m", q_N(x_index + 1)),
                    Scalar("pitch_change_rad", pitch_change),
                    Scalar("max_base_effort", effort),
                    Scalar("airborne_steps", airborne_steps),
                    Scalar("airborne_time_s", airborne_steps * config.problem.time_step),
                    Scalar("min_ground_force_fraction", min_force_fraction),
                    Scalar("max_foot_clearance_m", max_clearance)};
  result.task_success = distance >= kMinDistance && airborne_steps >= kMinAirborneSteps &&
                        effort < kMaxBaseEffort && std::abs(pitch_change) < kMaxPitchChange;
  return result;
}

}  // namespace idto::examples
