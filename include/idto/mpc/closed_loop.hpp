#pragma once

/// @file
/// Closed-loop simulation: an MPC Controller against a Plant, with a latency model so that the
/// reported behaviour is achievable in real time on the machine that ran it.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "idto/mpc/controller.hpp"
#include "idto/sim/plant.hpp"

namespace idto::mpc {

/// How long after a re-plan at time t its plan starts driving the robot.
enum class LatencyModel {
  kSolveTime,     ///< t + the measured wall-clock solve time (what this machine achieves)
  kControlPeriod  ///< t + 1 / control_rate (a fixed one-period delay)
};

/// A scripted external push on the plant.
struct Disturbance {
  int body{-1};                                      ///< idto body index (-1: none)
  double start{0.0};                                 ///< s
  double duration{0.0};                              ///< s
  Eigen::Vector3d force_W{Eigen::Vector3d::Zero()};  ///< N, world frame, at the body origin
};

struct ClosedLoopOptions {
  double duration{5.0};          ///< simulated seconds
  double plant_time_step{1e-3};  ///< s: plant steps between control updates
  LatencyModel latency{LatencyModel::kSolveTime};
  std::vector<Disturbance> disturbances;
  /// Log every `log_every` plant steps (1: every step).
  int log_every{10};
};

/// What a closed-loop run recorded.
struct ClosedLoopLog {
  std::vector<double> t;                 ///< log times, s
  std::vector<Eigen::VectorXd> q, v, u;  ///< plant state and applied generalized forces
  std::vector<Eigen::VectorXd> contact;  ///< contact force magnitude per body, N
  std::vector<double> replan_time;       ///< time of each re-plan, s
  std::vector<double> solve_time;        ///< wall-clock seconds of each re-plan
  std::vector<int> solve_status;         ///< TerminationType of each re-plan
  int num_rejected_plans{0};
  double control_period{0.0};

  double mean_solve_time() const;
  double max_solve_time() const;
  /// The p-th percentile (0..100) of the solve times.
  double percentile_solve_time(double p) const;
  /// Fraction of re-plans whose solve time was within the control period.
  double fraction_on_time() const;
  /// CSV: t, q..., v..., u..., contact... with a header naming the coordinates and bodies.
  std::string ToCsv(const Model& model) const;
};

/// Runs `controller` against `plant` from the plant's current state for options.duration.
/// Re-plans every 1 / control_rate s; the PD+ command is recomputed every plant step from the
/// plan in force (see LatencyModel).
ClosedLoopLog RunClosedLoop(const Model& model, const ClosedLoopOptions& options,
                            Controller* controller, sim::Plant* plant);

}  // namespace idto::mpc
