#include "idto/mpc/closed_loop.hpp"

#include <string>

#include "idto/core/csv.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include <Eigen/Geometry>
#include <stdexcept>

#include "core/parallel.hpp"
#include "idto/core/errors.hpp"
#include "idto/mpc/position_filter.hpp"

namespace idto::mpc {

double ClosedLoopLog::mean_solve_time() const {
  if (solve_time.empty()) return 0.0;
  double s = 0.0;
  for (double x : solve_time) s += x;
  return s / static_cast<double>(solve_time.size());
}

double ClosedLoopLog::max_solve_time() const {
  return solve_time.empty() ? 0.0 : *std::max_element(solve_time.begin(), solve_time.end());
}

double ClosedLoopLog::percentile_solve_time(double p) const {
  if (solve_time.empty()) return 0.0;
  std::vector<double> s = solve_time;
  std::sort(s.begin(), s.end());
  const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * static_cast<double>(s.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(rank));
  const size_t hi = std::min(lo + 1, s.size() - 1);
  return s[lo] + (rank - static_cast<double>(lo)) * (s[hi] - s[lo]);
}

double ClosedLoopLog::fraction_on_time() const {
  if (solve_time.empty()) return 1.0;
  int n = 0;
  for (double x : solve_time) n += x <= control_period ? 1 : 0;
  return static_cast<double>(n) / static_cast<double>(solve_time.size());
}

std::string ClosedLoopLog::ToCsv(const Model& model) const {
  std::ostringstream out;
  out.precision(10);
  out << "t";
  const auto field = [&out](const std::string& name) { out << ',' << CsvField(name); };
  for (int i = 0; i < model.nq(); ++i)
    field("q_" + model.position_name(i) + "_" + std::to_string(i));
  for (int i = 0; i < model.nv(); ++i)
    field("v_" + model.velocity_name(i) + "_" + std::to_string(i));
  for (int i = 0; i < model.nv(); ++i)
    field("u_" + model.velocity_name(i) + "_" + std::to_string(i));
  for (int b = 0; b < model.num_bodies(); ++b) field("contact_" + model.body_name(b));
  out << "\n";
  for (size_t k = 0; k < t.size(); ++k) {
    out << t[k];
    for (int i = 0; i < q[k].size(); ++i) out << "," << q[k](i);
    for (int i = 0; i < v[k].size(); ++i) out << "," << v[k](i);
    for (int i = 0; i < u[k].size(); ++i) out << "," << u[k](i);
    for (int i = 0; i < contact[k].size(); ++i) out << "," << contact[k](i);
    out << "\n";
  }
  return out.str();
}

double UniformDraw(std::mt19937_64* rng) { return static_cast<double>((*rng)() >> 11) * 0x1.0p-53; }

double NormalDraw(std::mt19937_64* rng) {
  // Box-Muller; 1 - u is in (0, 1], so the logarithm is finite.
  const double u1 = 1.0 - UniformDraw(rng);
  const double u2 = UniformDraw(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

void MeasureState(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                  const SensorNoise& noise, std::mt19937_64* rng, Eigen::VectorXd* q_hat,
                  Eigen::VectorXd* v_hat) {
  *q_hat = q;
  *v_hat = v;
  if (!noise.enabled()) return;
  if (noise.position > 0.0) {
    for (JointIndex j : model.floating_joints()) {
      const int s = model.position_start(j);
      Eigen::Vector3d rotation;
      for (int k = 0; k < 3; ++k) rotation(k) = noise.position * NormalDraw(rng);
      const double angle = rotation.norm();
      const Eigen::Quaterniond turn =
          angle > 0.0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation / angle))
                      : Eigen::Quaterniond::Identity();
      const Eigen::Quaterniond measured =
          (turn * Eigen::Quaterniond(q(s), q(s + 1), q(s + 2), q(s + 3))).normalized();
      q_hat->segment<4>(s) << measured.w(), measured.x(), measured.y(), measured.z();
    }
    // Every other coordinate (no allocation: the floating joints are few).
    for (int i = 0; i < model.nq(); ++i) {
      bool quaternion = false;
      for (JointIndex j : model.floating_joints()) {
        const int s = model.position_start(j);
        quaternion = quaternion || (i >= s && i < s + 4);
      }
      if (!quaternion) (*q_hat)(i) += noise.position * NormalDraw(rng);
    }
  }
  if (noise.velocity_relative > 0.0 || noise.velocity_floor > 0.0) {
    for (int i = 0; i < model.nv(); ++i) {
      const double sigma = std::max(noise.velocity_relative * std::abs(v(i)), noise.velocity_floor);
      (*v_hat)(i) += sigma * NormalDraw(rng);
    }
  }
}

namespace {

void CheckOptions(const ClosedLoopOptions& options) {
  static constexpr const char* kWhere = "RunClosedLoop";
  CheckPositive(kWhere, "options.duration", options.duration);
  CheckPositive(kWhere, "options.plant_time_step", options.plant_time_step);
  CheckNonNegative(kWhere, "options.fixed_latency", options.fixed_latency);
  CheckNonNegative(kWhere, "options.latency_jitter", options.latency_jitter);
  CheckNonNegative(kWhere, "options.sensor_noise.position", options.sensor_noise.position);
  CheckNonNegative(kWhere, "options.sensor_noise.velocity_relative",
                   options.sensor_noise.velocity_relative);
  CheckNonNegative(kWhere, "options.sensor_noise.velocity_floor",
                   options.sensor_noise.velocity_floor);
  if (options.log_every < 1) {
    ThrowInvalidArgument(kWhere, "options.log_every", std::to_string(options.log_every),
                         "at least 1");
  }
  if (options.realtime_priority < 0 || options.realtime_priority > kMaxRealtimePriority) {
    ThrowInvalidArgument(
        kWhere, "options.realtime_priority", std::to_string(options.realtime_priority),
        "0 (off) or a SCHED_FIFO priority in [1, " + std::to_string(kMaxRealtimePriority) + "]");
  }
}

/// The sum of the scripted disturbances acting at time t (body -1 when none does).
void DisturbanceAt(const std::vector<Disturbance>& disturbances, double t, int* body,
                   Eigen::Vector3d* f) {
  *body = -1;
  f->setZero();
  for (const Disturbance& d : disturbances) {
    if (d.body >= 0 && t >= d.start && t < d.start + d.duration) {
      *body = d.body;
      *f += d.force_W;
    }
  }
}

using Clock = std::chrono::steady_clock;

/// keep_workers_awake: for its lifetime, idle pool workers yield for a control period plus 2 ms
/// before they sleep, so they are awake when the next re-plan starts. Loops running at the same
/// time (on several threads) share the process-wide setting: it is the largest of their
/// requests, and the value before the first returns when the last one ends.
class AwakeWorkers {
 public:
  AwakeWorkers(bool enabled, double period) {
    if (!enabled) return;
    request_ = std::chrono::duration_cast<std::chrono::microseconds>(
        std::chrono::duration<double>(period + 2e-3));
    const std::lock_guard<std::mutex> lock(Mutex());
    if (Requests().empty()) Original() = internal::ThreadPoolIdleYield();
    Requests().insert(request_);
    Apply();
  }
  ~AwakeWorkers() {
    if (request_.count() < 0) return;
    const std::lock_guard<std::mutex> lock(Mutex());
    Requests().erase(Requests().find(request_));
    Apply();
  }
  AwakeWorkers(const AwakeWorkers&) = delete;
  AwakeWorkers& operator=(const AwakeWorkers&) = delete;

 private:
  static std::mutex& Mutex() {
    static std::mutex mutex;
    return mutex;
  }
  static std::multiset<std::chrono::microseconds>& Requests() {
    static std::multiset<std::chrono::microseconds> requests;
    return requests;
  }
  static std::chrono::microseconds& Original() {
    static std::chrono::microseconds original{0};
    return original;
  }
  // Under Mutex(): the pool's setting is the largest request, or the original value.
  static void Apply() {
    internal::SetThreadPoolIdleYield(
        Requests().empty() ? Original() : std::max(*Requests().rbegin(), Original()));
  }

  std::chrono::microseconds request_{-1};  // -1: not enabled
};

/// real_time: sleeps until t seconds after `start`.
void SleepUntil(Clock::time_point start, double t) {
  std::this_thread::sleep_until(
      start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t)));
}

/// The plans of a closed-loop run: the one in force, the one waiting for its activation time
/// (latency model) and, with LatePlanPolicy::kUseOnArrival, when the solver is free again.
struct PlanSchedule {
  Plan active;
  Plan pending;
  double pending_at{-1.0};
  double solver_busy_until{-1.0};
};

/// The re-plan of the control step at time t: runs it (or, while the solver is still busy with a
/// late re-plan, skips it), logs it and schedules its plan by the latency model.
void ReplanStep(const ClosedLoopOptions& options, double t, double period, double dt,
                Clock::time_point run_start, const Eigen::VectorXd& q_hat,
                const Eigen::VectorXd& v_hat, std::mt19937_64* rng, Controller* controller,
                PlanSchedule* plans, ClosedLoopLog* log) {
  if (t + 1e-12 < plans->solver_busy_until) {
    ++log->num_skipped_replans;
    return;
  }
  if (options.real_time) SleepUntil(run_start, t);
  const Clock::time_point t0 = Clock::now();
  const SolverSummary s = controller->Replan(t, q_hat, v_hat);
  const double solve = std::chrono::duration<double>(Clock::now() - t0).count();
  log->replan_time.push_back(t);
  log->solve_time.push_back(solve);
  log->solve_status.push_back(static_cast<int>(s.termination));
  double delay = options.latency == LatencyModel::kSolveTime ? solve
                 : options.latency == LatencyModel::kFixed   ? options.fixed_latency
                                                             : period;
  if (options.latency_jitter > 0.0) delay += options.latency_jitter * UniformDraw(rng);
  const bool late = delay > period + 1e-12;
  const bool use_late = options.late_plans == LatePlanPolicy::kUseOnArrival;
  if (late && use_late) plans->solver_busy_until = t + delay;  // no re-plan starts before then
  if (s.termination == TerminationType::kFailure) {
    return;  // rejected by the controller (counted there): the plan in force stays
  }
  if (late) ++log->num_late_plans;
  if (late && !use_late) return;  // too late to be used: the plan in force stays
  plans->pending = controller->plan();
  plans->pending_at = t + std::max(delay, dt);
}

}  // namespace

ClosedLoopLog RunClosedLoop(const Model& model, const ClosedLoopOptions& options,
                            Controller* controller, sim::Plant* plant) {
  CheckOptions(options);
  ClosedLoopLog log;
  const double period = 1.0 / controller->options().control_rate;
  log.control_period = period;
  const double dt = options.plant_time_step;
  const long steps = static_cast<long>(std::llround(options.duration / dt));
  const long steps_per_replan = std::max(1L, static_cast<long>(std::llround(period / dt)));
  std::mt19937_64 rng(options.seed);

  PlanSchedule plans;
  plans.active = controller->plan();
  PdGains gains = controller->options().gains;
  if (gains.Kp.size() == 0) gains.Kp = Eigen::VectorXd::Zero(model.nv());
  if (gains.Kd.size() == 0) gains.Kd = Eigen::VectorXd::Zero(model.nv());
  const PdController pd(model, controller->options().actuated, gains);
  Eigen::VectorXd q_d, v_d, u_ff, u = Eigen::VectorXd::Zero(model.nv());
  Eigen::VectorXd u_last = u, q_hat, v_hat;
  // Implicit PD damping: the plant applies -Kd v at the end of each step, so the command it
  // receives is u + Kd v (the plant's own v: with noise, u keeps -Kd v_hat, what the
  // controller would apply).
  Eigen::VectorXd kd_implicit = Eigen::VectorXd::Zero(model.nv());
  if (options.implicit_damping) {
    for (int i : controller->options().actuated) kd_implicit(i) = gains.Kd(i);
  }
  plant->SetExtraDamping(kd_implicit);
  Eigen::VectorXd u_plant = u;

  std::optional<PositionFilter> filter;
  const double time_constant = controller->options().estimator.position_time_constant;
  if (time_constant > 0.0) filter.emplace(model, time_constant);

  const AwakeWorkers awake_workers(options.keep_workers_awake, period);
  RealtimeScheduling realtime(options.realtime_priority);
  const Clock::time_point run_start = Clock::now();
  for (long step = 0; step < steps; ++step) {
    const double t = step * dt;
    MeasureState(model, plant->q(), plant->v(), options.sensor_noise, &rng, &q_hat, &v_hat);
    if (filter) {
      // The controller's estimate replaces the measured positions (MpcOptions::Estimator).
      if (step == 0) {
        filter->Reset(q_hat);
      } else {
        filter->Update(dt, q_hat, v_hat, &q_hat);
      }
    }
    // A plan due now takes over before a re-plan at this step replaces the pending one (a
    // latency of exactly one control period activates at the next re-plan's step).
    if (plans.pending_at >= 0.0 && t + 1e-12 >= plans.pending_at) {
      plans.active = plans.pending;
      plans.pending_at = -1.0;
    }
    if (step % steps_per_replan == 0 && step > 0) {
      ReplanStep(options, t, period, dt, run_start, q_hat, v_hat, &rng, controller, &plans, &log);
    }
    plans.active.Sample(model, t, &q_d, &v_d, &u_ff);
    pd.Compute(q_hat, v_hat, q_d, v_d, u_ff, &u);
    if (u.allFinite()) {
      u_last = u;
    } else {
      ++log.num_nonfinite_commands;
      u = u_last;
    }
    int body = -1;
    Eigen::Vector3d f;
    DisturbanceAt(options.disturbances, t, &body, &f);
    if (step % options.log_every == 0) {
      log.t.push_back(t);
      log.q.push_back(plant->q());
      log.v.push_back(plant->v());
      log.u.push_back(u);
      log.contact.push_back(plant->contact_force_per_body());
      log.q_plan.push_back(q_d);
    }
    try {
      u_plant = u + kd_implicit.cwiseProduct(plant->v());
      plant->Advance(dt, u_plant, body, f);
    } catch (const std::runtime_error& e) {
      // The plant gave up (e.g. MuJoCo's instability check): keep what was logged and say so.
      log.failure = e.what();
      log.failure_time = t;
      break;
    }
  }
  log.num_rejected_plans = controller->num_rejected_plans();
  log.realtime_error = realtime.CheckWorkers();
  return log;
}

}  // namespace idto::mpc
