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
  kSolveTime,      ///< t + the measured wall-clock solve time (what this machine achieves)
  kControlPeriod,  ///< t + 1 / control_rate (a fixed one-period delay)
  kFixed           ///< t + ClosedLoopOptions::fixed_latency: reproducible runs (tests, sweeps)
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
  double fixed_latency{0.0};  ///< s, >= 0: the delay of LatencyModel::kFixed
  std::vector<Disturbance> disturbances;
  /// The PD's -Kd v term is integrated implicitly by the plant (Plant::SetExtraDamping), the
  /// rest of u explicitly: stable at 1 ms even where Kd h / I > 2 on a light link. False: all
  /// of u is held constant over each plant step.
  bool implicit_damping{true};
  /// Log every `log_every` plant steps (1: every step).
  int log_every{10};
};

/// What a closed-loop run recorded.
struct ClosedLoopLog {
  std::vector<double> t;                 ///< log times, s
  std::vector<Eigen::VectorXd> q, v, u;  ///< plant state and applied generalized forces
  std::vector<Eigen::VectorXd> contact;  ///< contact force magnitude per body, N
  /// The configuration the plan in force asked for at each log time (q_d of the PD+), nq each.
  std::vector<Eigen::VectorXd> q_plan;
  std::vector<double> replan_time;  ///< time of each re-plan, s
  std::vector<double> solve_time;   ///< wall-clock seconds of each re-plan
  std::vector<int> solve_status;    ///< TerminationType of each re-plan
  int num_rejected_plans{0};
  double control_period{0.0};
  /// Empty unless the plant failed (threw from Advance); the run stopped at failure_time.
  std::string failure;
  double failure_time{-1.0};

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
/// plan in force (see LatencyModel). When the plant throws (e.g. MuJoCo reports an unstable
/// simulation), the run stops there and the log keeps everything up to it, with the reason in
/// ClosedLoopLog::failure.
ClosedLoopLog RunClosedLoop(const Model& model, const ClosedLoopOptions& options,
                            Controller* controller, sim::Plant* plant);

}  // namespace idto::mpc
