#include "joint_vector_reader.hpp"

#include <vector>

#include "idto/multibody/joint.hpp"

namespace idto::config_internal {

Eigen::VectorXd JointVectorReader::Read(const YAML::Node& node, const std::string& path,
                                        Space space, const Eigen::VectorXd& base,
                                        bool weights) const {
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
    if (static_cast<int>(node.size()) != n) {
      reader_.FailValue(node, path, Describe(node), expected);
    }
    for (int i = 0; i < n; ++i) x(i) = Value(node[i], At(path, i), weights);
  } else if (node.IsMap()) {
    ReadMap(node, path, space, weights, &x);
  } else {
    reader_.FailValue(node, path, Describe(node), expected);
  }
  if (positions && !weights) NormalizeQuaternions(node, path, &x);
  return x;
}

void JointVectorReader::ReadMap(const YAML::Node& node, const std::string& path, Space space,
                                bool weights, Eigen::VectorXd* x) const {
  const bool positions = space == Space::kPositions;
  const std::vector<MapEntry> entries = reader_.Entries(node, path, "a map");
  // `default` first, whatever its place in the map.
  for (const MapEntry& e : entries) {
    if (e.key != "default") continue;
    if (!weights) {
      reader_.Fail(e.key_node, Join(path, "default"),
                   "unknown key; `default` applies to weights only; expected joint names (" +
                       JointNames() + ")");
    }
    x->setConstant(Value(e.value, Join(path, "default"), weights));
  }
  for (const MapEntry& e : entries) {
    if (e.key == "default") continue;
    const std::string key_path = Join(path, e.key);
    if (!model_.HasJoint(e.key)) {
      reader_.Fail(e.key_node, key_path,
                   std::string("unknown joint; expected ") + (weights ? "`default` or " : "") +
                       "one of " + JointNames());
    }
    const JointIndex j = model_.GetJointIndex(e.key);
    const int start = positions ? model_.position_start(j) : model_.velocity_start(j);
    const int size = positions ? model_.joint_nq(j) : model_.joint_nv(j);
    if (size == 0) {
      reader_.Fail(e.key_node, key_path, "joint '" + e.key + "' is fixed and has no coordinates");
    }
    const YAML::Node& value = e.value;
    if (value.IsScalar() && (weights || size == 1)) {
      x->segment(start, size).setConstant(Value(value, key_path, weights));
    } else if (value.IsSequence() && static_cast<int>(value.size()) == size) {
      for (int i = 0; i < size; ++i) (*x)(start + i) = Value(value[i], At(key_path, i), weights);
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
}

std::string JointVectorReader::CoordinateNames(Space space) const {
  const bool positions = space == Space::kPositions;
  const int n = positions ? model_.nq() : model_.nv();
  std::vector<std::string> names;
  for (int i = 0; i < n; ++i) {
    names.push_back(positions ? model_.position_name(i) : model_.velocity_name(i));
  }
  return "coordinates of " + JoinNames(names, 12);
}

std::string JointVectorReader::JointNames() const {
  std::vector<std::string> names;
  for (JointIndex j = 1; j <= model_.num_joints(); ++j) {
    if (model_.joint_nv(j) > 0) names.push_back(model_.joint_name(j));
  }
  return names.empty() ? std::string("(none: the model has no moving joints)") : JoinNames(names);
}

double JointVectorReader::Value(const YAML::Node& node, const std::string& path,
                                bool weights) const {
  return weights ? reader_.NonNegative(node, path) : reader_.Double(node, path);
}

void JointVectorReader::NormalizeQuaternions(const YAML::Node& node, const std::string& path,
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

}  // namespace idto::config_internal
