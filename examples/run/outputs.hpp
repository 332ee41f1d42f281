#pragma once

// idto-run's output files: the coordinate labels of its CSV files and the check that no output
// overwrites an input or another output.

#include <string>
#include <utility>
#include <vector>

#include "idto/config/config.hpp"
#include "idto/multibody/model.hpp"

namespace idto::examples {

/// Labels of the coordinates of q (positions) or v: the joint name for 1-DoF joints,
/// joint.qw, joint.x, ... for floating joints and joint.x, joint.y, joint.theta for planar ones.
std::vector<std::string> CoordinateLabels(const Model& model, bool positions);

/// Throws InvalidArgument when an output file (flag, path; empty paths are skipped) names the
/// same file as another output or as an input (the YAML file at `config_path`, the URDF files of
/// `config`), naming the flags and the path.
void CheckOutputPaths(const std::vector<std::pair<std::string, std::string>>& outputs,
                      const std::string& config_path, const ExampleConfig& config);

}  // namespace idto::examples
