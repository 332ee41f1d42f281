#include "idto/parsers/config.hpp"

// YAML example configurations -> Model + ProblemDefinition + SolverOptions.
//
// Every map is read through MapReader, which rejects unknown and duplicate keys up front, so
// that a typo is always reported (with the keys that are allowed) rather than silently ignored.
// Every error goes through Reader::Fail, which formats "<file>: <key path>: <problem> (line L)"
// as a FileError. The key path spells maps with dots and lists with [i]:
// "scene.models[0].position", "problem.weights.Qq.elbow".

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Geometry>

#include "idto/core/errors.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "idto/multibody/model_builder.hpp"

namespace idto {
namespace {

namespace fs = std::filesystem;

std::string Join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string At(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

std::string JoinNames(const std::vector<std::string>& names, std::size_t max_names = 40) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < max_names; ++i) {
    if (i > 0) out += ", ";
    out += names[i];
  }
  if (names.size() > max_names) out += ", ... (" + std::to_string(names.size()) + " in all)";
  return out;
}

std::string Trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r\n");
  return s.substr(begin, end - begin + 1);
}

/// A plain number over the whole string (strtod, C locale).
bool ParsePlainNumber(const std::string& s, double* out) {
  if (s.empty()) return false;
  const char* begin = s.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  if (end != begin + s.size()) return false;
  *out = value;
  return true;
}

/// YAML numbers, YAML's .nan/.inf spellings, and multiples of pi: "pi", "-pi", "2*pi",
/// "pi/2", "-0.5*pi/3" (spaces allowed).
bool ParseNumber(const std::string& text, double* out) {
  std::string s;
  for (char c : text) {
    if (c != ' ' && c != '\t') s.push_back(c);
  }
  if (s.empty()) return false;
  static const std::set<std::string> kNan = {".nan", ".NaN", ".NAN"};
  static const std::set<std::string> kInf = {".inf", ".Inf", ".INF", "+.inf", "+.Inf", "+.INF"};
  static const std::set<std::string> kNegInf = {"-.inf", "-.Inf", "-.INF"};
  if (kNan.count(s)) {
    *out = std::nan("");
    return true;
  }
  if (kInf.count(s)) {
    *out = INFINITY;
    return true;
  }
  if (kNegInf.count(s)) {
    *out = -INFINITY;
    return true;
  }
  const auto pi_pos = s.find("pi");
  if (pi_pos == std::string::npos) return ParsePlainNumber(s, out);
  const std::string prefix = s.substr(0, pi_pos);
  const std::string suffix = s.substr(pi_pos + 2);
  double factor = 1.0;
  if (prefix == "-") {
    factor = -1.0;
  } else if (prefix.empty() || prefix == "+") {
    factor = 1.0;
  } else if (prefix.back() == '*') {
    if (!ParsePlainNumber(prefix.substr(0, prefix.size() - 1), &factor)) return false;
  } else {
    return false;
  }
  double divisor = 1.0;
  if (!suffix.empty()) {
    if (suffix.front() != '/') return false;
    if (!ParsePlainNumber(suffix.substr(1), &divisor) || divisor == 0.0) return false;
  }
  *out = factor * M_PI / divisor;
  return true;
}

/// "'text'", "a list of 3 entries [1, 2, 3]", "a map", "empty".
std::string Describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
      return "missing";
    case YAML::NodeType::Null:
      return "empty";
    case YAML::NodeType::Scalar:
      return "'" + node.Scalar() + "'";
    case YAML::NodeType::Sequence: {
      std::string text =
          "a list of " + std::to_string(node.size()) + (node.size() == 1 ? " entry" : " entries");
      YAML::Emitter emitter;
      emitter << YAML::Flow << node;
      const std::string flow = emitter.good() ? std::string(emitter.c_str()) : std::string();
      if (!flow.empty() && flow.size() <= 80) text += " " + flow;
      return text;
    }
    case YAML::NodeType::Map:
      return "a map";
  }
  return "unknown";
}

/// Reads values and reports errors for one file.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  const std::string& file() const { return file_; }

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& path,
                         const std::string& problem) const {
    std::string text = problem;
    if (node.IsDefined()) {
      const YAML::Mark mark = node.Mark();
      if (mark.line >= 0) text += " (line " + std::to_string(mark.line + 1) + ")";
    }
    ThrowFileError(file_, path, text);
  }

  [[noreturn]] void FailValue(const YAML::Node& node, const std::string& path,
                              const std::string& found, const std::string& expected) const {
    Fail(node, path, "is " + found + "; expected " + expected);
  }

  double Double(const YAML::Node& node, const std::string& path) const {
    if (!node.IsScalar()) FailValue(node, path, Describe(node), "a number");
    double value = 0.0;
    if (!ParseNumber(node.Scalar(), &value)) FailValue(node, path, Describe(node), "a number");
    if (!std::isfinite(value)) FailValue(node, path, FormatValue(value), "a finite number");
    return value;
  }

  double Positive(const YAML::Node& node, const std::string& path) const {
    const double value = Double(node, path);
    if (!(value > 0.0)) FailValue(node, path, FormatValue(value), "a finite positive number");
    return value;
  }

  double NonNegative(const YAML::Node& node, const std::string& path) const {
    const double value = Double(node, path);
    if (!(value >= 0.0)) {
      FailValue(node, path, FormatValue(value), "a finite non-negative number");
    }
    return value;
  }

  int Int(const YAML::Node& node, const std::string& path, int min_value) const {
    const std::string expected = "an integer >= " + std::to_string(min_value);
    if (!node.IsScalar()) FailValue(node, path, Describe(node), expected);
    const std::string text = Trim(node.Scalar());
    char* end = nullptr;
    const long long value = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || end != text.c_str() + text.size() || value > 1000000000LL ||
        value < -1000000000LL) {
      FailValue(node, path, Describe(node), expected);
    }
    if (value < min_value) FailValue(node, path, std::to_string(value), expected);
    return static_cast<int>(value);
  }

  bool Bool(const YAML::Node& node, const std::string& path) const {
    bool value = false;
    if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value)) {
      FailValue(node, path, Describe(node), "true or false");
    }
    return value;
  }

  std::string String(const YAML::Node& node, const std::string& path) const {
    if (!node.IsScalar()) FailValue(node, path, Describe(node), "a string");
    return node.Scalar();
  }

  /// One of `names`; returns its index.
  int Enum(const YAML::Node& node, const std::string& path,
           const std::vector<std::string>& names) const {
    const std::string expected = "one of " + JoinNames(names);
    if (!node.IsScalar()) FailValue(node, path, Describe(node), expected);
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (node.Scalar() == names[i]) return static_cast<int>(i);
    }
    FailValue(node, path, Describe(node), expected);
  }

  /// A list of exactly `size` finite numbers.
  Eigen::VectorXd Vector(const YAML::Node& node, const std::string& path, int size) const {
    const std::string expected =
        "a list of " + std::to_string(size) + (size == 1 ? " number" : " numbers");
    if (!node.IsSequence() || static_cast<int>(node.size()) != size) {
      FailValue(node, path, Describe(node), expected);
    }
    Eigen::VectorXd x(size);
    for (int i = 0; i < size; ++i) x(i) = Double(node[i], At(path, i));
    return x;
  }

  Eigen::Vector3d Vector3(const YAML::Node& node, const std::string& path) const {
    return Vector(node, path, 3);
  }

  /// A list of strings.
  std::vector<std::string> StringList(const YAML::Node& node, const std::string& path) const {
    if (!node.IsSequence()) FailValue(node, path, Describe(node), "a list of names");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < node.size(); ++i) out.push_back(String(node[i], At(path, i)));
    return out;
  }

 private:
  std::string file_;
};

/// A YAML map whose keys have been checked against an allowed list (unknown and duplicate keys
/// are errors).
class MapReader {
 public:
  MapReader(const Reader& reader, const YAML::Node& node, std::string path,
            const std::vector<std::string>& allowed)
      : reader_(reader), node_(node), path_(std::move(path)) {
    if (!node.IsMap()) {
      reader.FailValue(node, path_.empty() ? std::string("(top level)") : path_, Describe(node),
                       "a map with keys " + JoinNames(allowed));
    }
    for (auto it = node.begin(); it != node.end(); ++it) {
      const YAML::Node key = it->first;
      if (!key.IsScalar()) {
        reader.FailValue(key, path_.empty() ? std::string("(top level)") : path_,
                         "a map with key " + Describe(key), "string keys");
      }
      const std::string name = key.Scalar();
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
        reader.Fail(key, Join(path_, name), "unknown key; expected one of " + JoinNames(allowed));
      }
      if (entries_.count(name)) reader.Fail(key, Join(path_, name), "duplicate key");
      entries_.emplace(name, it->second);
    }
  }

  bool Has(const std::string& key) const { return entries_.count(key) > 0; }
  /// The value of `key` (an undefined node when absent).
  YAML::Node Get(const std::string& key) const {
    auto it = entries_.find(key);
    return it == entries_.end() ? YAML::Node(YAML::NodeType::Undefined) : it->second;
  }
  std::string Path(const std::string& key) const { return Join(path_, key); }
  const std::string& path() const { return path_; }
  const YAML::Node& node() const { return node_; }

  /// Fails unless `key` is present.
  YAML::Node Require(const std::string& key) const {
    if (!Has(key)) reader_.Fail(node_, Path(key), "missing (required)");
    return Get(key);
  }

  double Double(const std::string& key, double fallback) const {
    return Has(key) ? reader_.Double(Get(key), Path(key)) : fallback;
  }
  double Positive(const std::string& key, double fallback) const {
    return Has(key) ? reader_.Positive(Get(key), Path(key)) : fallback;
  }
  double NonNegative(const std::string& key, double fallback) const {
    return Has(key) ? reader_.NonNegative(Get(key), Path(key)) : fallback;
  }
  int Int(const std::string& key, int fallback, int min_value) const {
    return Has(key) ? reader_.Int(Get(key), Path(key), min_value) : fallback;
  }
  bool Bool(const std::string& key, bool fallback) const {
    return Has(key) ? reader_.Bool(Get(key), Path(key)) : fallback;
  }
  std::string String(const std::string& key, const std::string& fallback) const {
    return Has(key) ? reader_.String(Get(key), Path(key)) : fallback;
  }
  int Enum(const std::string& key, const std::vector<std::string>& names, int fallback) const {
    return Has(key) ? reader_.Enum(Get(key), Path(key), names) : fallback;
  }

 private:
  const Reader& reader_;
  YAML::Node node_;
  std::string path_;
  std::map<std::string, YAML::Node> entries_;
};

/// URDF roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Matrix3d RpyToRotation(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// position [3], and rpy [3] or quaternion [w, x, y, z] (not both).
Eigen::Isometry3d ReadPose(const Reader& reader, const MapReader& map) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  if (map.Has("position")) {
    X.translation() = reader.Vector3(map.Get("position"), map.Path("position"));
  }
  if (map.Has("rpy") && map.Has("quaternion")) {
    reader.Fail(map.Get("quaternion"), map.Path("quaternion"),
                "given together with rpy; expected one orientation (rpy or quaternion)");
  }
  if (map.Has("rpy")) {
    X.linear() = RpyToRotation(reader.Vector3(map.Get("rpy"), map.Path("rpy")));
  } else if (map.Has("quaternion")) {
    const Eigen::VectorXd w = reader.Vector(map.Get("quaternion"), map.Path("quaternion"), 4);
    if (!(w.norm() > 1e-12)) {
      reader.FailValue(map.Get("quaternion"), map.Path("quaternion"), "a zero quaternion",
                       "a non-zero quaternion [w, x, y, z] (normalized on use)");
    }
    X.linear() = Eigen::Quaterniond(w(0), w(1), w(2), w(3)).normalized().toRotationMatrix();
  }
  return X;
}

/// Search folders for URDF files: the given share folders, then two levels above the YAML file.
std::string ResolveUrdf(const std::string& urdf, const std::string& base_dir,
                        const std::vector<std::string>& share_dirs,
                        std::vector<std::string>* searched) {
  const fs::path p(urdf);
  std::vector<fs::path> candidates;
  if (p.is_absolute()) {
    candidates.push_back(p);
  } else {
    candidates.push_back(fs::path(base_dir) / p);
    std::vector<fs::path> dirs(share_dirs.begin(), share_dirs.end());
    dirs.push_back(fs::path(base_dir) / ".." / "..");
    for (const fs::path& dir : dirs) {
      candidates.push_back(dir / "models" / p);
      candidates.push_back(dir / p);
    }
  }
  for (const fs::path& c : candidates) {
    const fs::path normal = c.lexically_normal();
    std::error_code ec;
    if (fs::is_regular_file(normal, ec)) return normal.string();
    searched->push_back(normal.string());
  }
  return "";
}

/// Reads a vector over the positions (nq) or velocities (nv) of `model`: a list of the full
/// size, a number (weights: every entry; states: only when the size is 1), or a map
/// joint name -> number or list of the joint's size (weights also take `default`). Entries not
/// given keep their value in `base`.
class JointVectorReader {
 public:
  enum class Space { kPositions, kVelocities };

  JointVectorReader(const Reader& reader, const Model& model) : reader_(reader), model_(model) {}

  Eigen::VectorXd Read(const YAML::Node& node, const std::string& path, Space space,
                       const Eigen::VectorXd& base, bool weights) const {
    const bool positions = space == Space::kPositions;
    const int n = positions ? model_.nq() : model_.nv();
    const std::string size_name = std::string(positions ? "nq = " : "nv = ") + std::to_string(n);
    std::string expected = "a list of " + size_name + " numbers (" + CoordinateNames(space) + ")";
    if (weights) {
      expected += ", a number for every entry, or a map {default: number, <joint>: number or list}";
    } else {
      expected += " or a map <joint>: number or list";
    }
    Eigen::VectorXd x = base;
    if (node.IsScalar() && (weights || n == 1)) {
      x.setConstant(Value(node, path, weights));
    } else if (node.IsSequence()) {
      if (static_cast<int>(node.size()) != n)
        reader_.FailValue(node, path, Describe(node), expected);
      for (int i = 0; i < n; ++i) x(i) = Value(node[i], At(path, i), weights);
    } else if (node.IsMap()) {
      std::set<std::string> seen;
      // `default` first, whatever its place in the map.
      for (auto it = node.begin(); it != node.end(); ++it) {
        if (it->first.IsScalar() && it->first.Scalar() == "default") {
          if (!weights) {
            reader_.Fail(it->first, Join(path, "default"),
                         "unknown key; `default` applies to weights only; expected joint names (" +
                             JointNames() + ")");
          }
          x.setConstant(Value(it->second, Join(path, "default"), weights));
        }
      }
      for (auto it = node.begin(); it != node.end(); ++it) {
        if (!it->first.IsScalar()) {
          reader_.FailValue(it->first, path, "a map with key " + Describe(it->first),
                            "joint names as keys");
        }
        const std::string key = it->first.Scalar();
        const std::string key_path = Join(path, key);
        if (!seen.insert(key).second) reader_.Fail(it->first, key_path, "duplicate key");
        if (key == "default") continue;
        if (!model_.HasJoint(key)) {
          reader_.Fail(it->first, key_path,
                       std::string("unknown joint; expected ") + (weights ? "`default` or " : "") +
                           "one of " + JointNames());
        }
        const JointIndex j = model_.GetJointIndex(key);
        const int start = positions ? model_.position_start(j) : model_.velocity_start(j);
        const int size = positions ? model_.joint_nq(j) : model_.joint_nv(j);
        if (size == 0) {
          reader_.Fail(it->first, key_path, "joint '" + key + "' is fixed and has no coordinates");
        }
        const YAML::Node value = it->second;
        if (value.IsScalar() && (weights || size == 1)) {
          x.segment(start, size).setConstant(Value(value, key_path, weights));
        } else if (value.IsSequence() && static_cast<int>(value.size()) == size) {
          for (int i = 0; i < size; ++i) x(start + i) = Value(value[i], At(key_path, i), weights);
        } else {
          const std::string joint_expected =
              size == 1 ? std::string("a number")
                        : "a list of " + std::to_string(size) + " numbers (the " +
                              JointTypeName(model_.joint_type(j)) + " joint's " +
                              (positions ? "positions" : "velocities") + ")" +
                              (weights ? " or a number for all of them" : "");
          reader_.FailValue(value, key_path, Describe(value), joint_expected);
        }
      }
    } else {
      reader_.FailValue(node, path, Describe(node), expected);
    }
    if (positions && !weights) NormalizeQuaternions(node, path, &x);
    return x;
  }

  /// Comma-separated coordinate names "shoulder, elbow" (joint names, repeated for each of
  /// their coordinates), shortened for big models.
  std::string CoordinateNames(Space space) const {
    const bool positions = space == Space::kPositions;
    const int n = positions ? model_.nq() : model_.nv();
    std::vector<std::string> names;
    for (int i = 0; i < n; ++i) {
      names.push_back(positions ? model_.position_name(i) : model_.velocity_name(i));
    }
    return "coordinates of " + JoinNames(names, 12);
  }

  std::string JointNames() const {
    std::vector<std::string> names;
    for (JointIndex j = 1; j <= model_.num_joints(); ++j) {
      if (model_.joint_nv(j) > 0) names.push_back(model_.joint_name(j));
    }
    return names.empty() ? std::string("(none: the model has no moving joints)") : JoinNames(names);
  }

 private:
  double Value(const YAML::Node& node, const std::string& path, bool weights) const {
    return weights ? reader_.NonNegative(node, path) : reader_.Double(node, path);
  }

  void NormalizeQuaternions(const YAML::Node& node, const std::string& path,
                            Eigen::VectorXd* q) const {
    for (JointIndex j : model_.floating_joints()) {
      auto quaternion = q->segment<4>(model_.position_start(j));
      const double norm = quaternion.norm();
      if (!(norm > 1e-12)) {
        reader_.Fail(node, path,
                     "the quaternion [qw qx qy qz] of floating joint '" + model_.joint_name(j) +
                         "' is zero; expected a non-zero quaternion (normalized on use)");
      }
      quaternion /= norm;
    }
  }

  const Reader& reader_;
  const Model& model_;
};

const std::vector<std::string> kTopLevelKeys = {"name",    "description", "task_success", "scene",
                                                "problem", "solver",      "mpc"};
const std::vector<std::string> kSceneKeys = {"models", "geometry", "gravity", "enable_contact",
                                             "contact"};
const std::vector<std::string> kModelKeys = {"urdf",   "base",       "position",
                                             "rpy",    "quaternion", "planar_normal",
                                             "prefix", "name",       "inscribed_spheres"};
const std::vector<std::string> kGeometryKeys = {
    "name",     "shape", "radius",     "length", "size",
    "position", "rpy",   "quaternion", "body",   "inscribed_spheres"};
const std::vector<std::string> kInscribedSpheresKeys = {"num_per_axis", "radius_fraction",
                                                        "center_sphere"};
const std::vector<std::string> kContactParameterKeys = {
    "stiffness", "smoothing", "dissipation_velocity", "friction_coefficient", "stiction_velocity"};
const std::vector<std::string> kProblemKeys = {"time_step", "horizon",         "num_steps",
                                               "q_init",    "v_init",          "nominal",
                                               "weights",   "unactuated_dofs", "initial_guess"};
const std::vector<std::string> kNominalKeys = {"q_nom", "v_nom", "q_start", "q_end"};
const std::vector<std::string> kWeightKeys = {"Qq", "Qv", "R", "Qfq", "Qfv"};
const std::vector<std::string> kSolverKeys = {
    "max_iterations",   "num_threads",          "constraint_method",
    "penalty_weight",   "derivative_method",    "finite_difference_step",
    "scaling",          "initial_trust_radius", "max_trust_radius",
    "acceptance_ratio", "cost_tolerance",       "gradient_tolerance",
    "step_tolerance",   "fixed_iterations",     "verbosity"};

/// `inscribed_spheres`: true (InscribedSpheresOptions{}), false (none), or a map
/// {num_per_axis, radius_fraction, center_sphere} (enabled, unspecified keys at their defaults).
std::optional<InscribedSpheresOptions> ReadInscribedSpheres(const Reader& reader,
                                                            const YAML::Node& node,
                                                            const std::string& path) {
  const std::string expected =
      "true, false or a map {num_per_axis: integer >= 2, radius_fraction: number in (0, 0.5], "
      "center_sphere: bool}";
  if (node.IsScalar()) {
    bool enabled = false;
    if (!YAML::convert<bool>::decode(node, enabled)) {
      reader.FailValue(node, path, Describe(node), expected);
    }
    if (!enabled) return std::nullopt;
    return InscribedSpheresOptions{};
  }
  if (!node.IsMap()) reader.FailValue(node, path, Describe(node), expected);
  const MapReader m(reader, node, path, kInscribedSpheresKeys);
  InscribedSpheresOptions options;
  options.num_per_axis = m.Int("num_per_axis", options.num_per_axis, 2);
  if (options.num_per_axis > 100) {
    reader.FailValue(m.Get("num_per_axis"), m.Path("num_per_axis"),
                     std::to_string(options.num_per_axis), "an integer from 2 to 100");
  }
  options.radius_fraction = m.Double("radius_fraction", options.radius_fraction);
  if (!(options.radius_fraction > 0.0 && options.radius_fraction <= 0.5)) {
    reader.FailValue(m.Get("radius_fraction"), m.Path("radius_fraction"),
                     FormatValue(options.radius_fraction),
                     "a number in (0, 0.5] (sphere radius / smallest box side)");
  }
  options.center_sphere = m.Bool("center_sphere", options.center_sphere);
  return options;
}

class ConfigLoader {
 public:
  ConfigLoader(std::string source_name, std::string base_dir, std::vector<std::string> share_dirs)
      : reader_(source_name), base_dir_(std::move(base_dir)), share_dirs_(std::move(share_dirs)) {
    config_.source_file = std::move(source_name);
  }

  ExampleConfig Load(const YAML::Node& root) {
    if (!root.IsDefined() || root.IsNull()) {
      reader_.Fail(root, "(top level)",
                   "the file is empty; expected a map with keys " + JoinNames(kTopLevelKeys));
    }
    const MapReader top(reader_, root, "", kTopLevelKeys);
    config_.name = top.String("name", DefaultName());
    config_.description = top.String("description", "");
    config_.task_success = top.String("task_success", "");

    LoadScene(MapReader(reader_, top.Require("scene"), "scene", kSceneKeys));
    LoadProblem(MapReader(reader_, top.Require("problem"), "problem", kProblemKeys));
    if (top.Has("solver")) {
      LoadSolver(MapReader(reader_, top.Get("solver"), "solver", kSolverKeys));
    }
    if (top.Has("mpc")) {
      const YAML::Node mpc = top.Get("mpc");
      if (!mpc.IsMap()) {
        reader_.FailValue(mpc, "mpc", Describe(mpc),
                          "a map (reserved for model predictive control options)");
      }
      YAML::Emitter emitter;
      emitter << mpc;
      config_.mpc = emitter.c_str();
      // The controller's own contact law (parameters only: the scene's pair filters and
      // per-pair overrides stay) and solver options, when given.
      if (mpc["problem"] || mpc["contact"]) {
        const ContactOptions scene_contact = contact_;
        if (mpc["contact"]) {
          LoadContactParameters(
              MapReader(reader_, mpc["contact"], "mpc.contact", kContactParameterKeys),
              &contact_.parameters);
        }
        LoadMpcProblem(top.Get("problem"),
                       mpc["problem"] ? mpc["problem"] : YAML::Node(YAML::NodeType::Map));
        contact_ = scene_contact;
      }
      if (mpc["solver"]) {
        const SolverOptions open_loop = config_.solver;
        LoadSolver(MapReader(reader_, mpc["solver"], "mpc.solver", kSolverKeys));
        config_.mpc_solver = config_.solver;
        config_.solver = open_loop;
      }
    }
    return std::move(config_);
  }

 private:
  std::string DefaultName() const { return fs::path(config_.source_file).stem().string(); }

  // ---------------------------------------------------------------- scene
  void LoadScene(const MapReader& scene) {
    ModelBuilder builder(config_.name);
    const YAML::Node models = scene.Require("models");
    if (!models.IsSequence() || models.size() == 0) {
      reader_.FailValue(models, scene.Path("models"), Describe(models),
                        "a non-empty list of models {urdf: file, base: fixed|floating|planar, "
                        "...}");
    }
    for (std::size_t i = 0; i < models.size(); ++i) {
      LoadModel(MapReader(reader_, models[i], At(scene.Path("models"), i), kModelKeys), &builder);
    }
    if (scene.Has("geometry")) {
      const YAML::Node geometry = scene.Get("geometry");
      if (!geometry.IsSequence()) {
        reader_.FailValue(geometry, scene.Path("geometry"), Describe(geometry),
                          "a list of geometries {name, shape, ...}");
      }
      for (std::size_t i = 0; i < geometry.size(); ++i) {
        LoadGeometry(MapReader(reader_, geometry[i], At(scene.Path("geometry"), i), kGeometryKeys),
                     &builder);
      }
    }
    if (scene.Has("gravity")) {
      builder.SetGravity(reader_.Vector3(scene.Get("gravity"), scene.Path("gravity")));
    }
    try {
      config_.model = builder.Build();
    } catch (const std::exception& e) {
      reader_.Fail(scene.node(), "scene",
                   std::string("the scene is not a valid model: ") + e.what());
    }
    enable_contact_ = scene.Bool("enable_contact", true);
    if (scene.Has("contact")) {
      LoadContact(MapReader(reader_, scene.Get("contact"), scene.Path("contact"), ContactKeys()));
    }
  }

  void LoadModel(const MapReader& m, ModelBuilder* builder) {
    SceneModelConfig model;
    const std::string urdf = reader_.String(m.Require("urdf"), m.Path("urdf"));
    std::vector<std::string> searched;
    model.urdf_file = ResolveUrdf(urdf, base_dir_, share_dirs_, &searched);
    if (model.urdf_file.empty()) {
      reader_.Fail(m.Get("urdf"), m.Path("urdf"),
                   "cannot find URDF file '" + urdf + "'; searched " + JoinNames(searched));
    }
    model.options.base = static_cast<BaseType>(
        m.Enum("base", {"fixed", "floating", "planar"}, static_cast<int>(BaseType::kFixed)));
    static_assert(static_cast<int>(BaseType::kFixed) == 0 &&
                      static_cast<int>(BaseType::kFloating) == 1 &&
                      static_cast<int>(BaseType::kPlanar) == 2,
                  "BaseType order");
    model.options.X_WB = ReadPose(reader_, m);
    if (m.Has("planar_normal")) {
      if (model.options.base != BaseType::kPlanar) {
        reader_.Fail(m.Get("planar_normal"), m.Path("planar_normal"),
                     "given for a base that is not planar; expected base: planar");
      }
      const Eigen::Vector3d n = reader_.Vector3(m.Get("planar_normal"), m.Path("planar_normal"));
      if (!(n.norm() > 1e-12)) {
        reader_.FailValue(m.Get("planar_normal"), m.Path("planar_normal"), "a zero vector",
                          "a non-zero vector");
      }
      model.options.planar_normal = n.normalized();
    }
    model.options.prefix = m.String("prefix", "");
    model.options.model_name = m.String("name", "");
    if (m.Has("inscribed_spheres")) {
      model.options.box_inscribed_spheres =
          ReadInscribedSpheres(reader_, m.Get("inscribed_spheres"), m.Path("inscribed_spheres"));
    }
    try {
      AddUrdfFile(model.urdf_file, model.options, builder);
    } catch (const std::exception& e) {
      reader_.Fail(m.Get("urdf"), m.Path("urdf"),
                   "cannot load '" + model.urdf_file + "': " + e.what());
    }
    config_.models.push_back(std::move(model));
  }

  void LoadGeometry(const MapReader& g, ModelBuilder* builder) {
    const std::string name = reader_.String(g.Require("name"), g.Path("name"));
    const int type = reader_.Enum(g.Require("shape"), g.Path("shape"),
                                  {"sphere", "capsule", "cylinder", "box", "half_space"});
    // The keys each shape takes.
    const std::vector<std::vector<std::string>> kShapeKeys = {
        {"radius"}, {"radius", "length"}, {"radius", "length"}, {"size"}, {}};
    const std::vector<std::string> kShapeNames = {"sphere", "capsule", "cylinder", "box",
                                                  "half_space"};
    for (const std::string key : {"radius", "length", "size"}) {
      const auto& keys = kShapeKeys[type];
      const bool takes = std::find(keys.begin(), keys.end(), key) != keys.end();
      if (g.Has(key) && !takes) {
        reader_.Fail(g.Get(key), g.Path(key),
                     "not used by shape " + kShapeNames[type] + "; expected " +
                         (keys.empty() ? std::string("no size keys") : JoinNames(keys)));
      }
      if (!g.Has(key) && takes) {
        reader_.Fail(g.node(), g.Path(key),
                     "missing (required by shape " + kShapeNames[type] + ")");
      }
    }
    Shape shape;
    switch (type) {
      case 0:
        shape = Sphere{reader_.Positive(g.Get("radius"), g.Path("radius"))};
        break;
      case 1:
        shape = Capsule{reader_.Positive(g.Get("radius"), g.Path("radius")),
                        reader_.NonNegative(g.Get("length"), g.Path("length"))};
        break;
      case 2:
        shape = Cylinder{reader_.Positive(g.Get("radius"), g.Path("radius")),
                         reader_.Positive(g.Get("length"), g.Path("length"))};
        break;
      case 3: {
        const Eigen::Vector3d size = reader_.Vector3(g.Get("size"), g.Path("size"));
        for (int i = 0; i < 3; ++i) {
          if (!(size(i) > 0.0)) {
            reader_.FailValue(g.Get("size")[i], At(g.Path("size"), i), FormatValue(size(i)),
                              "a finite positive number (full side length, m)");
          }
        }
        shape = Box{size};
        break;
      }
      default:
        shape = HalfSpace{};
        break;
    }
    std::optional<InscribedSpheresOptions> inscribed_spheres;
    if (g.Has("inscribed_spheres")) {
      if (type != 3) {
        reader_.Fail(g.Get("inscribed_spheres"), g.Path("inscribed_spheres"),
                     "not used by shape " + kShapeNames[type] + "; expected only with shape: box");
      }
      inscribed_spheres =
          ReadInscribedSpheres(reader_, g.Get("inscribed_spheres"), g.Path("inscribed_spheres"));
    }
    const Eigen::Isometry3d X_BG = ReadPose(reader_, g);
    const std::string body_name = g.String("body", "world");
    if (!builder->HasBody(body_name)) {
      reader_.Fail(g.Get("body"), g.Path("body"),
                   "unknown body '" + body_name + "'; expected 'world' or a body of the models");
    }
    try {
      const BodyIndex body = builder->GetBodyIndex(body_name);
      if (!inscribed_spheres.has_value()) {
        builder->AddGeometry(name, body, X_BG, shape);
      } else {
        // The box's inscribed spheres instead of the box: <name>_sphere0, <name>_sphere1, ...
        const std::vector<InscribedSphere> spheres =
            InscribedSpheres(std::get<Box>(shape), *inscribed_spheres);
        for (std::size_t k = 0; k < spheres.size(); ++k) {
          builder->AddGeometry(name + "_sphere" + std::to_string(k), body,
                               X_BG * spheres[k].X_BoxSphere, spheres[k].sphere);
        }
      }
    } catch (const std::exception& e) {
      reader_.Fail(g.node(), g.path(), e.what());
    }
  }

  static std::vector<std::string> ContactKeys() {
    std::vector<std::string> keys = kContactParameterKeys;
    keys.insert(keys.end(), {"force_tolerance", "excluded_pairs", "included_pairs",
                             "collision_groups", "overrides"});
    return keys;
  }

  /// A geometry name, a body name, or "*".
  std::string ContactName(const YAML::Node& node, const std::string& path) const {
    const std::string name = reader_.String(node, path);
    if (name == "*") return name;
    const Model& model = config_.model;
    if (model.HasBody(name)) return name;
    for (const GeometryInstance& g : model.geometries()) {
      if (g.name == name) return name;
    }
    std::vector<std::string> geometry_names;
    for (const GeometryInstance& g : model.geometries()) geometry_names.push_back(g.name);
    reader_.FailValue(node, path, "'" + name + "'",
                      "a geometry name (" +
                          (geometry_names.empty() ? std::string("the scene has none")
                                                  : JoinNames(geometry_names, 20)) +
                          "), a body name, or '*'");
  }

  std::vector<std::pair<std::string, std::string>> ReadPairs(const YAML::Node& node,
                                                             const std::string& path) const {
    if (!node.IsSequence()) {
      reader_.FailValue(node, path, Describe(node), "a list of name pairs [a, b]");
    }
    std::vector<std::pair<std::string, std::string>> pairs;
    for (std::size_t i = 0; i < node.size(); ++i) {
      const YAML::Node pair = node[i];
      if (!pair.IsSequence() || pair.size() != 2) {
        reader_.FailValue(pair, At(path, i), Describe(pair), "a pair of names [a, b]");
      }
      pairs.emplace_back(ContactName(pair[0], At(At(path, i), 0)),
                         ContactName(pair[1], At(At(path, i), 1)));
    }
    return pairs;
  }

  // The law's parameters present in `c`, over the values in *p.
  static void LoadContactParameters(const MapReader& c, ContactParameters* p) {
    p->stiffness = c.Positive("stiffness", p->stiffness);
    p->smoothing = c.Positive("smoothing", p->smoothing);
    p->dissipation_velocity = c.Positive("dissipation_velocity", p->dissipation_velocity);
    p->friction_coefficient = c.NonNegative("friction_coefficient", p->friction_coefficient);
    p->stiction_velocity = c.Positive("stiction_velocity", p->stiction_velocity);
  }

  void LoadContact(const MapReader& c) {
    ContactOptions& options = contact_;
    LoadContactParameters(c, &options.parameters);
    options.force_tolerance = c.NonNegative("force_tolerance", options.force_tolerance);
    if (c.Has("excluded_pairs")) {
      options.excluded_pairs = ReadPairs(c.Get("excluded_pairs"), c.Path("excluded_pairs"));
    }
    if (c.Has("included_pairs")) {
      options.included_pairs = ReadPairs(c.Get("included_pairs"), c.Path("included_pairs"));
    }
    if (c.Has("collision_groups")) {
      const YAML::Node groups = c.Get("collision_groups");
      const std::string path = c.Path("collision_groups");
      if (!groups.IsSequence()) {
        reader_.FailValue(groups, path, Describe(groups), "a list of lists of names");
      }
      for (std::size_t i = 0; i < groups.size(); ++i) {
        const YAML::Node group = groups[i];
        if (!group.IsSequence()) {
          reader_.FailValue(group, At(path, i), Describe(group), "a list of names");
        }
        std::vector<std::string> names;
        for (std::size_t j = 0; j < group.size(); ++j) {
          names.push_back(ContactName(group[j], At(At(path, i), j)));
        }
        options.collision_groups.push_back(std::move(names));
      }
    }
    if (c.Has("overrides")) {
      const YAML::Node overrides = c.Get("overrides");
      const std::string path = c.Path("overrides");
      if (!overrides.IsSequence()) {
        reader_.FailValue(overrides, path, Describe(overrides),
                          "a list of {a, b, <contact parameter>: value}");
      }
      std::vector<std::string> keys = {"a", "b"};
      keys.insert(keys.end(), kContactParameterKeys.begin(), kContactParameterKeys.end());
      for (std::size_t i = 0; i < overrides.size(); ++i) {
        const MapReader o(reader_, overrides[i], At(path, i), keys);
        ContactParameterOverride entry;
        entry.a = ContactName(o.Require("a"), o.Path("a"));
        entry.b = ContactName(o.Require("b"), o.Path("b"));
        if (o.Has("stiffness")) entry.stiffness = o.Positive("stiffness", 0.0);
        if (o.Has("smoothing")) entry.smoothing = o.Positive("smoothing", 0.0);
        if (o.Has("dissipation_velocity")) {
          entry.dissipation_velocity = o.Positive("dissipation_velocity", 0.0);
        }
        if (o.Has("friction_coefficient")) {
          entry.friction_coefficient = o.NonNegative("friction_coefficient", 0.0);
        }
        if (o.Has("stiction_velocity")) {
          entry.stiction_velocity = o.Positive("stiction_velocity", 0.0);
        }
        options.overrides.push_back(std::move(entry));
      }
    }
  }

  // ---------------------------------------------------------------- problem
  void LoadProblem(const MapReader& p) {
    const Model& model = config_.model;
    ProblemDefinition& problem = config_.problem;
    const JointVectorReader joints(reader_, model);
    using Space = JointVectorReader::Space;

    problem.time_step = reader_.Positive(p.Require("time_step"), p.Path("time_step"));
    if (p.Has("horizon") == p.Has("num_steps")) {
      reader_.Fail(p.Has("horizon") ? p.Get("num_steps") : p.node(), p.Path("horizon"),
                   p.Has("horizon") ? "given together with num_steps; expected one of them"
                                    : "missing; expected horizon (s) or num_steps");
    }
    if (p.Has("num_steps")) {
      problem.num_steps = p.Int("num_steps", 1, 1);
    } else {
      const double horizon = p.Positive("horizon", 1.0);
      const double ratio = horizon / problem.time_step;
      const double steps = std::round(ratio);
      if (!(steps >= 1.0) || std::abs(ratio - steps) > 1e-9 * std::max(1.0, ratio) || steps > 1e7) {
        reader_.FailValue(p.Get("horizon"), p.Path("horizon"), FormatValue(horizon),
                          "a positive multiple of time_step = " + FormatValue(problem.time_step) +
                              " (horizon / time_step = " + FormatValue(ratio) + ")");
      }
      problem.num_steps = static_cast<int>(steps);
    }
    const int N = problem.num_steps;

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

    // Nominal trajectory: constant q_nom, or q_start -> q_end interpolated over k = 0..N.
    Eigen::VectorXd q_start = problem.q_init;
    Eigen::VectorXd q_end = problem.q_init;
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
            joints.Read(n.Get("q_nom"), n.Path("q_nom"), Space::kPositions, problem.q_init, false);
        q_end = q_start;
      }
      if (n.Has("q_start")) {
        q_start = joints.Read(n.Get("q_start"), n.Path("q_start"), Space::kPositions,
                              problem.q_init, false);
      }
      q_end = q_start;
      if (n.Has("q_end")) {
        q_end = joints.Read(n.Get("q_end"), n.Path("q_end"), Space::kPositions, q_start, false);
      }
      if (n.Has("v_nom")) {
        v_nom = joints.Read(n.Get("v_nom"), n.Path("v_nom"), Space::kVelocities, v_nom, false);
      }
    }
    problem.q_nom.resize(N + 1);
    problem.v_nom.assign(N + 1, v_nom);
    for (int k = 0; k <= N; ++k) {
      problem.q_nom[k] =
          InterpolateConfiguration(model, q_start, q_end, static_cast<double>(k) / N);
    }

    // Weights (default zero).
    problem.Qq = Eigen::VectorXd::Zero(model.nq());
    problem.Qfq = Eigen::VectorXd::Zero(model.nq());
    problem.Qv = Eigen::VectorXd::Zero(model.nv());
    problem.R = Eigen::VectorXd::Zero(model.nv());
    problem.Qfv = Eigen::VectorXd::Zero(model.nv());
    if (p.Has("weights")) {
      const MapReader w(reader_, p.Get("weights"), p.Path("weights"), kWeightKeys);
      const auto read = [&](const char* key, Space space, Eigen::VectorXd* out) {
        if (w.Has(key)) *out = joints.Read(w.Get(key), w.Path(key), space, *out, true);
      };
      read("Qq", Space::kPositions, &problem.Qq);
      read("Qv", Space::kVelocities, &problem.Qv);
      read("R", Space::kVelocities, &problem.R);
      read("Qfq", Space::kPositions, &problem.Qfq);
      read("Qfv", Space::kVelocities, &problem.Qfv);
    }

    // Unactuated DoFs: the base DoFs plus the joints (or velocity indices) listed.
    if (p.Has("unactuated_dofs")) {
      const YAML::Node list = p.Get("unactuated_dofs");
      const std::string path = p.Path("unactuated_dofs");
      if (!list.IsSequence()) {
        reader_.FailValue(list, path, Describe(list),
                          "a list of joint names (or velocity indices)");
      }
      std::set<int> dofs;
      for (int i = 0; i < model.nv(); ++i) {
        if (model.is_base_velocity()[i]) dofs.insert(i);
      }
      for (std::size_t i = 0; i < list.size(); ++i) {
        const YAML::Node entry = list[i];
        const std::string entry_path = At(path, i);
        if (!entry.IsScalar()) {
          reader_.FailValue(entry, entry_path, Describe(entry), "a joint name");
        }
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
                          "a joint name (" + joints.JointNames() + ") or a velocity index");
      }
      problem.unactuated_dofs = std::vector<int>(dofs.begin(), dofs.end());
    }

    config_.initial_guess = static_cast<InitialGuessType>(
        p.Enum("initial_guess", {"interpolate", "constant", "nominal"},
               static_cast<int>(InitialGuessType::kInterpolate)));

    problem.enable_contact = enable_contact_;
    problem.contact = contact_;

    try {
      problem.Validate(model);
    } catch (const std::exception& e) {
      reader_.Fail(p.node(), "problem", e.what());
    }
  }

  // ---------------------------------------------------------------- mpc.problem
  // The controller's problem: `problem` with the keys of `mpc.problem` replacing the open-loop
  // ones; `nominal` and `weights` are merged key by key (e.g. only a new q_end).
  void LoadMpcProblem(const YAML::Node& problem, const YAML::Node& overrides) {
    const MapReader check(reader_, overrides, "mpc.problem", kProblemKeys);
    YAML::Node merged = YAML::Clone(problem);
    for (auto it = overrides.begin(); it != overrides.end(); ++it) {
      const std::string key = it->first.Scalar();
      const bool merge = (key == "nominal" || key == "weights") && it->second.IsMap() &&
                         merged[key] && merged[key].IsMap();
      if (!merge) {
        merged[key] = it->second;
        continue;
      }
      YAML::Node sub = YAML::Clone(merged[key]);
      for (auto jt = it->second.begin(); jt != it->second.end(); ++jt) {
        sub[jt->first.Scalar()] = jt->second;
      }
      merged[key] = sub;
    }
    ProblemDefinition open_loop = std::move(config_.problem);
    const InitialGuessType guess = config_.initial_guess;
    LoadProblem(MapReader(reader_, merged, "mpc.problem", kProblemKeys));
    config_.mpc_problem = std::move(config_.problem);
    config_.problem = std::move(open_loop);
    config_.initial_guess = guess;
  }

  // ---------------------------------------------------------------- solver
  void LoadSolver(const MapReader& s) {
    SolverOptions& o = config_.solver;
    o.max_iterations = s.Int("max_iterations", o.max_iterations, 0);
    o.num_threads = s.Int("num_threads", o.num_threads, 1);
    o.constraint_method =
        static_cast<ConstraintMethod>(s.Enum("constraint_method", {"none", "penalty", "lagrange"},
                                             static_cast<int>(o.constraint_method)));
    o.penalty_weight = s.NonNegative("penalty_weight", o.penalty_weight);
    o.derivative_method = static_cast<DerivativeMethod>(
        s.Enum("derivative_method", {"forward", "central"}, static_cast<int>(o.derivative_method)));
    o.finite_difference_step = s.NonNegative("finite_difference_step", o.finite_difference_step);
    o.scaling = static_cast<ScalingMethod>(
        s.Enum("scaling", {"none", "sqrt", "double_sqrt"}, static_cast<int>(o.scaling)));
    o.initial_trust_radius = s.Positive("initial_trust_radius", o.initial_trust_radius);
    o.max_trust_radius = s.Positive("max_trust_radius", o.max_trust_radius);
    o.acceptance_ratio = s.NonNegative("acceptance_ratio", o.acceptance_ratio);
    o.cost_tolerance = s.NonNegative("cost_tolerance", o.cost_tolerance);
    o.gradient_tolerance = s.NonNegative("gradient_tolerance", o.gradient_tolerance);
    o.step_tolerance = s.NonNegative("step_tolerance", o.step_tolerance);
    o.fixed_iterations = s.Bool("fixed_iterations", o.fixed_iterations);
    o.verbosity = s.Int("verbosity", o.verbosity, 0);
    std::string why;
    if (!o.IsValid(&why)) reader_.Fail(s.node(), s.path(), "invalid options: " + why);
  }

  static_assert(static_cast<int>(ConstraintMethod::kNone) == 0 &&
                    static_cast<int>(ConstraintMethod::kPenalty) == 1 &&
                    static_cast<int>(ConstraintMethod::kLagrangeMultipliers) == 2,
                "ConstraintMethod order");
  static_assert(static_cast<int>(DerivativeMethod::kForwardDifferences) == 0 &&
                    static_cast<int>(DerivativeMethod::kCentralDifferences) == 1,
                "DerivativeMethod order");
  static_assert(static_cast<int>(ScalingMethod::kNone) == 0 &&
                    static_cast<int>(ScalingMethod::kSqrt) == 1 &&
                    static_cast<int>(ScalingMethod::kDoubleSqrt) == 2,
                "ScalingMethod order");
  static_assert(static_cast<int>(InitialGuessType::kInterpolate) == 0 &&
                    static_cast<int>(InitialGuessType::kConstant) == 1 &&
                    static_cast<int>(InitialGuessType::kNominal) == 2,
                "InitialGuessType order");

  Reader reader_;
  std::string base_dir_;
  std::vector<std::string> share_dirs_;
  ExampleConfig config_;
  bool enable_contact_{true};
  ContactOptions contact_;
};

YAML::Node ParseYaml(const std::string& text, const std::string& source_name) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    std::string where = "(YAML syntax)";
    std::string problem = e.msg;
    if (e.mark.line >= 0) {
      problem += " (line " + std::to_string(e.mark.line + 1) + ", column " +
                 std::to_string(e.mark.column + 1) + ")";
    }
    ThrowFileError(source_name, where, "malformed YAML: " + problem);
  }
}

bool IsRegularFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

}  // namespace

std::string InitialGuessTypeName(InitialGuessType type) {
  switch (type) {
    case InitialGuessType::kInterpolate:
      return "interpolate";
    case InitialGuessType::kConstant:
      return "constant";
    case InitialGuessType::kNominal:
      return "nominal";
  }
  return "unknown";
}

ExampleConfig LoadExampleConfigString(const std::string& yaml_text, const std::string& source_name,
                                      const std::string& base_dir,
                                      const std::vector<std::string>& share_dirs) {
  const YAML::Node root = ParseYaml(yaml_text, source_name);
  ConfigLoader loader(source_name, base_dir, share_dirs);
  return loader.Load(root);
}

ExampleConfig LoadExampleConfig(const std::string& path,
                                const std::vector<std::string>& share_dirs) {
  std::error_code ec;
  if (!fs::exists(path, ec)) ThrowFileError(path, "", "no such file");
  if (!fs::is_regular_file(path, ec)) ThrowFileError(path, "", "not a regular file");
  std::ifstream in(path);
  if (!in) ThrowFileError(path, "", "cannot open the file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  std::string base_dir = fs::path(path).parent_path().string();
  if (base_dir.empty()) base_dir = ".";
  return LoadExampleConfigString(text.str(), path, base_dir, share_dirs);
}

std::vector<std::string> ListExamples(const std::vector<std::string>& search_dirs) {
  std::set<std::string> names;
  for (const std::string& dir : search_dirs) {
    std::error_code ec;
    const fs::path examples = fs::path(dir) / "examples";
    if (!fs::is_directory(examples, ec)) continue;
    for (const auto& entry : fs::directory_iterator(examples, ec)) {
      const std::string name = entry.path().filename().string();
      if (IsRegularFile(entry.path() / (name + ".yaml"))) names.insert(name);
    }
  }
  return {names.begin(), names.end()};
}

std::string FindExampleConfig(const std::string& name_or_path,
                              const std::vector<std::string>& search_dirs) {
  if (IsRegularFile(name_or_path)) return name_or_path;
  const fs::path p(name_or_path);
  const std::string extension = p.extension().string();
  const bool looks_like_path =
      name_or_path.find('/') != std::string::npos || extension == ".yaml" || extension == ".yml";
  if (name_or_path.empty()) {
    ThrowFileError("<config>", "", "empty name; expected an example name or a YAML file");
  }
  if (looks_like_path) ThrowFileError(name_or_path, "", "no such file");
  std::vector<std::string> searched;
  for (const std::string& dir : search_dirs) {
    const fs::path candidate =
        (fs::path(dir) / "examples" / name_or_path / (name_or_path + ".yaml")).lexically_normal();
    if (IsRegularFile(candidate)) return candidate.string();
    searched.push_back(candidate.string());
  }
  const std::vector<std::string> available = ListExamples(search_dirs);
  ThrowFileError(
      name_or_path, "",
      "no such file or example; searched " +
          (searched.empty() ? std::string("nothing (no search folders)") : JoinNames(searched)) +
          "; examples found: " + (available.empty() ? std::string("none") : JoinNames(available)) +
          " (set IDTO_SHARE_DIR to the folder holding examples/ and models/)");
}

std::vector<std::string> DefaultShareDirs(const std::string& build_tree_dir,
                                          const std::string& executable_path) {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("IDTO_SHARE_DIR"); env != nullptr && env[0] != '\0') {
    dirs.emplace_back(env);
  }
  if (!build_tree_dir.empty()) dirs.push_back(build_tree_dir);
  if (!executable_path.empty()) {
    fs::path exe_dir = fs::path(executable_path).parent_path();
    if (exe_dir.empty()) exe_dir = ".";
    dirs.push_back((exe_dir / ".." / "share" / "idto").lexically_normal().string());
  }
  return dirs;
}

Eigen::VectorXd InterpolateConfiguration(const Model& model, const Eigen::VectorXd& q_a,
                                         const Eigen::VectorXd& q_b, double s) {
  model.CheckConfiguration("InterpolateConfiguration", "q_a", q_a);
  model.CheckConfiguration("InterpolateConfiguration", "q_b", q_b);
  Eigen::VectorXd q = (1.0 - s) * q_a + s * q_b;
  for (JointIndex j : model.floating_joints()) {
    const int start = model.position_start(j);
    const Eigen::Quaterniond Qa =
        Eigen::Quaterniond(q_a(start), q_a(start + 1), q_a(start + 2), q_a(start + 3)).normalized();
    const Eigen::Quaterniond Qb =
        Eigen::Quaterniond(q_b(start), q_b(start + 1), q_b(start + 2), q_b(start + 3)).normalized();
    Eigen::Quaterniond Q = Qa.slerp(s, Qb).normalized();
    q(start) = Q.w();
    q(start + 1) = Q.x();
    q(start + 2) = Q.y();
    q(start + 3) = Q.z();
  }
  return q;
}

std::vector<Eigen::VectorXd> MakeInitialGuess(const ExampleConfig& config) {
  const ProblemDefinition& problem = config.problem;
  const int N = problem.num_steps;
  std::vector<Eigen::VectorXd> q(N + 1, problem.q_init);
  switch (config.initial_guess) {
    case InitialGuessType::kConstant:
      break;
    case InitialGuessType::kNominal:
      for (int k = 1; k <= N; ++k) q[k] = problem.q_nom[k];
      break;
    case InitialGuessType::kInterpolate:
      for (int k = 1; k <= N; ++k) {
        q[k] = InterpolateConfiguration(config.model, problem.q_init, problem.q_nom[N],
                                        static_cast<double>(k) / N);
      }
      break;
  }
  return q;
}

}  // namespace idto
