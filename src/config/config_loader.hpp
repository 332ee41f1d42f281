#pragma once

// The loader of example configuration files (private to src/config/). One ConfigLoader reads
// one file; its sections are defined in one source file each:
//   config.cpp           the top level (Load) and the public entry points
//   scene_section.cpp    scene: models (URDF), extra geometry, gravity
//   contact_section.cpp  scene.contact and mpc.contact
//   problem_section.cpp  problem and mpc.problem
//   solver_section.cpp   solver and mpc.solver
//   mpc_config.cpp       mpc: the rest of the section (controller, plant, closed loop)
// Every value is read through yaml_reader.hpp, so every section follows the same rules.

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "idto/config/config.hpp"
#include "idto/contact/contact_engine.hpp"
#include "idto/multibody/model_builder.hpp"
#include "yaml_reader.hpp"

namespace idto::config_internal {

/// Reads one configuration file's YAML tree into an ExampleConfig.
class ConfigLoader {
 public:
  /// `source_name` names the file in messages; URDF paths are resolved against `base_dir` (the
  /// file's folder) and `share_dirs` (LoadExampleConfig).
  ConfigLoader(std::string source_name, std::string base_dir, std::vector<std::string> share_dirs);

  /// Reads every section of `root` (the whole file). Throws FileError.
  ExampleConfig Load(const YAML::Node& root);

 private:
  // scene_section.cpp: config_.models, config_.model, enable_contact_, contact_.
  void LoadScene(const YAML::Node& node, const std::string& path);
  void LoadModel(const MapReader& m, ModelBuilder* builder);
  void LoadGeometry(const MapReader& g, ModelBuilder* builder);

  // contact_section.cpp: contact_ (pairs, groups, overrides, law parameters).
  void LoadContact(const YAML::Node& node, const std::string& path);
  /// mpc.contact into contact_: law parameters replaced, per-pair overrides appended.
  void LoadMpcContact(const YAML::Node& node, const std::string& path);
  void LoadContactGroups(const YAML::Node& node, const std::string& path);
  void LoadContactOverrides(const YAML::Node& node, const std::string& path);
  std::string ContactName(const YAML::Node& node, const std::string& path) const;
  std::vector<std::pair<std::string, std::string>> ReadPairs(const YAML::Node& node,
                                                             const std::string& path) const;

  // problem_section.cpp: config_.problem, config_.initial_guess, config_.mpc_problem.
  void LoadProblem(const YAML::Node& node, const std::string& path);
  void ReadHorizon(const MapReader& p, ProblemDefinition* problem) const;
  void ReadNominal(const MapReader& p, ProblemDefinition* problem) const;
  void ReadWeights(const MapReader& p, ProblemDefinition* problem) const;
  void ReadUnactuatedDofs(const MapReader& p, ProblemDefinition* problem) const;
  void ReadLimits(const MapReader& p, ProblemDefinition* problem) const;
  void LoadMpcProblem(const YAML::Node& problem, const YAML::Node& overrides);

  // solver_section.cpp: config_.solver.
  void LoadSolver(const YAML::Node& node, const std::string& path);

  // mpc_config.cpp: config_.mpc, config_.mpc_problem, config_.mpc_solver.
  void LoadMpc(const YAML::Node& mpc, const YAML::Node& open_loop_problem);

  Reader reader_;
  std::string base_dir_;
  std::vector<std::string> share_dirs_;
  ExampleConfig config_;
  bool enable_contact_{true};  ///< scene.enable_contact
  ContactOptions contact_;     ///< scene.contact (during mpc.contact: the controller's)
};

}  // namespace idto::config_internal
