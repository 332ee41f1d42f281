#pragma once

// Per-coordinate vectors of the config files (private to src/config/): q_init, v_init, the
// nominal trajectory, the cost weights and the MPC gains.

#include <string>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>

#include "idto/multibody/model.hpp"
#include "yaml_reader.hpp"

namespace idto::config_internal {

/// Reads a vector over the positions (nq) or velocities (nv) of `model`: a list of the full
/// size, a number (weights: every entry; states: only when the size is 1), or a map
/// joint name -> number or list of the joint's size (weights also take `default`). Entries not
/// given keep their value in `base`. Errors name the key path ("problem.weights.Qq.elbow") and
/// the line.
class JointVectorReader {
 public:
  enum class Space { kPositions, kVelocities };

  JointVectorReader(const Reader& reader, const Model& model) : reader_(reader), model_(model) {}

  /// The vector at `node` (key path `path`) over `space`, starting from `base`. `weights`:
  /// entries must be >= 0 and a map may give a `default`; otherwise (states) the quaternions of
  /// floating joints are normalized.
  Eigen::VectorXd Read(const YAML::Node& node, const std::string& path, Space space,
                       const Eigen::VectorXd& base, bool weights) const;

  /// "coordinates of shoulder, elbow" (joint names, repeated for each of their coordinates),
  /// shortened for big models.
  std::string CoordinateNames(Space space) const;

  /// The names of the joints that move, comma-separated.
  std::string JointNames() const;

 private:
  void ReadMap(const YAML::Node& node, const std::string& path, Space space, bool weights,
               Eigen::VectorXd* x) const;
  double Value(const YAML::Node& node, const std::string& path, bool weights) const;
  void NormalizeQuaternions(const YAML::Node& node, const std::string& path,
                            Eigen::VectorXd* q) const;

  const Reader& reader_;
  const Model& model_;
};

}  // namespace idto::config_internal
