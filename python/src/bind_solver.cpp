// TrajectoryOptimizer (solve, warm start, evaluation, callbacks), trajectories and summaries.

#include "solver_glue.hpp"

namespace idto::python {

CallbackReturn CheckSignalsCallback(const IterationSummary&) {
  if (!OnMainThread()) return CallbackReturn::kContinue;  // only it runs signal handlers
  py::gil_scoped_acquire gil;
  if (HasPendingError()) return CallbackReturn::kAbort;
  if (PyErr_CheckSignals() != 0) {
    StorePendingError();
    return CallbackReturn::kAbort;
  }
  return CallbackReturn::kContinue;
}

IterationCallback MakePythonCallback(py::object fn) {
  auto shared = std::make_shared<py::object>(std::move(fn));
  return [shared](const IterationSummary& summary) {
    py::gil_scoped_acquire gil;
    if (HasPendingError()) return CallbackReturn::kAbort;
    try {
      const py::object r = (*shared)(summary);
      if (r.is_none()) return CallbackReturn::kContinue;
      if (py::isinstance<py::bool_>(r)) {
        return r.cast<bool>() ? CallbackReturn::kContinue : CallbackReturn::kTerminate;
      }
      if (py::isinstance<CallbackReturn>(r)) return r.cast<CallbackReturn>();
      PyErr_SetString(PyExc_TypeError,
                      "TrajectoryOptimizer callback: returned a value that is not None, a bool or "
                      "a CallbackReturn");
    } catch (py::error_already_set& e) {
      e.restore();
    }
    StorePendingError();
    return CallbackReturn::kAbort;
  };
}

py::tuple SummaryAndTrajectory(SolverSummary summary, Trajectory trajectory) {
  return py::make_tuple(py::cast(std::move(summary)), py::cast(std::move(trajectory)));
}

namespace {

void BindSummaries(py::module_& m) {
  py::enum_<TerminationType>(m, "TerminationType")
      .value("kConverged", TerminationType::kConverged)
      .value("kMaxIterations", TerminationType::kMaxIterations)
      .value("kFailure", TerminationType::kFailure)
      .value("kUserTermination", TerminationType::kUserTermination)
      .value("kUserAbort", TerminationType::kUserAbort);
  m.def("termination_type_name", &TerminationTypeName);
  py::enum_<DoglegStep>(m, "DoglegStep")
      .value("kNewton", DoglegStep::kNewton)
      .value("kCauchy", DoglegStep::kCauchy)
      .value("kDogleg", DoglegStep::kDogleg)
      .value("kNone", DoglegStep::kNone);
  using I = IterationSummary;
  py::class_<I>(m, "IterationSummary", "Statistics of one solver iteration.")
      .def(py::init<>())
      .def_readonly("iteration", &I::iteration)
      .def_readonly("cost", &I::cost)
      .def_readonly("merit", &I::merit)
      .def_readonly("gradient_norm", &I::gradient_norm)
      .def_readonly("step_norm", &I::step_norm)
      .def_readonly("scaled_step_norm", &I::scaled_step_norm)
      .def_readonly("correction_norm", &I::correction_norm)
      .def_readonly("trust_radius", &I::trust_radius)
      .def_readonly("ratio", &I::ratio)
      .def_readonly("accepted", &I::accepted)
      .def_readonly("step_type", &I::step_type)
      .def_readonly("constraint_violation", &I::constraint_violation)
      .def_readonly("trial_cost", &I::trial_cost)
      .def_readonly("trial_with_derivatives", &I::trial_with_derivatives)
      .def_readonly("growth_guard", &I::growth_guard)
      .def_readonly("regularization", &I::regularization)
      .def_readonly("time_derivatives", &I::time_derivatives)
      .def_readonly("time_cost", &I::time_cost)
      .def_readonly("time_hessian", &I::time_hessian)
      .def_readonly("time_factorization", &I::time_factorization)
      .def_readonly("time_multipliers", &I::time_multipliers)
      .def_readonly("time_total", &I::time_total)
      .def_readonly("time_contact", &I::time_contact);
  using S = SolverSummary;
  py::class_<S>(m, "SolverSummary", "The outcome of a solve and its iteration log.")
      .def(py::init<>())
      .def_readonly("termination", &S::termination)
      .def_readonly("message", &S::message)
      .def_readonly("iterations", &S::iterations)
      .def_readonly("initial_cost", &S::initial_cost)
      .def_readonly("final_cost", &S::final_cost)
      .def_readonly("constraint_violation", &S::constraint_violation)
      .def_readonly("solve_time", &S::solve_time)
      .def_readonly("log", &S::log, "list of IterationSummary (a new list at each access)")
      .def_property_readonly(
          "costs",
          [](const S& s) {
            std::vector<double> c;
            for (const IterationSummary& it : s.log) c.push_back(it.cost);
            return ToArray(c);
          },
          "cost at the start of each iteration (numpy)")
      .def("mean_iteration_time", &S::mean_iteration_time)
      .def("brief_report", &S::BriefReport)
      .def("full_report", &S::FullReport)
      .def("to_csv", &S::ToCsv)
      .def("__repr__", [](const S& s) { return "<idto.SolverSummary: " + s.BriefReport() + ">"; });
}

void BindTrajectory(py::module_& m) {
  static constexpr const char* kWhere = "Trajectory";
  py::class_<Trajectory>(m, "Trajectory",
                         "q (N + 1, nq), v (N + 1, nv), tau (N + 1, nv; tau_N = 0) as numpy")
      .def(py::init<>())
      .def_property(
          "q", [](const Trajectory& t) { return ToArray(t.q); },
          [](Trajectory& t, py::handle x) { t.q = ToVectors(x, kWhere, "q", -1, -1); })
      .def_property(
          "v", [](const Trajectory& t) { return ToArray(t.v); },
          [](Trajectory& t, py::handle x) { t.v = ToVectors(x, kWhere, "v", -1, -1); })
      .def_property(
          "tau", [](const Trajectory& t) { return ToArray(t.tau); },
          [](Trajectory& t, py::handle x) { t.tau = ToVectors(x, kWhere, "tau", -1, -1); })
      .def("__len__", [](const Trajectory& t) { return t.q.size(); });
}

/// q_0..q_N of the optimizer's problem.
std::vector<Eigen::VectorXd> Knots(const TrajectoryOptimizer& o, py::handle q, const char* where,
                                   const char* name = "q") {
  return ToVectors(q, where, name, o.problem().num_steps + 1, o.model().nq(), "N + 1, nq");
}

void BindOptimizerSolve(py::class_<TrajectoryOptimizer>& c) {
  using T = TrajectoryOptimizer;
  c.def(
       "solve",
       [](T& o, py::handle q_guess) {
         const auto guess = Knots(o, q_guess, "TrajectoryOptimizer.solve", "q_guess");
         Trajectory traj;
         SolverSummary s = RunWithoutGil([&] { return o.Solve(guess, &traj); });
         return SummaryAndTrajectory(std::move(s), std::move(traj));
       },
       py::arg("q_guess"),
       "Solves from q_guess ((N + 1) x nq); returns (SolverSummary, Trajectory). Releases the "
       "GIL; Ctrl-C stops it (KeyboardInterrupt).")
      .def(
          "solve_warm_start",
          [](T& o) {
            Trajectory traj;
            SolverSummary s = RunWithoutGil([&] { return o.SolveWarmStart(&traj); });
            return SummaryAndTrajectory(std::move(s), std::move(traj));
          },
          "Continues from the last solution and trust radius (MPC).")
      .def(
          "reset_initial_conditions",
          [](T& o, py::handle q_init, py::handle v_init) {
            static constexpr const char* kWhere = "TrajectoryOptimizer.reset_initial_conditions";
            o.ResetInitialConditions(ToVector(q_init, kWhere, "q_init", o.model().nq(), "nq"),
                                     ToVector(v_init, kWhere, "v_init", o.model().nv(), "nv"));
          },
          py::arg("q_init"), py::arg("v_init"))
      .def(
          "update_nominal_trajectory",
          [](T& o, py::handle q_nom, py::handle v_nom) {
            static constexpr const char* kWhere = "TrajectoryOptimizer.update_nominal_trajectory";
            const int n = o.problem().num_steps + 1;
            o.UpdateNominalTrajectory(
                ToVectors(q_nom, kWhere, "q_nom", n, o.model().nq(), "N + 1, nq"),
                ToVectors(v_nom, kWhere, "v_nom", n, o.model().nv(), "N + 1, nv"));
          },
          py::arg("q_nom"), py::arg("v_nom"))
      .def(
          "set_iterate",
          [](T& o, py::handle q) { o.SetIterate(Knots(o, q, "TrajectoryOptimizer.set_iterate")); },
          py::arg("q"))
      .def(
          "add_callback",
          [](T& o, py::object fn) {
            if (!PyCallable_Check(fn.ptr())) {
              throw py::type_error("TrajectoryOptimizer.add_callback: fn is not callable");
            }
            o.AddCallback(MakePythonCallback(std::move(fn)));
          },
          py::arg("fn"),
          "fn(IterationSummary) after each iteration, with the GIL: returns None/True (continue), "
          "False or CallbackReturn.kTerminate (stop), CallbackReturn.kAbort; exceptions abort "
          "the solve and are raised by it.");
}

void BindOptimizerEval(py::class_<TrajectoryOptimizer>& c) {
  using T = TrajectoryOptimizer;
  c.def(
       "eval_cost",
       [](T& o, py::handle q) {
         const auto k = Knots(o, q, "TrajectoryOptimizer.eval_cost");
         return RunWithoutGil([&] { return o.EvalCost(k); });
       },
       py::arg("q"))
      .def(
          "eval_trajectory",
          [](T& o, py::handle q) {
            const auto k = Knots(o, q, "TrajectoryOptimizer.eval_trajectory");
            return RunWithoutGil([&] {
              Trajectory t;
              o.EvalTrajectory(k, &t);
              return t;
            });
          },
          py::arg("q"))
      .def(
          "eval_gradient",
          [](T& o, py::handle q) {
            const auto k = Knots(o, q, "TrajectoryOptimizer.eval_gradient");
            return ToArray(RunWithoutGil([&] {
              Eigen::VectorXd g;
              o.EvalGradient(k, &g);
              return g;
            }));
          },
          py::arg("q"), "Gradient with respect to q_1..q_N (N nq).")
      .def(
          "eval_dense_hessian",
          [](T& o, py::handle q) {
            const auto k = Knots(o, q, "TrajectoryOptimizer.eval_dense_hessian");
            return ToArray(RunWithoutGil([&] { return o.EvalDenseHessian(k); }));
          },
          py::arg("q"))
      .def(
          "eval_constraints",
          [](T& o, py::handle q) {
            const auto k = Knots(o, q, "TrajectoryOptimizer.eval_constraints");
            return ToArray(RunWithoutGil([&] {
              Eigen::VectorXd h;
              o.EvalConstraints(k, &h);
              return h;
            }));
          },
          py::arg("q"), "h(q): unactuated rows of tau_0..tau_{N-1} (N n_u).")
      .def("trust_radius", &T::trust_radius)
      .def_property_readonly(
          "problem", [](const T& o) { return o.problem(); }, "(a copy)")
      .def_property_readonly("model", &T::model, py::return_value_policy::reference_internal)
      .def_property(
          "options", &T::mutable_options,
          [](T& o, const SolverOptions& options) {
            std::string why;
            if (!options.IsValid(&why)) throw InvalidArgument(why);
            o.mutable_options() = options;
          },
          py::return_value_policy::reference_internal);
}

}  // namespace

void BindSolver(py::module_& m) {
  BindSummaries(m);
  BindTrajectory(m);
  py::enum_<CallbackReturn>(m, "CallbackReturn")
      .value("kContinue", CallbackReturn::kContinue)
      .value("kTerminateSuccessfully", CallbackReturn::kTerminateSuccessfully)
      .value("kAbort", CallbackReturn::kAbort)
      .value("kTerminate", CallbackReturn::kTerminate);
  py::class_<TrajectoryOptimizer> c(m, "TrajectoryOptimizer", "The IDTO solver.");
  c.def(py::init(
            [](const Model& model, const ProblemDefinition& problem, const SolverOptions& options) {
              auto o = std::make_unique<TrajectoryOptimizer>(model, problem, options);
              o->AddCallback(&CheckSignalsCallback);
              return o;
            }),
        py::arg("model"), py::arg("problem"), py::arg("options") = SolverOptions());
  BindOptimizerSolve(c);
  BindOptimizerEval(c);
}

}  // namespace idto::python
