#include "idto/parsers/mpc_config.hpp"

#include <cmath>
#include <cstdlib>
#include <set>
#include <string>

#include <yaml-cpp/yaml.h>

#include "idto/core/errors.hpp"

namespace idto {

namespace {

struct Context {
  const ExampleConfig& config;
  [[noreturn]] void Fail(const std::string& key, const YAML::Node& node,
                         const std::string& problem) const {
    std::string where = "mpc." + key;
    if (node.IsDefined() && node.Mark().line >= 0) {
      where += " (line " + std::to_string(node.Mark().line + 1) + ")";
    }
    ThrowFileError(config.source_file, where, problem);
  }
};

std::string Describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "empty";
  if (node.IsScalar()) return "\"" + node.Scalar() + "\"";
  return node.IsSequence() ? "a list" : "a map";
}

double Number(const Context& c, const std::string& key, const YAML::Node& node) {
  double x;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, x) || !std::isfinite(x)) {
    c.Fail(key, node, "is " + Describe(node) + "; expected a finite number");
  }
  return x;
}

double Positive(const Context& c, const std::string& key, const YAML::Node& node) {
  const double x = Number(c, key, node);
  if (!(x > 0.0)) c.Fail(key, node, "is " + FormatValue(x) + "; expected a positive number");
  return x;
}

double NonNegative(const Context& c, const std::string& key, const YAML::Node& node) {
  const double x = Number(c, key, node);
  if (!(x >= 0.0)) c.Fail(key, node, "is " + FormatValue(x) + "; expected a number >= 0");
  return x;
}

// A per-velocity vector: a number (every entry), a list of nv, or {default: x, joint: value}.
Eigen::VectorXd VelocityVector(const Context& c, const std::string& key, const YAML::Node& node) {
  const Model& model = c.config.model;
  const int nv = model.nv();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(nv);
  if (node.IsScalar()) {
    x.setConstant(NonNegative(c, key, node));
  } else if (node.IsSequence()) {
    if (static_cast<int>(node.size()) != nv) {
      c.Fail(key, node,
             "is a list of " + std::to_string(node.size()) + " entries; expected nv = " +
                 std::to_string(nv) + " numbers, a number, or {default: x, <joint>: value}");
    }
    for (int i = 0; i < nv; ++i)
      x(i) = NonNegative(c, key + "[" + std::to_string(i) + "]", node[i]);
  } else if (node.IsMap()) {
    for (const auto& kv : node) {
      const std::string name = kv.first.as<std::string>();
      if (name == "default") continue;
      if (!model.HasJoint(name)) {
        c.Fail(key + "." + name, kv.first, "is not a joint of the scene");
      }
    }
    if (node["default"]) x.setConstant(NonNegative(c, key + ".default", node["default"]));
    for (const auto& kv : node) {
      const std::string name = kv.first.as<std::string>();
      if (name == "default") continue;
      const JointIndex j = model.GetJointIndex(name);
      const int iv = model.velocity_start(j), n = model.joint_nv(j);
      if (kv.second.IsSequence()) {
        if (static_cast<int>(kv.second.size()) != n) {
          c.Fail(key + "." + name, kv.second,
                 "has " + std::to_string(kv.second.size()) + " entries; expected " +
                     std::to_string(n) + " (the joint's DoFs)");
        }
        for (int k = 0; k < n; ++k) {
          x(iv + k) = NonNegative(c, key + "." + name, kv.second[k]);
        }
      } else {
        x.segment(iv, n).setConstant(NonNegative(c, key + "." + name, kv.second));
      }
    }
  } else {
    c.Fail(key, node, "is " + Describe(node) + "; expected a number, a list or a map");
  }
  return x;
}

}  // namespace

MpcConfig ParseMpcConfig(const ExampleConfig& config) {
  MpcConfig m;
  const Context c{config};
  const Model& model = config.model;
  m.plant = sim::HaveMujoco() ? "mujoco" : "builtin";
  m.builtin.pairs = config.problem.contact;
  m.mujoco.pairs = config.problem.contact;
  m.mujoco.friction_coefficient = config.problem.contact.parameters.friction_coefficient;
  m.controller.gains.Kp = Eigen::VectorXd::Zero(model.nv());
  m.controller.gains.Kd = Eigen::VectorXd::Zero(model.nv());
  if (config.mpc.empty()) return m;
  YAML::Node root;
  try {
    root = YAML::Load(config.mpc);
  } catch (const YAML::Exception& e) {
    ThrowFileError(config.source_file, "mpc", std::string("is not valid YAML: ") + e.what());
  }
  if (!root.IsMap()) c.Fail("", root, "is " + Describe(root) + "; expected a map");
  static const std::set<std::string> kKeys = {
      "control_rate", "iterations_per_step", "duration", "initial_iterations", "plant",
      "plant_time_step", "latency", "kp", "kd", "relative", "orientation_lead", "builtin_contact",
      "mujoco_friction", "mujoco_torsional_friction", "mujoco_rolling_friction", "disturbances",
      // parsed by LoadExampleConfig:
      "problem", "contact", "solver"};
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (!kKeys.count(key)) {
      std::string allowed;
      for (const std::string& k : kKeys) allowed += (allowed.empty() ? "" : ", ") + k;
      c.Fail(key, kv.first, "is not a known key; expected one of: " + allowed);
    }
  }
  if (root["control_rate"])
    m.controller.control_rate = Positive(c, "control_rate", root["control_rate"]);
  if (root["iterations_per_step"]) {
    const double it = Positive(c, "iterations_per_step", root["iterations_per_step"]);
    if (it != std::floor(it)) {
      c.Fail("iterations_per_step", root["iterations_per_step"], "is not an integer");
    }
    m.controller.iterations_per_step = static_cast<int>(it);
  }
  if (root["duration"]) m.closed_loop.duration = Positive(c, "duration", root["duration"]);
  if (root["initial_iterations"]) {
    m.initial_iterations =
        static_cast<int>(NonNegative(c, "initial_iterations", root["initial_iterations"]));
  }
  if (root["plant"]) {
    const std::string p = root["plant"].as<std::string>();
    if (p != "mujoco" && p != "builtin") {
      c.Fail("plant", root["plant"], "is \"" + p + "\"; expected mujoco or builtin");
    }
    m.plant = p;
  }
  if (root["plant_time_step"]) {
    m.closed_loop.plant_time_step = Positive(c, "plant_time_step", root["plant_time_step"]);
  }
  m.builtin.time_step = m.closed_loop.plant_time_step;
  m.mujoco.time_step = m.closed_loop.plant_time_step;
  if (root["latency"]) {
    const std::string l = root["latency"].as<std::string>();
    if (l == "solve_time") {
      m.closed_loop.latency = mpc::LatencyModel::kSolveTime;
    } else if (l == "control_period") {
      m.closed_loop.latency = mpc::LatencyModel::kControlPeriod;
    } else {
      // A number: a fixed delay in seconds (reproducible runs).
      char* end = nullptr;
      const double seconds = std::strtod(l.c_str(), &end);
      if (l.empty() || end != l.c_str() + l.size() || !std::isfinite(seconds) || seconds < 0.0) {
        c.Fail("latency", root["latency"],
               "is \"" + l + "\"; expected solve_time, control_period or a delay in seconds >= 0");
      }
      m.closed_loop.latency = mpc::LatencyModel::kFixed;
      m.closed_loop.fixed_latency = seconds;
    }
  }
  if (root["kp"]) m.controller.gains.Kp = VelocityVector(c, "kp", root["kp"]);
  if (root["kd"]) m.controller.gains.Kd = VelocityVector(c, "kd", root["kd"]);
  if (root["relative"]) {
    const YAML::Node r = root["relative"];
    if (!r.IsSequence()) c.Fail("relative", r, "is " + Describe(r) + "; expected a list of joints");
    // Each entry: a joint name (all its position coordinates) or {joint: [coordinate indices
    // within the joint]} (e.g. only a floating base's x and y).
    for (size_t i = 0; i < r.size(); ++i) {
      const std::string path = "relative[" + std::to_string(i) + "]";
      const YAML::Node entry = r[i];
      std::string name;
      YAML::Node coords;
      bool has_coords = false;
      if (entry.IsScalar()) {
        name = entry.as<std::string>();
      } else if (entry.IsMap() && entry.size() == 1) {
        name = entry.begin()->first.as<std::string>();
        coords = entry.begin()->second;
        has_coords = true;
      } else {
        c.Fail(path, entry,
               "is " + Describe(entry) +
                   "; expected a joint name or {joint: [coordinate indices within the joint]}");
      }
      if (!model.HasJoint(name)) {
        c.Fail(path, entry, "is \"" + name + "\"; expected a joint of the scene");
      }
      const JointIndex j = model.GetJointIndex(name);
      const int nq_j = model.joint_nq(j);
      if (!has_coords) {
        for (int k = 0; k < nq_j; ++k) {
          m.controller.relative_positions.push_back(model.position_start(j) + k);
        }
        continue;
      }
      if (!coords.IsSequence() || coords.size() == 0) {
        c.Fail(path + "." + name, coords,
               "is " + Describe(coords) + "; expected a non-empty list of coordinate indices");
      }
      for (size_t k = 0; k < coords.size(); ++k) {
        const std::string cpath = path + "." + name + "[" + std::to_string(k) + "]";
        int index = -1;
        try {
          index = coords[k].as<int>();
        } catch (const YAML::Exception&) {
          c.Fail(cpath, coords[k], "is " + Describe(coords[k]) + "; expected an integer");
        }
        if (index < 0 || index >= nq_j) {
          c.Fail(cpath, coords[k],
                 "is " + std::to_string(index) + "; expected a coordinate index in [0, " +
                     std::to_string(nq_j) + ") of joint \"" + name + "\"");
        }
        m.controller.relative_positions.push_back(model.position_start(j) + index);
      }
    }
  }
  if (root["orientation_lead"]) {
    const YAML::Node o = root["orientation_lead"];
    if (!o.IsMap() || o.size() == 0) {
      c.Fail("orientation_lead", o,
             "is " + Describe(o) + "; expected a map {floating joint: largest lead in rad}");
    }
    for (const auto& kv : o) {
      const std::string name = kv.first.as<std::string>();
      const std::string path = "orientation_lead." + name;
      if (!model.HasJoint(name) ||
          model.joint_type(model.GetJointIndex(name)) != JointType::kFloating) {
        c.Fail(path, kv.first,
               "is \"" + name + "\"; expected a floating joint of the scene (its quaternion)");
      }
      mpc::MpcOptions::OrientationLead lead;
      lead.position_start = model.position_start(model.GetJointIndex(name));
      lead.max_angle = Positive(c, path, kv.second);
      m.controller.orientation_leads.push_back(lead);
    }
  }
  if (root["builtin_contact"]) {
    const YAML::Node b = root["builtin_contact"];
    if (!b.IsMap()) c.Fail("builtin_contact", b, "is " + Describe(b) + "; expected a map");
    ContactParameters& p = m.builtin.contact;
    for (const auto& kv : b) {
      const std::string key = kv.first.as<std::string>();
      const std::string path = "builtin_contact." + key;
      if (key == "stiffness") {
        p.stiffness = Positive(c, path, kv.second);
      } else if (key == "smoothing") {
        p.smoothing = Positive(c, path, kv.second);
      } else if (key == "dissipation_velocity") {
        p.dissipation_velocity = Positive(c, path, kv.second);
      } else if (key == "friction_coefficient") {
        p.friction_coefficient = NonNegative(c, path, kv.second);
      } else if (key == "stiction_velocity") {
        p.stiction_velocity = Positive(c, path, kv.second);
      } else {
        c.Fail(path, kv.first,
               "is not a known key; expected stiffness, smoothing, dissipation_velocity, "
               "friction_coefficient or stiction_velocity");
      }
    }
  } else {
    m.builtin.contact.friction_coefficient = config.problem.contact.parameters.friction_coefficient;
  }
  if (root["mujoco_friction"]) {
    m.mujoco.friction_coefficient = NonNegative(c, "mujoco_friction", root["mujoco_friction"]);
  }
  if (root["mujoco_torsional_friction"]) {
    m.mujoco.torsional_friction =
        NonNegative(c, "mujoco_torsional_friction", root["mujoco_torsional_friction"]);
  }
  if (root["mujoco_rolling_friction"]) {
    m.mujoco.rolling_friction =
        NonNegative(c, "mujoco_rolling_friction", root["mujoco_rolling_friction"]);
  }
  if (root["disturbances"]) {
    const YAML::Node d = root["disturbances"];
    if (!d.IsSequence()) c.Fail("disturbances", d, "is " + Describe(d) + "; expected a list");
    for (size_t i = 0; i < d.size(); ++i) {
      const std::string key = "disturbances[" + std::to_string(i) + "]";
      const YAML::Node e = d[i];
      if (!e.IsMap() || !e["body"] || !e["force"]) {
        c.Fail(key, e,
               "is " + Describe(e) + "; expected {body, start, duration, force: [fx, fy, fz]}");
      }
      mpc::Disturbance dist;
      const std::string body = e["body"].as<std::string>();
      if (!model.HasBody(body))
        c.Fail(key + ".body", e["body"], "is \"" + body + "\"; expected a body of the scene");
      dist.body = model.GetBodyIndex(body);
      if (e["start"]) dist.start = NonNegative(c, key + ".start", e["start"]);
      if (e["duration"]) dist.duration = Positive(c, key + ".duration", e["duration"]);
      const YAML::Node f = e["force"];
      if (!f.IsSequence() || f.size() != 3)
        c.Fail(key + ".force", f, "is " + Describe(f) + "; expected [fx, fy, fz] in N");
      for (int k = 0; k < 3; ++k) dist.force_W(k) = Number(c, key + ".force", f[k]);
      m.closed_loop.disturbances.push_back(dist);
    }
  }
  m.controller.Validate(model);
  return m;
}

}  // namespace idto
