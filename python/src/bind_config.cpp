// Example configuration files (YAML): load_example and the objects it returns.

#include "convert.hpp"

namespace idto::python {
namespace {

/// What load_example returns: the configuration and its parsed `mpc` section.
struct Example {
  ExampleConfig config;
  MpcConfig mpc;
};

Example LoadExample(const std::string& name_or_path, const std::vector<std::string>& share_dirs) {
  const std::string path = FindExampleConfig(name_or_path, share_dirs);
  Example e;
  e.config = LoadExampleConfig(path, share_dirs);
  e.mpc = ParseMpcConfig(e.config);
  return e;
}

void BindExample(py::module_& m) {
  const auto ref = py::return_value_policy::reference_internal;
  py::class_<Example>(m, "Example",
                      "An example configuration: model, problem, solver and MPC options.")
      .def_property_readonly("name", [](const Example& e) { return e.config.name; })
      .def_property_readonly("source_file", [](const Example& e) { return e.config.source_file; })
      .def_property_readonly("description", [](const Example& e) { return e.config.description; })
      .def_property_readonly("task_success", [](const Example& e) { return e.config.task_success; })
      .def_property_readonly(
          "model", [](Example& e) -> Model& { return e.config.model; }, ref)
      .def_property_readonly(
          "urdf_warnings",
          [](const Example& e) {
            std::vector<std::string> out;
            for (const UrdfWarning& w : e.config.urdf_warnings) out.push_back(w.ToString());
            return out;
          },
          "What the scene's URDF files hold that idto ignores by design (\"file: element: "
          "message\" strings, in model order)")
      .def_property(
          "problem", [](Example& e) -> ProblemDefinition& { return e.config.problem; },
          [](Example& e, const ProblemDefinition& p) { e.config.problem = p; }, ref)
      .def_property(
          "solver_options", [](Example& e) -> SolverOptions& { return e.config.solver; },
          [](Example& e, const SolverOptions& o) { e.config.solver = o; }, ref)
      .def_property(
          "initial_guess_type", [](const Example& e) { return e.config.initial_guess; },
          [](Example& e, InitialGuessType t) { e.config.initial_guess = t; })
      .def_property(
          "mpc", [](Example& e) -> MpcConfig& { return e.mpc; },
          [](Example& e, const MpcConfig& c) { e.mpc = c; }, ref,
          "The `mpc` section: controller, closed_loop, plant, builtin, mujoco options")
      .def_property(
          "mpc_problem",
          [](Example& e) -> ProblemDefinition& {
            if (!e.config.mpc_problem) e.config.mpc_problem = e.config.problem;
            return *e.config.mpc_problem;
          },
          [](Example& e, const ProblemDefinition& p) { e.config.mpc_problem = p; }, ref,
          "The controller's problem (mpc.problem over problem)")
      .def_property_readonly(
          "mpc_model", [](const Example& e) -> const Model& { return ControllerModel(e.config); },
          ref, "The model the controller plans with (mpc.model_mass_scale over model)")
      .def_property(
          "mpc_solver_options",
          [](Example& e) -> SolverOptions& {
            if (!e.config.mpc_solver) e.config.mpc_solver = e.config.solver;
            return *e.config.mpc_solver;
          },
          [](Example& e, const SolverOptions& o) { e.config.mpc_solver = o; }, ref,
          "The controller's solver options (mpc.solver over solver)")
      .def(
          "initial_guess", [](const Example& e) { return ToArray(MakeInitialGuess(e.config)); },
          "The first iterate q_0..q_N ((N + 1) x nq) for the problem and initial_guess_type.")
      .def(
          "controller_initial_guess",
          [](const Example& e) { return ToArray(ControllerInitialGuess(e.config)); },
          "The first iterate of the controller's cold start ((N + 1) x nq; "
          "ControllerInitialGuess).")
      .def(
          "make_plant",
          [](const Example& e) {
            std::unique_ptr<sim::Plant> plant =
                e.mpc.plant == "mujoco" ? sim::MakeMujocoPlant(e.config.model, e.mpc.mujoco)
                                        : sim::MakeBuiltinPlant(e.config.model, e.mpc.builtin);
            const ProblemDefinition& p = ControllerProblem(e.config);
            plant->Reset(p.q_init, p.v_init);
            return plant;
          },
          "The plant of mpc.plant, reset to the controller problem's initial state.")
      .def("__repr__", [](const Example& e) { return "<idto.Example '" + e.config.name + "'>"; });
}

void BindMpcConfig(py::module_& m) {
  py::class_<MpcConfig>(m, "MpcConfig", "The `mpc` section of an example file.")
      .def(py::init<>())
      .def_readwrite("controller", &MpcConfig::controller)
      .def_readwrite("closed_loop", &MpcConfig::closed_loop)
      .def_readwrite("plant", &MpcConfig::plant)
      .def_readwrite("builtin", &MpcConfig::builtin)
      .def_readwrite("mujoco", &MpcConfig::mujoco)
      .def_readwrite("initial_iterations", &MpcConfig::initial_iterations);
}

}  // namespace

void BindConfig(py::module_& m) {
  py::enum_<InitialGuessType>(m, "InitialGuessType")
      .value("kInterpolate", InitialGuessType::kInterpolate)
      .value("kConstant", InitialGuessType::kConstant)
      .value("kNominal", InitialGuessType::kNominal);
  BindMpcConfig(m);
  BindExample(m);
  m.def("_load_example", &LoadExample, py::arg("name_or_path"), py::arg("share_dirs"));
  m.def("find_example_config", &FindExampleConfig, py::arg("name_or_path"), py::arg("search_dirs"));
  m.def("list_examples", &ListExamples, py::arg("search_dirs"));
  m.def(
      "interpolate_configuration",
      [](const Model& model, py::handle q_a, py::handle q_b, double s) {
        static constexpr const char* kWhere = "interpolate_configuration";
        return ToArray(InterpolateConfiguration(model,
                                                ToVector(q_a, kWhere, "q_a", model.nq(), "nq"),
                                                ToVector(q_b, kWhere, "q_b", model.nq(), "nq"), s));
      },
      py::arg("model"), py::arg("q_a"), py::arg("q_b"), py::arg("s"));
}

}  // namespace idto::python
