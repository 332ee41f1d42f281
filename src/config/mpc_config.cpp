#include "idto/config/mpc_config.hpp"

// The `mpc` section: its sub-sections `problem`, `contact` and `solver` (read by the problem,
// contact and solver sections' code) and the controller, plant and closed-loop keys (here).
// Read from the file's own YAML tree by the reader of yaml_reader.hpp, like every section.

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "config_loader.hpp"
#include "idto/config/config.hpp"
#include "idto/core/errors.hpp"
#include "idto/mpc/realtime.hpp"
#include "idto/multibody/model_builder.hpp"
#include "joint_vector_reader.hpp"

namespace idto {

namespace config_internal {

namespace {

const std::vector<std::string> kMpcKeys = {"control_rate",
                                           "iterations_per_step",
                                           "duration",
                                           "initial_iterations",
                                           "plant",
                                           "plant_time_step",
                                           "latency",
                                           "latency_jitter",
                                           "late_plans",
                                           "real_time",
                                           "keep_workers_awake",
                                           "realtime_priority",
                                           "sensor_noise",
                                           "seed",
                                           "kp",
                                           "kd",
                                           "relative",
                                           "relative_goal",
                                           "orientation_lead",
                                           "hold",
                                           "estimator",
                                           "builtin_contact",
                                           "mujoco_friction",
                                           "mujoco_torsional_friction",
                                           "mujoco_rolling_friction",
                                           "mujoco_cone",
                                           "model_mass_scale",
                                           "disturbances",
                                           "problem",
                                           "contact",
                                           "solver"};
const std::vector<std::string> kBuiltinContactKeys = {
    "stiffness", "smoothing", "dissipation_velocity", "friction_coefficient", "stiction_velocity"};
const std::vector<std::string> kSensorNoiseKeys = {"position", "velocity_relative",
                                                   "velocity_floor"};
const std::vector<std::string> kEstimatorKeys = {"position_time_constant"};
const std::vector<std::string> kDisturbanceKeys = {"body", "start", "duration", "force"};

/// The options of a file without an `mpc` section (and the starting point of one with it).
MpcConfig DefaultMpcConfig(const Model& model, const ContactOptions& scene_contact) {
  MpcConfig m;
  m.plant = sim::HaveMujoco() ? "mujoco" : "builtin";
  m.builtin.pairs = scene_contact;
  m.builtin.contact.friction_coefficient = scene_contact.parameters.friction_coefficient;
  m.mujoco.pairs = scene_contact;
  m.mujoco.friction_coefficient = scene_contact.parameters.friction_coefficient;
  m.controller.gains.Kp = Eigen::VectorXd::Zero(model.nv());
  m.controller.gains.Kd = Eigen::VectorXd::Zero(model.nv());
  return m;
}

/// control_rate, iterations_per_step, duration, initial_iterations, plant, plant_time_step,
/// real_time, keep_workers_awake, realtime_priority and the MuJoCo friction keys.
void ReadScalars(const MapReader& mpc, MpcConfig* m) {
  mpc::MpcOptions& c = m->controller;
  c.control_rate = mpc.Positive("control_rate", c.control_rate);
  c.iterations_per_step = mpc.Int("iterations_per_step", c.iterations_per_step, 1);
  m->initial_iterations = mpc.Int("initial_iterations", m->initial_iterations, 0);
  const std::vector<std::string> plants = {"mujoco", "builtin"};
  m->plant = plants[mpc.Enum("plant", plants, m->plant == "mujoco" ? 0 : 1)];
  mpc::ClosedLoopOptions& cl = m->closed_loop;
  cl.plant_time_step = mpc.Positive("plant_time_step", cl.plant_time_step);
  m->builtin.time_step = cl.plant_time_step;
  m->mujoco.time_step = cl.plant_time_step;
  cl.duration = mpc.Positive("duration", cl.duration);
  cl.real_time = mpc.Bool("real_time", cl.real_time);
  cl.keep_workers_awake = mpc.Bool("keep_workers_awake", cl.keep_workers_awake);
  cl.realtime_priority = mpc.Int("realtime_priority", cl.realtime_priority, 0);
  if (cl.realtime_priority > mpc::kMaxRealtimePriority) {
    mpc.reader().FailValue(mpc.Get("realtime_priority"), mpc.Path("realtime_priority"),
                           std::to_string(cl.realtime_priority),
                           "0 (off) or a SCHED_FIFO priority in [1, " +
                               std::to_string(mpc::kMaxRealtimePriority) + "]");
  }
  if (cl.duration < cl.plant_time_step) {
    const bool given = mpc.Has("duration");
    mpc.reader().FailValue(
        given ? mpc.Get("duration") : mpc.Get("plant_time_step"), mpc.Path("duration"),
        FormatValue(cl.duration) + " s",
        "at least one plant step (plant_time_step = " + FormatValue(cl.plant_time_step) + " s)");
  }
  m->mujoco.friction_coefficient =
      mpc.NonNegative("mujoco_friction", m->mujoco.friction_coefficient);
  m->mujoco.torsional_friction =
      mpc.NonNegative("mujoco_torsional_friction", m->mujoco.torsional_friction);
  m->mujoco.rolling_friction =
      mpc.NonNegative("mujoco_rolling_friction", m->mujoco.rolling_friction);
  const std::vector<std::string> cones = {"elliptic", "pyramidal"};
  m->mujoco.friction_cone =
      cones[mpc.Enum("mujoco_cone", cones, m->mujoco.friction_cone == "pyramidal" ? 1 : 0)];
}

/// latency: solve_time, control_period, or a fixed delay in seconds (reproducible runs);
/// late_plans: discard or use_on_arrival (mpc::LatePlanPolicy).
void ReadLatency(const MapReader& mpc, mpc::ClosedLoopOptions* cl) {
  const std::vector<std::string> late = {"discard", "use_on_arrival"};
  cl->late_plans = static_cast<mpc::LatePlanPolicy>(
      mpc.Enum("late_plans", late, static_cast<int>(cl->late_plans)));
  if (!mpc.Has("latency")) return;
  const YAML::Node node = mpc.Get("latency");
  const std::string expected = "solve_time, control_period or a delay in seconds >= 0";
  if (!node.IsScalar()) mpc.reader().FailValue(node, mpc.Path("latency"), Describe(node), expected);
  const std::string text = Trim(node.Scalar());
  double seconds = 0.0;
  if (text == "solve_time") {
    cl->latency = mpc::LatencyModel::kSolveTime;
  } else if (text == "control_period") {
    cl->latency = mpc::LatencyModel::kControlPeriod;
  } else if (ParseNumber(text, &seconds) && std::isfinite(seconds) && seconds >= 0.0) {
    cl->latency = mpc::LatencyModel::kFixed;
    cl->fixed_latency = seconds;
  } else {
    mpc.reader().FailValue(node, mpc.Path("latency"), Describe(node), expected);
  }
}

/// latency_jitter (s), seed (integer >= 0) and sensor_noise: {position, velocity_relative,
/// velocity_floor} (mpc::ClosedLoopOptions; absent keys keep the defaults: no noise, no jitter).
void ReadNoiseAndJitter(const MapReader& mpc, mpc::ClosedLoopOptions* cl) {
  cl->latency_jitter = mpc.NonNegative("latency_jitter", cl->latency_jitter);
  cl->seed = static_cast<std::uint64_t>(mpc.Int("seed", static_cast<int>(cl->seed), 0));
  if (!mpc.Has("sensor_noise")) return;
  const MapReader n(mpc.reader(), mpc.Get("sensor_noise"), mpc.Path("sensor_noise"),
                    kSensorNoiseKeys);
  mpc::SensorNoise& noise = cl->sensor_noise;
  noise.position = n.NonNegative("position", noise.position);
  noise.velocity_relative = n.NonNegative("velocity_relative", noise.velocity_relative);
  noise.velocity_floor = n.NonNegative("velocity_floor", noise.velocity_floor);
}

/// estimator: {position_time_constant: s >= 0} (mpc::MpcOptions::Estimator; absent: off).
void ReadEstimator(const MapReader& mpc, mpc::MpcOptions* c) {
  if (!mpc.Has("estimator")) return;
  const MapReader e(mpc.reader(), mpc.Get("estimator"), mpc.Path("estimator"), kEstimatorKeys);
  c->estimator.position_time_constant =
      e.NonNegative("position_time_constant", c->estimator.position_time_constant);
}

/// relative: [joint, or {joint: [coordinate indices within the joint]}] -> position indices.
void ReadRelative(const MapReader& mpc, const Model& model, mpc::MpcOptions* c) {
  if (!mpc.Has("relative")) return;
  const Reader& r = mpc.reader();
  const YAML::Node list = mpc.Get("relative");
  const std::string expected = "a joint name or {joint: [coordinate indices within the joint]}";
  if (!list.IsSequence())
    r.FailValue(list, mpc.Path("relative"), Describe(list), "a list of joints");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string path = At(mpc.Path("relative"), i);
    const YAML::Node entry = list[i];
    if (!entry.IsScalar() && !(entry.IsMap() && entry.size() == 1)) {
      r.FailValue(entry, path, Describe(entry), expected);
    }
    const MapEntry e = entry.IsScalar() ? MapEntry{entry.Scalar(), entry, YAML::Node()}
                                        : r.Entries(entry, path, expected).front();
    if (!model.HasJoint(e.key)) {
      r.FailValue(e.key_node, path, "'" + e.key + "'", "a joint of the scene");
    }
    const JointIndex j = model.GetJointIndex(e.key);
    const int nq_j = model.joint_nq(j);
    if (entry.IsScalar()) {
      for (int k = 0; k < nq_j; ++k) c->relative_positions.push_back(model.position_start(j) + k);
      continue;
    }
    const std::string joint_path = Join(path, e.key);
    if (!e.value.IsSequence() || e.value.size() == 0) {
      r.FailValue(e.value, joint_path, Describe(e.value), "a non-empty list of coordinate indices");
    }
    for (std::size_t k = 0; k < e.value.size(); ++k) {
      const int index = r.Int(e.value[k], At(joint_path, k), 0);
      if (index >= nq_j) {
        r.FailValue(
            e.value[k], At(joint_path, k), std::to_string(index),
            "a coordinate index in [0, " + std::to_string(nq_j) + ") of joint '" + e.key + "'");
      }
      c->relative_positions.push_back(model.position_start(j) + index);
    }
  }
}

/// relative_goal: {joint: goal, or [goals]}: one goal per coordinate of the joint listed in
/// `relative` (read before), in that order; a single number when there is one.
void ReadRelativeGoals(const MapReader& mpc, const Model& model, mpc::MpcOptions* c) {
  if (!mpc.Has("relative_goal")) return;
  const Reader& r = mpc.reader();
  const std::string path = mpc.Path("relative_goal");
  const std::vector<MapEntry> entries =
      r.Entries(mpc.Get("relative_goal"), path, "a map {joint: goal or [goals]}");
  for (const MapEntry& e : entries) {
    const std::string joint_path = Join(path, e.key);
    std::vector<int> positions;  // the joint's relative coordinates, in `relative` order
    if (model.HasJoint(e.key)) {
      const JointIndex j = model.GetJointIndex(e.key);
      const int start = model.position_start(j), end = start + model.joint_nq(j);
      for (int p : c->relative_positions) {
        if (p >= start && p < end) positions.push_back(p);
      }
    }
    if (positions.empty()) {
      r.FailValue(e.key_node, joint_path, "'" + e.key + "'", "a joint listed in mpc.relative");
    }
    const int n = static_cast<int>(positions.size());
    if (e.value.IsScalar() && n == 1) {
      c->relative_goals.push_back({positions[0], r.Double(e.value, joint_path)});
      continue;
    }
    const Eigen::VectorXd goals = r.Vector(e.value, joint_path, n);
    for (int k = 0; k < n; ++k) c->relative_goals.push_back({positions[k], goals(k)});
  }
}

/// model_mass_scale: {body: factor > 0}: the controller's model with those bodies' masses and
/// rotational inertias scaled (ScaleBodyInertias); empty without the key.
std::optional<Model> ReadModelMassScale(const MapReader& mpc, const Model& model) {
  if (!mpc.Has("model_mass_scale")) return std::nullopt;
  const Reader& r = mpc.reader();
  const std::string path = mpc.Path("model_mass_scale");
  const std::string expected = "a map {body: mass factor > 0}";
  const std::vector<MapEntry> entries = r.Entries(mpc.Get("model_mass_scale"), path, expected);
  if (entries.empty()) r.FailValue(mpc.Get("model_mass_scale"), path, "an empty map", expected);
  std::vector<double> scale(static_cast<size_t>(model.num_bodies()), 1.0);
  for (const MapEntry& e : entries) {
    if (!model.HasBody(e.key) || model.GetBodyIndex(e.key) == kWorldBody) {
      r.FailValue(e.key_node, Join(path, e.key), "'" + e.key + "'",
                  "a body of the scene other than the world");
    }
    scale[static_cast<size_t>(model.GetBodyIndex(e.key))] = r.Positive(e.value, Join(path, e.key));
  }
  return ScaleBodyInertias(model, scale);
}

/// orientation_lead: {floating joint: largest lead angle in rad}.
void ReadOrientationLeads(const MapReader& mpc, const Model& model, mpc::MpcOptions* c) {
  if (!mpc.Has("orientation_lead")) return;
  const Reader& r = mpc.reader();
  const std::string path = mpc.Path("orientation_lead");
  const std::string expected = "a map {floating joint: largest lead in rad}";
  const std::vector<MapEntry> entries = r.Entries(mpc.Get("orientation_lead"), path, expected);
  if (entries.empty()) r.FailValue(mpc.Get("orientation_lead"), path, "an empty map", expected);
  for (const MapEntry& e : entries) {
    if (!model.HasJoint(e.key) ||
        model.joint_type(model.GetJointIndex(e.key)) != JointType::kFloating) {
      r.FailValue(e.key_node, Join(path, e.key), "'" + e.key + "'",
                  "a floating joint of the scene (its quaternion)");
    }
    mpc::MpcOptions::OrientationLead lead;
    lead.position_start = model.position_start(model.GetJointIndex(e.key));
    lead.max_angle = r.Positive(e.value, Join(path, e.key));
    c->orientation_leads.push_back(lead);
  }
}

/// hold: {joint, squeeze: {tip body: m}, enter, predict, exit, rest_exit, distance, refresh,
/// seek_rate, seek_step, seek_max} (mpc::MpcOptions::Hold; the controller checks the values).
void ReadHold(const MapReader& mpc, const Model& model, mpc::MpcOptions* c) {
  if (!mpc.Has("hold")) return;
  const Reader& r = mpc.reader();
  const MapReader h(r, mpc.Get("hold"), mpc.Path("hold"),
                    {"joint", "squeeze", "enter", "predict", "exit", "rest_exit", "distance",
                     "refresh", "seek_rate", "seek_step", "seek_max"});
  const std::string joint = r.String(h.Require("joint"), h.Path("joint"));
  if (!model.HasJoint(joint) ||
      model.joint_type(model.GetJointIndex(joint)) != JointType::kFloating) {
    r.FailValue(h.Get("joint"), h.Path("joint"), "'" + joint + "'", "a floating joint");
  }
  mpc::MpcOptions::Hold& o = c->hold;
  o.position_start = model.position_start(model.GetJointIndex(joint));
  o.enter_angle = h.Positive("enter", o.enter_angle);
  o.exit_angle = h.Positive("exit", o.exit_angle);
  o.predict = h.NonNegative("predict", o.predict);
  o.distance = h.Positive("distance", o.distance);
  o.refresh = h.NonNegative("refresh", o.refresh);
  o.seek_rate = h.NonNegative("seek_rate", o.seek_rate);
  o.seek_step = h.NonNegative("seek_step", o.seek_step);
  o.seek_max = h.NonNegative("seek_max", o.seek_max);
  o.rest_exit_angle = h.NonNegative("rest_exit", o.rest_exit_angle);
  for (const MapEntry& e : r.Entries(h.Require("squeeze"), h.Path("squeeze"), "a map")) {
    if (!model.HasBody(e.key)) {
      r.FailValue(e.key_node, Join(h.Path("squeeze"), e.key), "'" + e.key + "'", "a body");
    }
    o.tips.push_back(model.GetBodyIndex(e.key));
    o.squeeze.push_back(r.Double(e.value, Join(h.Path("squeeze"), e.key)));
  }
}

/// builtin_contact: the built-in plant's contact law (keys absent keep the plant's defaults,
/// except the friction coefficient, which stays the scene's as without the key).
void ReadBuiltinContact(const MapReader& mpc, sim::BuiltinPlantOptions* builtin) {
  if (!mpc.Has("builtin_contact")) return;
  const MapReader b(mpc.reader(), mpc.Get("builtin_contact"), mpc.Path("builtin_contact"),
                    kBuiltinContactKeys);
  ContactParameters& p = builtin->contact;
  const double scene_friction = p.friction_coefficient;
  p = sim::BuiltinPlantOptions{}.contact;
  p.friction_coefficient = scene_friction;
  p.stiffness = b.Positive("stiffness", p.stiffness);
  p.smoothing = b.Positive("smoothing", p.smoothing);
  p.dissipation_velocity = b.Positive("dissipation_velocity", p.dissipation_velocity);
  p.friction_coefficient = b.NonNegative("friction_coefficient", p.friction_coefficient);
  p.stiction_velocity = b.Positive("stiction_velocity", p.stiction_velocity);
}

/// disturbances: [{body, start, duration, force: [fx, fy, fz]}].
void ReadDisturbances(const MapReader& mpc, const Model& model, mpc::ClosedLoopOptions* cl) {
  if (!mpc.Has("disturbances")) return;
  const Reader& r = mpc.reader();
  const YAML::Node list = mpc.Get("disturbances");
  if (!list.IsSequence()) {
    r.FailValue(list, mpc.Path("disturbances"), Describe(list),
                "a list of {body, start, duration, force: [fx, fy, fz]}");
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const MapReader d(r, list[i], At(mpc.Path("disturbances"), i), kDisturbanceKeys);
    mpc::Disturbance disturbance;
    const std::string body = r.String(d.Require("body"), d.Path("body"));
    if (!model.HasBody(body)) {
      r.FailValue(d.Get("body"), d.Path("body"), "'" + body + "'", "a body of the scene");
    }
    disturbance.body = model.GetBodyIndex(body);
    disturbance.start = d.NonNegative("start", disturbance.start);
    // Required: a push without a duration would never act.
    disturbance.duration = r.Positive(d.Require("duration"), d.Path("duration"));
    disturbance.force_W = r.Vector3(d.Require("force"), d.Path("force"));
    cl->disturbances.push_back(disturbance);
  }
}

/// The controller, plant and closed-loop keys of `mpc`.
MpcConfig ReadMpcConfig(const MapReader& mpc, const ExampleConfig& config) {
  const Model& model = config.model;
  MpcConfig m = DefaultMpcConfig(model, config.problem.contact);
  ReadScalars(mpc, &m);
  ReadLatency(mpc, &m.closed_loop);
  ReadNoiseAndJitter(mpc, &m.closed_loop);
  const JointVectorReader gains(mpc.reader(), model);
  using Space = JointVectorReader::Space;
  if (mpc.Has("kp")) {
    m.controller.gains.Kp =
        gains.Read(mpc.Get("kp"), mpc.Path("kp"), Space::kVelocities, m.controller.gains.Kp, true);
  }
  if (mpc.Has("kd")) {
    m.controller.gains.Kd =
        gains.Read(mpc.Get("kd"), mpc.Path("kd"), Space::kVelocities, m.controller.gains.Kd, true);
  }
  ReadRelative(mpc, model, &m.controller);
  ReadRelativeGoals(mpc, model, &m.controller);
  ReadOrientationLeads(mpc, model, &m.controller);
  ReadHold(mpc, model, &m.controller);
  ReadEstimator(mpc, &m.controller);
  ReadBuiltinContact(mpc, &m.builtin);
  ReadDisturbances(mpc, model, &m.closed_loop);
  try {
    m.controller.Validate(model);
  } catch (const std::exception& e) {
    mpc.reader().Fail(mpc.node(), mpc.path(), e.what());
  }
  return m;
}

}  // namespace

void ConfigLoader::LoadMpc(const YAML::Node& node, const YAML::Node& open_loop_problem) {
  const MapReader mpc(reader_, node, "mpc", kMpcKeys);
  // The controller's own contact law (parameters, and per-pair overrides after the scene's; the
  // scene's pair filters stay) and problem, when given.
  if (mpc.Has("problem") || mpc.Has("contact")) {
    const ContactOptions scene_contact = contact_;
    if (mpc.Has("contact")) {
      LoadMpcContact(mpc.Get("contact"), mpc.Path("contact"));
    }
    LoadMpcProblem(open_loop_problem,
                   mpc.Has("problem") ? mpc.Get("problem") : YAML::Node(YAML::NodeType::Map));
    contact_ = scene_contact;
  }
  // The controller's solver options: the open loop's with the keys of mpc.solver over them.
  if (mpc.Has("solver")) {
    const SolverOptions open_loop = config_.solver;
    LoadSolver(mpc.Get("solver"), mpc.Path("solver"));
    config_.mpc_solver = config_.solver;
    config_.solver = open_loop;
  }
  config_.mpc_model = ReadModelMassScale(mpc, config_.model);
  config_.mpc = ReadMpcConfig(mpc, config_);
}

}  // namespace config_internal

MpcConfig ParseMpcConfig(const ExampleConfig& config) {
  if (config.mpc.has_value()) return *config.mpc;
  return config_internal::DefaultMpcConfig(config.model, config.problem.contact);
}

const Model& ControllerModel(const ExampleConfig& config) {
  return config.mpc_model ? *config.mpc_model : config.model;
}

const ProblemDefinition& ControllerProblem(const ExampleConfig& config) {
  return config.mpc_problem ? *config.mpc_problem : config.problem;
}

}  // namespace idto
