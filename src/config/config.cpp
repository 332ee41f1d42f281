#include "idto/config/config.hpp"

// YAML example configurations -> Model + ProblemDefinition + SolverOptions + MpcConfig: the top
// level of a file and the public entry points. The sections are read by ConfigLoader
// (config_loader.hpp) through the one reader of yaml_reader.hpp.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "config_loader.hpp"
#include "idto/core/errors.hpp"
#include "yaml_reader.hpp"

namespace idto {

namespace config_internal {

namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kTopLevelKeys = {"name",    "description", "task_success", "scene",
                                                "problem", "solver",      "mpc"};

}  // namespace

ConfigLoader::ConfigLoader(std::string source_name, std::string base_dir,
                           std::vector<std::string> share_dirs)
    : reader_(source_name), base_dir_(std::move(base_dir)), share_dirs_(std::move(share_dirs)) {
  config_.source_file = std::move(source_name);
}

ExampleConfig ConfigLoader::Load(const YAML::Node& root) {
  if (!root.IsDefined() || root.IsNull()) {
    reader_.Fail(root, "(top level)",
                 "the file is empty; expected a map with keys " + JoinNames(kTopLevelKeys));
  }
  const MapReader top(reader_, root, "", kTopLevelKeys);
  config_.name = top.String("name", fs::path(config_.source_file).stem().string());
  config_.description = top.String("description", "");
  config_.task_success = top.String("task_success", "");

  LoadScene(top.Require("scene"), "scene");
  LoadProblem(top.Require("problem"), "problem");
  if (top.Has("solver")) LoadSolver(top.Get("solver"), "solver");
  if (top.Has("mpc")) LoadMpc(top.Get("mpc"), top.Get("problem"));
  return std::move(config_);
}

}  // namespace config_internal

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
  const YAML::Node root = config_internal::ParseYaml(yaml_text, source_name);
  config_internal::ConfigLoader loader(source_name, base_dir, share_dirs);
  try {
    return loader.Load(root);
  } catch (const YAML::Exception& e) {
    // The readers never convert with yaml-cpp; should one of its calls throw all the same, the
    // caller still gets a FileError naming the file (and the line yaml-cpp gives).
    std::string problem = "cannot read the YAML: " + e.msg;
    if (e.mark.line >= 0) problem += " (line " + std::to_string(e.mark.line + 1) + ")";
    ThrowFileError(source_name, "(YAML)", problem);
  }
}

ExampleConfig LoadExampleConfig(const std::string& path,
                                const std::vector<std::string>& share_dirs) {
  namespace fs = std::filesystem;
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

}  // namespace idto
