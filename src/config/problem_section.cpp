// The `problem` section (time step, horizon, initial state, nominal trajectory, weights,
// unactuated DoFs, initial guess) and `mpc.problem` (the controller's departures from it).

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "config_loader.hpp"
#include "idto/core/errors.hpp"
#include "joint_vector_reader.hpp"

namespace idto::config_internal {

namespace {

using Space = JointVectorReader::Space;

const std::vector<std::string> kProblemKeys = {
    "time_step", "horizon", "num_steps",       "q_init",        "v_init",
    "nominal",   "weights", "unactuated_dofs", "initial_guess", "limits"};
const std::vector<std::string> kLimitKeys = {"position_weight", "velocity_weight", "effort_weight",
                                             "velocity", "effort"};
const std::vector<std::string> kNominalKeys = {"q_nom", "v_nom", "q_start", "q_end"};
const std::vector<std::string> kWeightKeys = {"Qq", "Qv", "R", "Qfq", "Qfv"};

static_assert(static_cast<int>(InitialGuessType::kInterpolate) == 0 &&
                  static_cast<int>(InitialGuessType::kConstant) == 1 &&
                  static_cast<int>(InitialGuessType::kNominal) == 2,
              "InitialGuessType order");

/// `base` with the entries of `overrides` put over it (a new map; the values are the nodes of
/// the file, so their marks, and the line numbers of messages, are kept).
YAML::Node MergeMaps(const YAML::Node& base, const YAML::Node& overrides) {
  YAML::Node merged(YAML::NodeType::Map);
  for (const YAML::Node& map : {base, overrides}) {
    if (!map.IsMap()) continue;
    for (auto it = map.begin(); it != map.end(); ++it) merged[it->first.Scalar()] = it->second;
  }
  return merged;
}

}  // namespace

void ConfigLoader::LoadProblem(const YAML::Node& node, const std::string& path) {
  const MapReader p(reader_, node, path, kProblemKeys);
  const Model& model = config_.model;
  ProblemDefinition& problem = config_.problem;
  const JointVectorReader joints(reader_, model);

  problem.time_step = reader_.Positive(p.Require("time_step"), p.Path("time_step"));
  ReadHorizon(p, &problem);
  problem.q_init = model.NeutralConfiguration();
  if (p.Has("q_init")) {
    problem.q_init =
        joints.Read(p.Get("q_init"), p.Path("q_init"), Space::kPositions, problem.q_init, false);
  }
  problem.v_init = Eigen::VectorXd::Zero(model.nv());
  if (p.Has("v_init")) {
    problem.v_init =
        joints.Read(p.Get("v_init"), p.Path("v_init"), Space::kVelocities, problem.v_init, false);
  }
  ReadNominal(p, &problem);
  ReadWeights(p, &problem);
  ReadUnactuatedDofs(p, &problem);
  ReadLimits(p, &problem);
  config_.initial_guess =
      static_cast<InitialGuessType>(p.Enum("initial_guess", {"interpolate", "constant", "nominal"},
                                           static_cast<int>(InitialGuessType::kInterpolate)));
  problem.enable_contact = enable_contact_;
  problem.contact = contact_;
  try {
    problem.Validate(model);
  } catch (const std::exception& e) {
    reader_.Fail(p.node(), path, e.what());
  }
}

void ConfigLoader::ReadHorizon(const MapReader& p, ProblemDefinition* problem) const {
  if (p.Has("horizon") == p.Has("num_steps")) {
    reader_.Fail(p.Has("horizon") ? p.Get("num_steps") : p.node(), p.Path("horizon"),
                 p.Has("horizon") ? "given together with num_steps; expected one of them"
                                  : "missing; expected horizon (s) or num_steps");
  }
  // The same limit in both spellings (10^7 steps: far beyond any horizon a solve can hold).
  constexpr int kMaxNumSteps = 10000000;
  if (p.Has("num_steps")) {
    problem->num_steps = p.Int("num_steps", 1, 1);
    if (problem->num_steps > kMaxNumSteps) {
      reader_.FailValue(p.Get("num_steps"), p.Path("num_steps"), std::to_string(problem->num_steps),
                        "an integer from 1 to " + std::to_string(kMaxNumSteps));
    }
    return;
  }
  const double horizon = p.Positive("horizon", 1.0);
  const double ratio = horizon / problem->time_step;
  const double steps = std::round(ratio);
  if (!(steps >= 1.0) || std::abs(ratio - steps) > 1e-9 * std::max(1.0, ratio) ||
      steps > kMaxNumSteps) {
    reader_.FailValue(p.Get("horizon"), p.Path("horizon"), FormatValue(horizon),
                      "a positive multiple of time_step = " + FormatValue(problem->time_step) +
                          ", at most " + std::to_string(kMaxNumSteps) +
                          " steps (horizon / time_step = " + FormatValue(ratio) + ")");
  }
  problem->num_steps = static_cast<int>(steps);
}

// Nominal trajectory: constant q_nom, or q_start -> q_end interpolated over k = 0..N.
void ConfigLoader::ReadNominal(const MapReader& p, ProblemDefinition* problem) const {
  const Model& model = config_.model;
  const JointVectorReader joints(reader_, model);
  const int N = problem->num_steps;
  Eigen::VectorXd q_start = problem->q_init;
  Eigen::VectorXd q_end = problem->q_init;
  Eigen::VectorXd v_nom = Eigen::VectorXd::Zero(model.nv());
  if (p.Has("nominal")) {
    const MapReader n(reader_, p.Get("nominal"), p.Path("nominal"), kNominalKeys);
    if (n.Has("q_nom") && (n.Has("q_start") || n.Has("q_end"))) {
      reader_.Fail(n.Get("q_nom"), n.Path("q_nom"),
                   "given together with q_start/q_end; expected either a constant q_nom or "
                   "an interpolation q_start -> q_end");
    }
    if (n.Has("q_nom")) {
      q_start =
          joints.Read(n.Get("q_nom"), n.Path("q_nom"), Space::kPositions, problem->q_init, false);
    }
    if (n.Has("q_start")) {
      q_start = joints.Read(n.Get("q_start"), n.Path("q_start"), Space::kPositions, problem->q_init,
                            false);
    }
    q_end = q_start;
    if (n.Has("q_end")) {
      q_end = joints.Read(n.Get("q_end"), n.Path("q_end"), Space::kPositions, q_start, false);
    }
    if (n.Has("v_nom")) {
      v_nom = joints.Read(n.Get("v_nom"), n.Path("v_nom"), Space::kVelocities, v_nom, false);
    }
  }
  problem->q_nom.resize(N + 1);
  problem->v_nom.assign(N + 1, v_nom);
  for (int k = 0; k <= N; ++k) {
    problem->q_nom[k] = InterpolateConfiguration(model, q_start, q_end, static_cast<double>(k) / N);
  }
}

// Joint limits as penalties (off unless a weight is given): position bounds from the model
// (URDF <limit>); velocity and effort maxima from the model unless given here.
void ConfigLoader::ReadLimits(const MapReader& p, ProblemDefinition* problem) const {
  problem->limits = LimitPenalties{};
  if (!p.Has("limits")) return;
  const Model& model = config_.model;
  const JointVectorReader joints(reader_, model);
  const MapReader l(reader_, p.Get("limits"), p.Path("limits"), kLimitKeys);
  LimitPenalties& limits = problem->limits;
  limits.position_weight = l.NonNegative("position_weight", 0.0);
  limits.velocity_weight = l.NonNegative("velocity_weight", 0.0);
  limits.effort_weight = l.NonNegative("effort_weight", 0.0);
  if (l.Has("velocity")) {
    limits.v_max = joints.Read(l.Get("velocity"), l.Path("velocity"), Space::kVelocities,
                               model.velocity_limits(), true);
  }
  if (l.Has("effort")) {
    limits.tau_max = joints.Read(l.Get("effort"), l.Path("effort"), Space::kVelocities,
                                 model.effort_limits(), true);
  }
}

// Weights (default zero).
void ConfigLoader::ReadWeights(const MapReader& p, ProblemDefinition* problem) const {
  const Model& model = config_.model;
  const JointVectorReader joints(reader_, model);
  problem->Qq = Eigen::VectorXd::Zero(model.nq());
  problem->Qfq = Eigen::VectorXd::Zero(model.nq());
  problem->Qv = Eigen::VectorXd::Zero(model.nv());
  problem->R = Eigen::VectorXd::Zero(model.nv());
  problem->Qfv = Eigen::VectorXd::Zero(model.nv());
  if (!p.Has("weights")) return;
  const MapReader w(reader_, p.Get("weights"), p.Path("weights"), kWeightKeys);
  const auto read = [&](const char* key, Space space, Eigen::VectorXd* out) {
    if (w.Has(key)) *out = joints.Read(w.Get(key), w.Path(key), space, *out, true);
  };
  read("Qq", Space::kPositions, &problem->Qq);
  read("Qv", Space::kVelocities, &problem->Qv);
  read("R", Space::kVelocities, &problem->R);
  read("Qfq", Space::kPositions, &problem->Qfq);
  read("Qfv", Space::kVelocities, &problem->Qfv);
}

// Unactuated DoFs: the base DoFs plus the joints (or velocity indices) listed.
void ConfigLoader::ReadUnactuatedDofs(const MapReader& p, ProblemDefinition* problem) const {
  if (!p.Has("unactuated_dofs")) return;
  const Model& model = config_.model;
  const YAML::Node list = p.Get("unactuated_dofs");
  const std::string path = p.Path("unactuated_dofs");
  if (!list.IsSequence()) {
    reader_.FailValue(list, path, Describe(list), "a list of joint names (or velocity indices)");
  }
  std::set<int> dofs;
  for (int i = 0; i < model.nv(); ++i) {
    if (model.is_base_velocity()[i]) dofs.insert(i);
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node entry = list[i];
    const std::string entry_path = At(path, i);
    if (!entry.IsScalar()) reader_.FailValue(entry, entry_path, Describe(entry), "a joint name");
    const std::string text = Trim(entry.Scalar());
    if (model.HasJoint(text)) {
      const JointIndex j = model.GetJointIndex(text);
      if (model.joint_nv(j) == 0) {
        reader_.Fail(entry, entry_path, "joint '" + text + "' is fixed and has no DoFs");
      }
      for (int d = 0; d < model.joint_nv(j); ++d) dofs.insert(model.velocity_start(j) + d);
      continue;
    }
    char* end = nullptr;
    const long index = std::strtol(text.c_str(), &end, 10);
    if (!text.empty() && end == text.c_str() + text.size()) {
      if (index < 0 || index >= model.nv()) {
        reader_.FailValue(entry, entry_path, text,
                          "a velocity index in [0, " + std::to_string(model.nv()) + ")");
      }
      dofs.insert(static_cast<int>(index));
      continue;
    }
    reader_.FailValue(entry, entry_path, "'" + text + "'",
                      "a joint name (" + JointVectorReader(reader_, model).JointNames() +
                          ") or a velocity index");
  }
  problem->unactuated_dofs = std::vector<int>(dofs.begin(), dofs.end());
}

// The controller's problem: `problem` with the keys of `mpc.problem` replacing the open-loop
// ones; `nominal` and `weights` are merged key by key (e.g. only a new q_end), and a horizon or
// num_steps replaces both of the open loop's.
void ConfigLoader::LoadMpcProblem(const YAML::Node& problem, const YAML::Node& overrides) {
  const MapReader check(reader_, overrides, "mpc.problem", kProblemKeys);
  YAML::Node merged = MergeMaps(problem, YAML::Node(YAML::NodeType::Map));
  // horizon and num_steps are two spellings of one length: the controller's replaces the open
  // loop's in either spelling (both in mpc.problem is still an error).
  if (overrides["horizon"] || overrides["num_steps"]) {
    merged.remove("horizon");
    merged.remove("num_steps");
  }
  for (auto it = overrides.begin(); it != overrides.end(); ++it) {
    const std::string key = it->first.Scalar();
    const bool merge = (key == "nominal" || key == "weights") && it->second.IsMap() &&
                       merged[key] && merged[key].IsMap();
    merged[key] = merge ? MergeMaps(merged[key], it->second) : it->second;
  }
  ProblemDefinition open_loop = std::move(config_.problem);
  const InitialGuessType guess = config_.initial_guess;
  LoadProblem(merged, "mpc.problem");
  config_.mpc_problem = std::move(config_.problem);
  config_.problem = std::move(open_loop);
  if (overrides["initial_guess"]) config_.mpc_initial_guess = config_.initial_guess;
  config_.initial_guess = guess;
}

}  // namespace idto::config_internal
