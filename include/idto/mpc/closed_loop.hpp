#pragma once

/// @file
/// Closed-loop simulation: an MPC Controller against a Plant, with a latency model so that the
/// reported behaviour is achievable in real time on the machine that ran it.

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "idto/mpc/controller.hpp"
#include "idto/mpc/realtime.hpp"
#include "idto/sim/plant.hpp"

namespace idto::mpc {

/// How long after a re-plan at time t its plan starts driving the robot.
enum class LatencyModel {
  kSolveTime,      ///< t + the measured wall-clock solve time (what this machine achieves)
  kControlPeriod,  ///< t + 1 / control_rate (a fixed one-period delay)
  kFixed           ///< t + ClosedLoopOptions::fixed_latency: reproducible runs (tests, sweeps)
};

/// What happens to a re-plan whose latency exceeds the control period (a *late* re-plan).
enum class LatePlanPolicy {
  /// The late plan is discarded and the plan in force stays; the next re-plan starts at the next
  /// control step as usual (as if each re-plan ran on its own solver).
  kDiscard,
  /// One solver, run asynchronously as the paper's MPC runs: the plan in force stays until the
  /// late plan arrives (t + its latency), which then takes over; the control steps that find the
  /// solver still busy start no re-plan (ClosedLoopLog::num_skipped_replans), and the next one
  /// starts at the first control step after the late plan arrived.
  kUseOnArrival
};

/// A scripted external push on the plant.
struct Disturbance {
  int body{-1};                                      ///< idto body index (-1: none)
  double start{0.0};                                 ///< s
  double duration{0.0};                              ///< s
  Eigen::Vector3d force_W{Eigen::Vector3d::Zero()};  ///< N, world frame, at the body origin
};

/// Noise on the controller's measurement (q̂, v̂) of the plant's state; the plant itself is
/// untouched. Zero (default) everywhere: the controller sees the plant's exact state.
struct SensorNoise {
  /// Standard deviation of the Gaussian noise on each position coordinate (rad or m, >= 0).
  /// The quaternion of a floating joint is instead turned by a small random rotation whose
  /// rotation vector has this standard deviation per axis (composed on the left, so q̂ stays a
  /// unit quaternion).
  double position{0.0};
  /// Relative standard deviation of the noise on each velocity coordinate (>= 0): the noise on
  /// v_i has standard deviation max(velocity_relative |v_i|, velocity_floor).
  double velocity_relative{0.0};
  /// Absolute floor of that standard deviation (rad/s or m/s, >= 0), so that a coordinate at
  /// rest is not measured exactly.
  double velocity_floor{0.0};
  bool enabled() const { return position > 0.0 || velocity_relative > 0.0 || velocity_floor > 0.0; }
};

struct ClosedLoopOptions {
  double duration{5.0};          ///< simulated seconds
  double plant_time_step{1e-3};  ///< s: plant steps between control updates
  LatencyModel latency{LatencyModel::kSolveTime};
  double fixed_latency{0.0};  ///< s, >= 0: the delay of LatencyModel::kFixed
  /// s, >= 0: each re-plan's latency is the latency model's value plus a draw from
  /// uniform [0, latency_jitter]. A re-plan whose latency exceeds the control period is late:
  /// it is counted (ClosedLoopLog::num_late_plans), the previous plan stays in force at the
  /// control step it missed, and `late_plans` says what happens to it.
  double latency_jitter{0.0};
  /// What a late re-plan's plan does: discarded (default), or used when it arrives by a solver
  /// that starts no other re-plan meanwhile.
  LatePlanPolicy late_plans{LatePlanPolicy::kDiscard};
  /// Noise on the measured state used by the controller (re-plans and the PD+ command).
  SensorNoise sensor_noise;
  /// Seed of the closed loop's random numbers (sensor noise, latency jitter; std::mt19937_64):
  /// with a fixed latency model, two runs with the same seed are bitwise identical.
  std::uint64_t seed{0};
  std::vector<Disturbance> disturbances;
  /// The PD's -Kd v term is integrated implicitly by the plant (Plant::SetExtraDamping), the
  /// rest of u explicitly: stable at 1 ms even where Kd h / I > 2 on a light link. False: all
  /// of u is held constant over each plant step.
  bool implicit_damping{true};
  /// Log every `log_every` plant steps (1: every step).
  int log_every{10};
  /// Pace the loop to the wall clock, as a controller on a robot runs: the re-plan at simulated
  /// time t starts no earlier than t after the run's start (the plant's steps in between run at
  /// once, then the loop sleeps). Off (default): the loop runs as fast as it can. Between two
  /// re-plans the controller's threads sleep, so the OS gives them the CPU ahead of a process
  /// that computes continuously (docs/benchmarks.md, "Issue 19: iteration time beside a busy
  /// competitor").
  bool real_time{false};
  /// Keep the solver's worker threads awake between re-plans: for the run, idle workers yield
  /// for up to a control period plus 2 ms before they sleep (instead of 250 µs), so a re-plan
  /// finds them running. For a paced loop on a machine to itself: on this 2-core VM it cut the
  /// quadruped's paced re-plan from 2.2 to 1.4 ms (mean), but beside a busy process the awake
  /// workers lose the scheduler's preference for threads that slept, and the p95 grew (docs/
  /// benchmarks.md, "Issue 19"). The pool's setting is process-wide: loops running at the same
  /// time get the largest of their requests, and the value from before returns when the last
  /// of them ends.
  bool keep_workers_awake{false};
  /// 0 (default): the loop's thread and the solver's workers keep their scheduling. 1..99: for
  /// the run they take SCHED_FIFO at this priority (RealtimeScheduling, idto/mpc/realtime.hpp),
  /// ahead of every normally scheduled process, as a robot's control loop is usually run. A
  /// refusal by the OS (no root, CAP_SYS_NICE or RLIMIT_RTPRIO) does not stop the run: it is
  /// reported in ClosedLoopLog::realtime_error. A free-running loop at SCHED_FIFO leaves its
  /// cores to other processes only through the kernel's real-time throttling (5 % of each
  /// second by default); a paced loop (real_time) leaves them what it does not use. For the
  /// steadiest re-plans, also hold a RealtimeScheduling of the same priority around the
  /// controller's Initialize, as idto-run does, so the solver's workers start under it.
  int realtime_priority{0};
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
  int num_rejected_plans{0};        ///< re-plans that failed or produced a non-finite plan
  /// Re-plans whose latency (model + jitter) exceeded the control period (discarded, or used on
  /// arrival: ClosedLoopOptions::late_plans).
  int num_late_plans{0};
  /// Control steps that started no re-plan because the solver was still busy with a late one
  /// (LatePlanPolicy::kUseOnArrival only; 0 otherwise). Not in replan_time / solve_time.
  int num_skipped_replans{0};
  /// Plant steps at which the PD+ command was not finite (non-finite measurement or plan): the
  /// last finite command (zero at the start) was applied instead.
  int num_nonfinite_commands{0};
  double control_period{0.0};
  /// Empty unless the plant failed (threw from Advance); the run stopped at failure_time.
  std::string failure;
  double failure_time{-1.0};
  /// With ClosedLoopOptions::realtime_priority: why SCHED_FIFO was not (fully) granted ("" when
  /// it was, or was not asked for).
  std::string realtime_error;

  double mean_solve_time() const;
  double max_solve_time() const;
  /// The p-th percentile (0..100) of the solve times.
  double percentile_solve_time(double p) const;
  /// Fraction of re-plans whose solve time was within the control period.
  double fraction_on_time() const;
  /// CSV: t, q..., v..., u..., contact... with a header naming the coordinates and bodies.
  std::string ToCsv(const Model& model) const;
};

/// The controller's measurement of the plant's state (q: nq, v: nv) with `noise` drawn from
/// `rng` (Gaussian, Box-Muller on the generator's raw 64-bit output, so the draws depend only
/// on the seed, not on the standard library's distributions). Outputs are resized. With no
/// noise, q_hat = q and v_hat = v and `rng` is not used.
void MeasureState(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                  const SensorNoise& noise, std::mt19937_64* rng, Eigen::VectorXd* q_hat,
                  Eigen::VectorXd* v_hat);

/// A uniform draw in [0, 1) from the raw output of `rng` (53 bits).
double UniformDraw(std::mt19937_64* rng);
/// A standard normal draw from `rng` (Box-Muller, two UniformDraw calls).
double NormalDraw(std::mt19937_64* rng);

/// Runs `controller` against `plant` from the plant's current state for options.duration.
/// Re-plans every 1 / control_rate s; the PD+ command is recomputed every plant step from the
/// plan in force (see LatencyModel), on the state measured with options.sensor_noise. A failed
/// or late re-plan keeps the previous plan in force; a non-finite command is never applied.
/// When the plant throws (e.g. MuJoCo reports an unstable
/// simulation), the run stops there and the log keeps everything up to it, with the reason in
/// ClosedLoopLog::failure.
ClosedLoopLog RunClosedLoop(const Model& model, const ClosedLoopOptions& options,
                            Controller* controller, sim::Plant* plant);

}  // namespace idto::mpc
