#include "campaign/campaign.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "idto/config/mpc_config.hpp"
#include "idto/core/errors.hpp"
#include "idto/mpc/closed_loop.hpp"
#include "idto/mpc/controller.hpp"
#include "idto/multibody/model_builder.hpp"
#include "idto/sim/plant.hpp"
#include "run/metrics_closed_loop.hpp"

namespace idto::campaign {
namespace {

/// SplitMix64: a seed for the closed loop's own generator that is not the conditions' stream.
std::uint64_t MixSeed(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

double MetricOr(const examples::TaskResult& task, const std::string& name, double fallback) {
  for (const examples::Metric& m : task.metrics) {
    if (m.name == name && !m.values.empty()) return m.values[0];
  }
  return fallback;
}

void Append(const std::string& part, std::string* mode) {
  *mode += (mode->empty() ? "" : "+") + part;
}

}  // namespace

std::vector<std::string> CampaignExamples() {
  return {"spinner", "quadruped", "quadruped_hills", "hopper", "bimanual_lift", "allegro"};
}

CampaignSettings DefaultSettings(const std::string& example) {
  // body, impulse (N s), fixed latency (s): about the mean solve time of docs/mpc.md's table.
  struct Row {
    const char* body;
    double impulse;
    double latency;
    bool along_x;
  };
  static const std::map<std::string, Row> kRows = {
      {"spinner", {"finger_link2", 0.5, 0.4e-3, false}},  // 2 iterations per step: 0.33 ms
      {"quadruped", {"body", 8.0, 2.5e-3, false}},        // 2 iterations per step: 2.5 ms
      {"quadruped_hills", {"body", 8.0, 4.5e-3, false}},  // 3 iterations: 1.5 ms measured
      {"hopper", {"body", 0.5, 6.0e-3, true}},
      {"bimanual_lift", {"box", 6.0, 5.0e-3, false}},  // 5 iterations: 3.6-5.1 ms measured
      {"allegro", {"ball", 0.05, 9.0e-3, false}},
  };
  const auto it = kRows.find(example);
  if (it == kRows.end()) {
    std::string names;
    for (const std::string& n : CampaignExamples()) names += (names.empty() ? "" : ", ") + n;
    ThrowInvalidArgument("idto-campaign", "NAME", "'" + example + "'", "one of " + names);
  }
  CampaignSettings s;
  s.example = example;
  s.push_body = it->second.body;
  s.max_impulse = it->second.impulse;
  s.latency = it->second.latency;
  s.jitter = 2.0 * it->second.latency;
  s.push_along_x = it->second.along_x;
  return s;
}

RunConditions DrawConditions(const CampaignSettings& settings, const ExampleConfig& config,
                             std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const auto uniform = [&rng](double lo, double hi) {
    return lo + (hi - lo) * mpc::UniformDraw(&rng);
  };
  RunConditions c;
  c.seed = seed;
  const double duration = ParseMpcConfig(config).closed_loop.duration;
  c.push_time = uniform(0.1 * duration, std::max(0.1, 0.8 * duration - settings.push_duration));
  c.push_direction = settings.push_along_x ? (mpc::UniformDraw(&rng) < 0.5 ? 0.0 : M_PI)
                                           : uniform(0.0, 2.0 * M_PI);
  c.push_impulse = uniform(0.0, settings.max_impulse);
  c.friction_scale = uniform(1.0 - settings.mismatch, 1.0 + settings.mismatch);
  const Model& model = config.model;
  c.mass_scale.assign(model.num_bodies(), 1.0);
  double mass = 0.0;
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    if (model.body_mass(b) <= 0.0) continue;
    c.mass_scale[b] = uniform(1.0 - settings.mismatch, 1.0 + settings.mismatch);
    mass += c.mass_scale[b] * model.body_mass(b);
  }
  c.total_mass_scale = mass / model.total_mass();
  return c;
}

std::string FailureMode(const std::string& example, const examples::TaskResult& task) {
  if (task.task_success) return "";
  std::string mode;
  if (example == "spinner") {
    Append("spinner rate", &mode);
  } else if (example == "quadruped" || example == "quadruped_hills") {
    if (MetricOr(task, "max_tilt_rad", 0.0) >= 0.5) Append("tilt", &mode);
    if (example == "quadruped" && MetricOr(task, "mean_forward_speed_m_s", 0.0) < 0.3) {
      Append("speed", &mode);
    }
    if (example == "quadruped_hills" &&
        MetricOr(task, "final_base_x_m", 0.0) <= MetricOr(task, "hills_end_x_m", 0.0)) {
      Append("short of the hills", &mode);
    }
  } else if (example == "hopper") {
    if (MetricOr(task, "base_distance_m", 0.0) < 0.5) Append("distance", &mode);
    if (MetricOr(task, "flight_phases", 0.0) < 2.0) Append("flights", &mode);
    if (MetricOr(task, "max_pitch_change_rad", 0.0) >= 1.0) Append("pitch", &mode);
  } else if (example == "allegro") {
    if (MetricOr(task, "min_orientation_error_rad", 1e9) >= 0.2) {
      Append("not reached", &mode);
    } else if (MetricOr(task, "max_orientation_error_last_3_s_rad", 1e9) >= 0.2) {
      Append("not held", &mode);
    }
    if (MetricOr(task, "max_ball_drift_m", 0.0) >= 0.05) Append("ball drifted", &mode);
  } else if (example == "bimanual_lift") {
    Append("box not held", &mode);
  }
  // What remains is the height criterion of the quadruped and the hopper.
  return mode.empty() ? "height" : mode;
}

RunResult RunOne(const CampaignSettings& settings, const ExampleConfig& config, int run_index,
                 std::uint64_t seed, std::string* trajectory_csv) {
  RunResult result;
  result.run_index = run_index;
  RunConditions& c = result.conditions;
  c = DrawConditions(settings, config, seed);
  const Model& model = config.model;
  MpcConfig mpc = ParseMpcConfig(config);
  mpc::ClosedLoopOptions& cl = mpc.closed_loop;
  cl.latency = mpc::LatencyModel::kFixed;
  cl.fixed_latency = settings.latency;
  cl.latency_jitter = settings.jitter;
  cl.sensor_noise = {settings.noise_position, settings.noise_velocity,
                     settings.noise_velocity_floor};
  cl.seed = MixSeed(seed);
  mpc::Disturbance push;
  push.body = model.GetBodyIndex(settings.push_body);
  push.start = c.push_time;
  push.duration = settings.push_duration;
  push.force_W = c.push_impulse / settings.push_duration *
                 Eigen::Vector3d(std::cos(c.push_direction), std::sin(c.push_direction), 0.0);
  cl.disturbances = {push};  // replaces the example's scripted pushes
  mpc.mujoco.friction_coefficient *= c.friction_scale;
  for (ContactParameterOverride& o : mpc.mujoco.pairs.overrides) {
    if (o.friction_coefficient) *o.friction_coefficient *= c.friction_scale;
  }
  const Model plant_model = ScaleBodyInertias(model, c.mass_scale);
  std::unique_ptr<sim::Plant> plant = sim::MakeMujocoPlant(plant_model, mpc.mujoco);

  // The initial-state perturbation: its own stream, drawn after the conditions.
  std::mt19937_64 rng(MixSeed(seed ^ 0xC0FFEEULL));
  const ProblemDefinition& problem = ControllerProblem(config);
  Eigen::VectorXd q0 = problem.q_init, v0 = problem.v_init;
  for (JointIndex j = 1; j <= model.num_joints(); ++j) {
    if (model.joint_nq(j) != 1) continue;
    q0(model.position_start(j)) += settings.initial_position * mpc::NormalDraw(&rng);
  }
  for (int i = 0; i < model.nv(); ++i) v0(i) += settings.initial_velocity * mpc::NormalDraw(&rng);
  c.initial_position_norm = (q0 - problem.q_init).norm();
  c.initial_velocity_norm = (v0 - problem.v_init).norm();
  plant->Reset(q0, v0);

  if (settings.iterations_per_step > 0) {
    mpc.controller.iterations_per_step = settings.iterations_per_step;
  }
  SolverOptions options = config.mpc_solver.value_or(config.solver);
  options.num_threads = settings.threads;
  options.verbosity = 0;
  mpc::Controller controller(ControllerModel(config), problem, options, mpc.controller);
  const SolverSummary first =
      controller.Initialize(ControllerInitialGuess(config), mpc.initial_iterations);
  const mpc::ClosedLoopLog log = mpc::RunClosedLoop(model, cl, &controller, plant.get());
  if (trajectory_csv != nullptr) *trajectory_csv = log.ToCsv(model);
  const examples::TaskResult task = examples::EvaluateClosedLoopTask(config, log);
  result.success = task.task_success;
  result.criterion = task.criterion;
  result.metrics = task.metrics;
  result.num_replans = static_cast<int>(log.solve_time.size());
  result.rejected_plans = log.num_rejected_plans;
  result.late_plans = log.num_late_plans;
  result.skipped_replans = log.num_skipped_replans;
  result.nonfinite_commands = log.num_nonfinite_commands;
  result.plant_failure = log.failure;
  result.plant_failure_time = log.failure_time;
  if (!result.success) {
    if (first.termination == TerminationType::kFailure) {
      result.failure_mode = "solver failure";
    } else if (!log.failure.empty()) {
      // The parts of the criterion already failed when the plant gave up (a quadruped that fell
      // and thrashed on its back until MuJoCo diverged reads "tilt+speed, then plant failure";
      // "height" is FailureMode's answer when no listed part failed).
      const std::string before = FailureMode(config.name, task);
      result.failure_mode = (before == "height" ? "" : before + ", then ") + "plant failure";
    } else {
      result.failure_mode = FailureMode(config.name, task);
    }
  }
  return result;
}

}  // namespace idto::campaign
