#pragma once

/// @file
/// Example configurations: one YAML file describing a scene (URDF models, extra world geometry,
/// gravity, contact), a trajectory optimization problem and solver options (design.md §8). Every
/// key is documented in docs/config.md. yaml-cpp is used only in src/.
///
/// Layout of a file (top-level keys; `scene` and `problem` are required):
/// @code{.yaml}
/// name: pendulum            # default: the file name without .yaml
/// description: "..."        # free text
/// task_success: "..."       # free text: the example's success criterion
/// scene:   {models: [...], geometry: [...], gravity: [0, 0, -9.81], enable_contact: true,
///           contact: {...}}
/// problem: {time_step: 0.05, horizon: 2.0, q_init: ..., v_init: ..., nominal: {...},
///           weights: {Qq: ..., Qv: ..., R: ..., Qfq: ..., Qfv: ...}, unactuated_dofs: [...],
///           initial_guess: interpolate}
/// solver:  {max_iterations: 100, constraint_method: lagrange, ...}   # SolverOptions fields
/// mpc:     {control_rate: 100, kp: ..., problem: {...}, solver: {...}, ...}   # MpcConfig
/// @endcode
///
/// Every section, `mpc` included, is read by one YAML reader (src/config/yaml_reader.hpp) from
/// the file's own YAML tree. Errors are FileError whose message names the file, the key path
/// (for example "problem.weights.Qq.elbow" or "mpc.kp.knee"), the value found and what was
/// expected, and the line in the file: "pendulum.yaml: problem.time_step: is -0.05; expected a
/// finite positive number (line 12)". Unknown keys, duplicate keys, wrong sizes, wrong types,
/// non-finite numbers, non-integers where an integer is expected (2.5, 1e300), negative
/// weights, non-positive time steps, unknown joint/body/geometry names and unreadable URDF
/// files are errors. No yaml-cpp exception escapes.
///
/// Numbers may be written as YAML numbers or with pi: "pi", "-pi/2", "2*pi", "0.5*pi/3".

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "idto/config/mpc_config.hpp"
#include "idto/multibody/model.hpp"
#include "idto/parsers/urdf.hpp"
#include "idto/problem/problem_definition.hpp"
#include "idto/solver/solver_options.hpp"

namespace idto {

/// How idto-run (and MakeInitialGuess) builds the first iterate q_0..q_N.
enum class InitialGuessType {
  kInterpolate,  ///< linear from q_init (k = 0) to the last nominal configuration (k = N);
                 ///< quaternions slerped (the default)
  kConstant,     ///< q_init at every step
  kNominal       ///< the nominal trajectory, with q_0 = q_init
};

/// "interpolate", "constant" or "nominal".
std::string InitialGuessTypeName(InitialGuessType type);

/// One URDF model of a scene, as the file gave it.
struct SceneModelConfig {
  std::string urdf_file;  ///< resolved path of the URDF file
  UrdfOptions options;    ///< base type, pose, planar normal, prefix, inscribed spheres
};

/// Everything a configuration file describes.
struct ExampleConfig {
  std::string name;          ///< `name`, or the file name without its extension
  std::string source_file;   ///< the YAML file (or source name) it was loaded from
  std::string description;   ///< `description` (free text, may be empty)
  std::string task_success;  ///< `task_success`: the success criterion in words (may be empty)

  std::vector<SceneModelConfig> models;  ///< the scene's URDF models, in order
  Model model;                           ///< the scene as one Model
  /// What the scene's URDF files contain that idto ignores by design (UrdfWarning, naming the
  /// file and the element: a <transmission>, <dynamics friction>, mass on a link welded to the
  /// world, ...), in model order. idto-run and idto-campaign print them on stderr; Python:
  /// Example.urdf_warnings.
  std::vector<UrdfWarning> urdf_warnings;
  ProblemDefinition problem;  ///< validated against `model`
  SolverOptions solver;       ///< valid (SolverOptions::IsValid)
  InitialGuessType initial_guess{InitialGuessType::kInterpolate};

  /// The `mpc` section (model predictive control options, idto/config/mpc_config.hpp), read and
  /// checked with the rest of the file; empty when the file has no `mpc` section
  /// (ParseMpcConfig then gives the defaults).
  std::optional<MpcConfig> mpc;
  /// The controller's problem when `mpc.problem` or `mpc.contact` is given: `problem` with the
  /// keys of `mpc.problem` replacing the open-loop ones (`nominal` and `weights` merged key by
  /// key) and the contact law parameters of `mpc.contact` replacing the scene's (its per-pair
  /// `overrides` follow the scene's, so they win; pair filters stay the scene's), validated like
  /// `problem` (errors name "mpc.problem.<key>" or "mpc.contact.<key>"). Empty otherwise: the
  /// controller uses `problem`.
  std::optional<ProblemDefinition> mpc_problem;
  /// The controller's solver options when `mpc.solver` is given: `solver` with the keys of
  /// `mpc.solver` replacing the open-loop ones (errors name "mpc.solver.<key>"). Empty
  /// otherwise: the controller uses `solver`. (`mpc.contact`, the controller's contact law
  /// parameters over the scene's, ends up in mpc_problem->contact.)
  std::optional<SolverOptions> mpc_solver;
  /// The controller's model when `mpc.model_mass_scale` is given: `model` with those bodies'
  /// masses and rotational inertias scaled (ScaleBodyInertias; errors name
  /// "mpc.model_mass_scale.<body>"), so that the controller plans with other masses than the
  /// plant has. Empty otherwise: the controller uses `model`.
  std::optional<Model> mpc_model;
  /// The controller's `initial_guess` when `mpc.problem.initial_guess` is given (its cold start
  /// builds ControllerInitialGuess with it). Empty otherwise.
  std::optional<InitialGuessType> mpc_initial_guess;
};

/// The model the controller plans with: mpc_model when given, else model.
const Model& ControllerModel(const ExampleConfig& config);
/// The controller's problem: mpc_problem when given, else problem.
const ProblemDefinition& ControllerProblem(const ExampleConfig& config);

/// Loads and checks a configuration file. URDF paths in `scene.models[i].urdf` are resolved, in
/// order: absolute paths as given; relative to the YAML file's folder; then `<dir>/models/<path>`
/// and `<dir>/<path>` for each dir in `share_dirs`, and finally for the folder two levels above
/// the YAML file (examples/<name>/<name>.yaml sits two levels below the share folder).
/// Throws FileError (see the file comment) on any problem.
ExampleConfig LoadExampleConfig(const std::string& path,
                                const std::vector<std::string>& share_dirs = {});

/// As LoadExampleConfig, from YAML text. `source_name` stands for the file in messages and
/// `base_dir` for the YAML file's folder when resolving URDF paths.
ExampleConfig LoadExampleConfigString(const std::string& yaml_text, const std::string& source_name,
                                      const std::string& base_dir = ".",
                                      const std::vector<std::string>& share_dirs = {});

/// Resolves an example name or a file path to a configuration file. Returns `name_or_path`
/// itself when it names an existing file; otherwise, when it looks like a name (no '/' and no
/// ".yaml"/".yml" suffix), the first existing `<dir>/examples/<name>/<name>.yaml` over
/// `search_dirs`, in order. Throws FileError listing the places searched and the examples
/// found there when nothing matches.
std::string FindExampleConfig(const std::string& name_or_path,
                              const std::vector<std::string>& search_dirs);

/// Names of the examples found as `<dir>/examples/<name>/<name>.yaml` over `search_dirs`
/// (sorted, unique).
std::vector<std::string> ListExamples(const std::vector<std::string>& search_dirs);

/// The usual share folders of a program, in search order: $IDTO_SHARE_DIR when set,
/// `build_tree_dir` when non-empty (the source tree, for programs run from the build tree), and
/// `<folder of executable_path>/../share/idto` (the install tree) when `executable_path` is
/// non-empty. Folders that do not exist are kept (searching skips them).
std::vector<std::string> DefaultShareDirs(const std::string& build_tree_dir,
                                          const std::string& executable_path);

/// The first iterate q_0..q_N (N + 1 configurations, nq each) for `config.initial_guess`.
std::vector<Eigen::VectorXd> MakeInitialGuess(const ExampleConfig& config);

/// The first iterate of the controller's cold start (N + 1 configurations of
/// ControllerProblem(config), nq each): MakeInitialGuess(config) when the controller's problem
/// has the open loop's horizon and initial state and `mpc.problem` names no initial_guess of its
/// own; otherwise the guess of type mpc_initial_guess (else initial_guess) built for the
/// controller's problem. The closed loop's plant starts from that problem's q_init, v_init.
std::vector<Eigen::VectorXd> ControllerInitialGuess(const ExampleConfig& config);

/// Interpolates configurations of `model`: (1 - s) q_a + s q_b for every coordinate except the
/// quaternions of floating joints, which are slerped (shortest arc, normalized). s in [0, 1].
Eigen::VectorXd InterpolateConfiguration(const Model& model, const Eigen::VectorXd& q_a,
                                         const Eigen::VectorXd& q_b, double s);

}  // namespace idto
