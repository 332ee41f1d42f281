// Problem definition (weights, nominal trajectory, contact) and solver options.

#include "convert.hpp"

namespace idto::python {
namespace {

template <typename C>
void VectorProperty(py::class_<C>& c, const char* name, Eigen::VectorXd C::*field,
                    const char* where, const char* doc = "") {
  c.def_property(
      name, [field](const C& o) { return ToArray(o.*field); },
      [field, name, where](C& o, py::handle x) { o.*field = ToVector(x, where, name); }, doc);
}

/// A list of 1-D arrays; set from a list of arrays or a 2-D array (one row per knot).
template <typename C>
void VectorListProperty(py::class_<C>& c, const char* name, std::vector<Eigen::VectorXd> C::*field,
                        const char* where, const char* doc = "") {
  c.def_property(
      name,
      [field](const C& o) {
        py::list out;
        for (const Eigen::VectorXd& x : o.*field) out.append(ToArray(x));
        return out;
      },
      [field, name, where](C& o, py::handle x) { o.*field = ToVectors(x, where, name, -1, -1); },
      doc);
}

void BindContact(py::module_& m) {
  py::class_<ContactParameters>(m, "ContactParameters", "The smooth compliant contact law.")
      .def(py::init<>())
      .def_readwrite("stiffness", &ContactParameters::stiffness)
      .def_readwrite("smoothing", &ContactParameters::smoothing)
      .def_readwrite("dissipation_velocity", &ContactParameters::dissipation_velocity)
      .def_readwrite("friction_coefficient", &ContactParameters::friction_coefficient)
      .def_readwrite("stiction_velocity", &ContactParameters::stiction_velocity)
      .def("validate", &ContactParameters::Validate, py::arg("where") = "ContactParameters");
  py::class_<ContactParameterOverride>(m, "ContactParameterOverride")
      .def(py::init<>())
      .def_readwrite("a", &ContactParameterOverride::a)
      .def_readwrite("b", &ContactParameterOverride::b)
      .def_readwrite("stiffness", &ContactParameterOverride::stiffness)
      .def_readwrite("smoothing", &ContactParameterOverride::smoothing)
      .def_readwrite("dissipation_velocity", &ContactParameterOverride::dissipation_velocity)
      .def_readwrite("friction_coefficient", &ContactParameterOverride::friction_coefficient)
      .def_readwrite("stiction_velocity", &ContactParameterOverride::stiction_velocity);
  py::class_<ContactOptions>(m, "ContactOptions",
                             "Pairs, parameters and pruning (list fields: assign whole lists).")
      .def(py::init<>())
      .def_readwrite("parameters", &ContactOptions::parameters)
      .def_readwrite("overrides", &ContactOptions::overrides)
      .def_readwrite("excluded_pairs", &ContactOptions::excluded_pairs)
      .def_readwrite("collision_groups", &ContactOptions::collision_groups)
      .def_readwrite("included_pairs", &ContactOptions::included_pairs)
      .def_readwrite("force_tolerance", &ContactOptions::force_tolerance);
}

void BindLimits(py::module_& m) {
  static constexpr const char* kWhere = "LimitPenalties";
  py::class_<LimitPenalties> c(m, "LimitPenalties",
                               "Joint limits as penalties (weights 0: off; empty bounds: the "
                               "model's URDF limits).");
  c.def(py::init<>())
      .def_readwrite("position_weight", &LimitPenalties::position_weight)
      .def_readwrite("velocity_weight", &LimitPenalties::velocity_weight)
      .def_readwrite("effort_weight", &LimitPenalties::effort_weight)
      .def("any", &LimitPenalties::any);
  VectorProperty(c, "q_lower", &LimitPenalties::q_lower, kWhere, "nq, or empty");
  VectorProperty(c, "q_upper", &LimitPenalties::q_upper, kWhere, "nq, or empty");
  VectorProperty(c, "v_max", &LimitPenalties::v_max, kWhere, "nv, or empty");
  VectorProperty(c, "tau_max", &LimitPenalties::tau_max, kWhere, "nv, or empty");
}

void BindProblemDefinition(py::module_& m) {
  BindLimits(m);
  static constexpr const char* kWhere = "ProblemDefinition";
  py::class_<ProblemDefinition> c(m, "ProblemDefinition",
                                  "One trajectory optimization problem (paper section 4).");
  c.def(py::init<>())
      .def_readwrite("time_step", &ProblemDefinition::time_step)
      .def_readwrite("num_steps", &ProblemDefinition::num_steps);
  VectorProperty(c, "q_init", &ProblemDefinition::q_init, kWhere, "q_0 (nq)");
  VectorProperty(c, "v_init", &ProblemDefinition::v_init, kWhere, "v_0 (nv)");
  VectorListProperty(c, "q_nom", &ProblemDefinition::q_nom, kWhere, "N + 1 arrays of nq");
  VectorListProperty(c, "v_nom", &ProblemDefinition::v_nom, kWhere, "N + 1 arrays of nv");
  VectorProperty(c, "Qq", &ProblemDefinition::Qq, kWhere);
  VectorProperty(c, "Qv", &ProblemDefinition::Qv, kWhere);
  VectorProperty(c, "R", &ProblemDefinition::R, kWhere);
  VectorProperty(c, "Qfq", &ProblemDefinition::Qfq, kWhere);
  VectorProperty(c, "Qfv", &ProblemDefinition::Qfv, kWhere);
  c.def_readwrite("unactuated_dofs", &ProblemDefinition::unactuated_dofs,
                  "Velocity indices with zero generalized force (None: the base DoFs)")
      .def_readwrite("enable_contact", &ProblemDefinition::enable_contact)
      .def_readwrite("contact", &ProblemDefinition::contact)
      .def_readwrite("limits", &ProblemDefinition::limits)
      .def("validate", &ProblemDefinition::Validate, py::arg("model"),
           "Raises ValueError naming the field unless the problem fits the model.")
      .def("get_unactuated_dofs", &ProblemDefinition::UnactuatedDofs, py::arg("model"),
           "The unactuated DoFs in effect (sorted).")
      .def_static("make_default", &ProblemDefinition::MakeDefault, py::arg("model"),
                  py::arg("time_step"), py::arg("num_steps"))
      .def(
          "set_constant_nominal",
          [](ProblemDefinition& p, py::handle q, py::handle v) {
            p.SetConstantNominal(ToVector(q, "set_constant_nominal", "q"),
                                 ToVector(v, "set_constant_nominal", "v"));
          },
          py::arg("q"), py::arg("v"))
      .def("__copy__", [](const ProblemDefinition& p) { return p; })
      .def("__deepcopy__", [](const ProblemDefinition& p, py::dict) { return p; });
}

void BindSolverOptions(py::module_& m) {
  py::enum_<ConstraintMethod>(m, "ConstraintMethod")
      .value("kNone", ConstraintMethod::kNone)
      .value("kPenalty", ConstraintMethod::kPenalty)
      .value("kLagrangeMultipliers", ConstraintMethod::kLagrangeMultipliers);
  m.def("constraint_method_name", &ConstraintMethodName);
  py::enum_<DerivativeMethod>(m, "DerivativeMethod")
      .value("kForwardDifferences", DerivativeMethod::kForwardDifferences)
      .value("kCentralDifferences", DerivativeMethod::kCentralDifferences)
      .value("kAnalytic", DerivativeMethod::kAnalytic);
  py::enum_<ScalingMethod>(m, "ScalingMethod")
      .value("kNone", ScalingMethod::kNone)
      .value("kSqrt", ScalingMethod::kSqrt)
      .value("kDoubleSqrt", ScalingMethod::kDoubleSqrt);
  using O = SolverOptions;
  py::class_<O>(m, "SolverOptions", "Solver options with documented defaults.")
      .def(py::init<>())
      .def_readwrite("max_iterations", &O::max_iterations)
      .def_readwrite("num_threads", &O::num_threads)
      .def_readwrite("constraint_method", &O::constraint_method)
      .def_readwrite("penalty_weight", &O::penalty_weight)
      .def_readwrite("derivative_method", &O::derivative_method)
      .def_readwrite("finite_difference_step", &O::finite_difference_step)
      .def_readwrite("scaling", &O::scaling)
      .def_readwrite("initial_trust_radius", &O::initial_trust_radius)
      .def_readwrite("max_trust_radius", &O::max_trust_radius)
      .def_readwrite("acceptance_ratio", &O::acceptance_ratio)
      .def_readwrite("cost_tolerance", &O::cost_tolerance)
      .def_readwrite("gradient_tolerance", &O::gradient_tolerance)
      .def_readwrite("step_tolerance", &O::step_tolerance)
      .def_readwrite("fixed_iterations", &O::fixed_iterations)
      .def_readwrite("trial_derivatives", &O::trial_derivatives)
      .def_readwrite("constraint_correction", &O::constraint_correction)
      .def_readwrite("kkt_extended_residual", &O::kkt_extended_residual)
      .def_readwrite("kkt_extended_threshold", &O::kkt_extended_threshold)
      .def_readwrite("verbosity", &O::verbosity)
      .def("is_valid", [](const O& o) { return o.IsValid(nullptr); })
      .def(
          "invalid_reason",
          [](const O& o) {
            std::string why;
            return o.IsValid(&why) ? std::string() : why;
          },
          "Why the options are not valid ('' when they are).")
      .def("__copy__", [](const O& o) { return o; })
      .def("__deepcopy__", [](const O& o, py::dict) { return o; });
}

}  // namespace

void BindProblem(py::module_& m) {
  BindContact(m);
  BindProblemDefinition(m);
  BindSolverOptions(m);
}

}  // namespace idto::python
