#include "run/outputs.hpp"

#include <filesystem>
#include <system_error>

#include "idto/core/errors.hpp"

namespace idto::examples {

std::vector<std::string> CoordinateLabels(const Model& model, bool positions) {
  std::vector<std::string> labels;
  for (JointIndex j = 1; j <= model.num_joints(); ++j) {
    const int n = positions ? model.joint_nq(j) : model.joint_nv(j);
    if (n == 0) continue;
    const std::string& name = model.joint_name(j);
    if (n == 1) {
      labels.push_back(name);
      continue;
    }
    std::vector<std::string> parts;
    if (model.joint_type(j) == JointType::kFloating) {
      parts = positions ? std::vector<std::string>{"qw", "qx", "qy", "qz", "x", "y", "z"}
                        : std::vector<std::string>{"wx", "wy", "wz", "vx", "vy", "vz"};
    } else if (model.joint_type(j) == JointType::kPlanar) {
      parts = {"x", "y", "theta"};
    }
    for (int i = 0; i < n; ++i) {
      labels.push_back(name + "." +
                       (i < static_cast<int>(parts.size()) ? parts[i] : std::to_string(i)));
    }
  }
  return labels;
}

void CheckOutputPaths(const std::vector<std::pair<std::string, std::string>>& outputs,
                      const std::string& config_path, const ExampleConfig& config) {
  namespace fs = std::filesystem;
  const auto canonical = [](const std::string& path) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
    return ec ? fs::absolute(path).lexically_normal().string() : p.string();
  };
  std::vector<std::pair<std::string, std::string>> inputs = {
      {"the configuration file", canonical(config_path)}};
  for (const SceneModelConfig& m : config.models) {
    inputs.push_back({"the URDF file", canonical(m.urdf_file)});
  }
  for (size_t i = 0; i < outputs.size(); ++i) {
    const auto& [flag, file] = outputs[i];
    if (file.empty()) continue;
    const std::string path = canonical(file);
    for (const auto& [what, input] : inputs) {
      if (path == input) {
        throw InvalidArgument(flag + " is '" + file + "', " + what +
                              "; expected an output file that is not an input");
      }
    }
    for (size_t j = 0; j < i; ++j) {
      if (!outputs[j].second.empty() && canonical(outputs[j].second) == path) {
        throw InvalidArgument(flag + " and " + outputs[j].first + " both name '" + file +
                              "'; expected a different file for each output");
      }
    }
  }
}

}  // namespace idto::examples
