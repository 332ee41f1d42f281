// Model predictive control: options, PD+ tracking, plans, the controller and the closed loop.

#include "solver_glue.hpp"

namespace idto::python {
namespace {

using mpc::ClosedLoopLog;
using mpc::ClosedLoopOptions;
using mpc::Controller;
using mpc::MpcOptions;
using mpc::Plan;

void BindOptions(py::module_& m) {
  py::class_<mpc::PdGains>(m, "PdGains", "PD gains per velocity coordinate (nv each).")
      .def(py::init<>())
      .def_property(
          "Kp", [](const mpc::PdGains& g) { return ToArray(g.Kp); },
          [](mpc::PdGains& g, py::handle x) { g.Kp = ToVector(x, "PdGains", "Kp"); })
      .def_property(
          "Kd", [](const mpc::PdGains& g) { return ToArray(g.Kd); },
          [](mpc::PdGains& g, py::handle x) { g.Kd = ToVector(x, "PdGains", "Kd"); });
  py::class_<MpcOptions::OrientationLead>(m, "OrientationLead")
      .def(py::init<>())
      .def_readwrite("position_start", &MpcOptions::OrientationLead::position_start)
      .def_readwrite("max_angle", &MpcOptions::OrientationLead::max_angle);
  py::class_<MpcOptions::RelativeGoal>(m, "RelativeGoal")
      .def(py::init<>())
      .def_readwrite("position", &MpcOptions::RelativeGoal::position)
      .def_readwrite("goal", &MpcOptions::RelativeGoal::goal);
  py::class_<MpcOptions::Estimator>(m, "Estimator",
                                    "The closed loop's estimate of q (0: the measurements).")
      .def(py::init<>())
      .def_readwrite("position_time_constant", &MpcOptions::Estimator::position_time_constant);
  py::class_<MpcOptions>(m, "MpcOptions", "Options of the real-time-iteration controller.")
      .def(py::init<>())
      .def_readwrite("control_rate", &MpcOptions::control_rate)
      .def_readwrite("iterations_per_step", &MpcOptions::iterations_per_step)
      .def_readwrite("relative_positions", &MpcOptions::relative_positions)
      .def_readwrite("relative_goals", &MpcOptions::relative_goals)
      .def_readwrite("orientation_leads", &MpcOptions::orientation_leads)
      .def_readwrite("estimator", &MpcOptions::estimator)
      .def_readwrite("gains", &MpcOptions::gains)
      .def_readwrite("actuated", &MpcOptions::actuated)
      .def("validate", &MpcOptions::Validate, py::arg("model"));
  py::class_<mpc::PdController>(m, "PdController", "PD+ tracking on the actuated DoFs.")
      .def(py::init<const Model&, const std::vector<int>&, const mpc::PdGains&>(), py::arg("model"),
           py::arg("actuated"), py::arg("gains"))
      .def(
          "compute",
          [](const mpc::PdController& pd, py::handle q, py::handle v, py::handle q_d,
             py::handle v_d, py::handle u_ff) {
            static constexpr const char* kWhere = "PdController.compute";
            Eigen::VectorXd u;
            pd.Compute(ToVector(q, kWhere, "q"), ToVector(v, kWhere, "v"),
                       ToVector(q_d, kWhere, "q_d"), ToVector(v_d, kWhere, "v_d"),
                       ToVector(u_ff, kWhere, "u_ff"), &u);
            return ToArray(u);
          },
          py::arg("q"), py::arg("v"), py::arg("q_d"), py::arg("v_d"), py::arg("u_ff"))
      .def("actuated", &mpc::PdController::actuated);
  py::class_<mpc::PositionFilter>(
      m, "PositionFilter",
      "Complementary filter on measured positions: predicted with the measured velocity, "
      "corrected towards the measured q at the rate 1 / time_constant.")
      .def(py::init<const Model&, double>(), py::arg("model"), py::arg("time_constant"),
           py::keep_alive<1, 2>())
      .def(
          "reset",
          [](mpc::PositionFilter& f, py::handle q) {
            f.Reset(ToVector(q, "PositionFilter.reset", "q"));
          },
          py::arg("q"))
      .def(
          "update",
          [](mpc::PositionFilter& f, double dt, py::handle q_hat, py::handle v_hat) {
            static constexpr const char* kWhere = "PositionFilter.update";
            Eigen::VectorXd q;
            f.Update(dt, ToVector(q_hat, kWhere, "q_hat"), ToVector(v_hat, kWhere, "v_hat"), &q);
            return ToArray(q);
          },
          py::arg("dt"), py::arg("q_hat"), py::arg("v_hat"), "The estimate after one measurement.")
      .def_property_readonly("estimate",
                             [](const mpc::PositionFilter& f) { return ToArray(f.estimate()); });
}

void BindPlan(py::module_& m) {
  py::class_<Plan>(m, "Plan", "Knots at start_time + k time_step and splines through them.")
      .def(py::init<>())
      .def_readonly("start_time", &Plan::start_time)
      .def_readonly("time_step", &Plan::time_step)
      .def_property_readonly("q", [](const Plan& p) { return ToArray(p.q); })
      .def_property_readonly("v", [](const Plan& p) { return ToArray(p.v); })
      .def_property_readonly("tau", [](const Plan& p) { return ToArray(p.tau); })
      .def(
          "sample",
          [](const Plan& p, const Model& model, double t) {
            if (p.q.empty()) throw InvalidArgument("Plan.sample: the plan is empty");
            if (static_cast<int>(p.q.front().size()) != model.nq()) {
              ThrowInvalidArgument("Plan.sample", "model",
                                   "a model with nq " + std::to_string(model.nq()),
                                   "the plan's model");
            }
            Eigen::VectorXd q_d, v_d, u_ff;
            p.Sample(model, t, &q_d, &v_d, &u_ff);
            return py::make_tuple(ToArray(q_d), ToArray(v_d), ToArray(u_ff));
          },
          py::arg("model"), py::arg("t"), "(q_d, v_d, u_ff) at time t.");
}

void BindController(py::module_& m) {
  py::class_<Controller>(m, "Controller", "Contact-implicit MPC by real-time iteration.")
      .def(py::init<const Model&, const ProblemDefinition&, const SolverOptions&,
                    const MpcOptions&>(),
           py::arg("model"), py::arg("problem"), py::arg("solver"), py::arg("options"))
      .def(
          "initialize",
          [](Controller& c, py::handle q_guess, int initial_iterations) {
            const auto guess = ToVectors(q_guess, "Controller.initialize", "q_guess",
                                         c.optimizer().problem().num_steps + 1,
                                         c.optimizer().model().nq(), "N + 1, nq");
            return RunWithoutGil([&] { return c.Initialize(guess, initial_iterations); });
          },
          py::arg("q_guess"), py::arg("initial_iterations"))
      .def(
          "replan",
          [](Controller& c, double t, py::handle q_hat, py::handle v_hat) {
            const Model& model = c.optimizer().model();
            Eigen::VectorXd q = ToVector(q_hat, "Controller.replan", "q_hat", model.nq(), "nq");
            Eigen::VectorXd v = ToVector(v_hat, "Controller.replan", "v_hat", model.nv(), "nv");
            return RunWithoutGil([&] { return c.Replan(t, q, v); });
          },
          py::arg("t"), py::arg("q_hat"), py::arg("v_hat"),
          "Re-plans at time t from the measured state (releases the GIL).")
      .def(
          "control",
          [](Controller& c, double t, py::handle q_hat, py::handle v_hat) {
            const Model& model = c.optimizer().model();
            Eigen::VectorXd u;
            c.Control(t, ToVector(q_hat, "Controller.control", "q_hat", model.nq(), "nq"),
                      ToVector(v_hat, "Controller.control", "v_hat", model.nv(), "nv"), &u);
            return ToArray(u);
          },
          py::arg("t"), py::arg("q_hat"), py::arg("v_hat"),
          "PD+ command u (nv) from the latest plan.")
      .def_property_readonly(
          "plan", [](const Controller& c) { return c.plan(); }, "(a copy)")
      .def_property_readonly("options", [](const Controller& c) { return c.options(); })
      .def_property_readonly("optimizer", &Controller::optimizer,
                             py::return_value_policy::reference_internal)
      .def("last_warm_start", [](const Controller& c) { return ToArray(c.last_warm_start()); })
      .def("num_rejected_plans", &Controller::num_rejected_plans);
}

void BindClosedLoop(py::module_& m) {
  py::enum_<mpc::LatencyModel>(m, "LatencyModel")
      .value("kSolveTime", mpc::LatencyModel::kSolveTime)
      .value("kControlPeriod", mpc::LatencyModel::kControlPeriod)
      .value("kFixed", mpc::LatencyModel::kFixed);
  py::enum_<mpc::LatePlanPolicy>(m, "LatePlanPolicy")
      .value("kDiscard", mpc::LatePlanPolicy::kDiscard)
      .value("kUseOnArrival", mpc::LatePlanPolicy::kUseOnArrival);
  py::class_<mpc::Disturbance>(m, "Disturbance", "A scripted push on a body (world frame, N).")
      .def(py::init<>())
      .def_readwrite("body", &mpc::Disturbance::body)
      .def_readwrite("start", &mpc::Disturbance::start)
      .def_readwrite("duration", &mpc::Disturbance::duration)
      .def_property(
          "force_W", [](const mpc::Disturbance& d) { return ToArray(Eigen::VectorXd(d.force_W)); },
          [](mpc::Disturbance& d, py::handle f) {
            d.force_W = ToVector(f, "Disturbance", "force_W", 3);
          });
  py::class_<ClosedLoopOptions>(m, "ClosedLoopOptions")
      .def(py::init<>())
      .def_readwrite("duration", &ClosedLoopOptions::duration)
      .def_readwrite("plant_time_step", &ClosedLoopOptions::plant_time_step)
      .def_readwrite("latency", &ClosedLoopOptions::latency)
      .def_readwrite("fixed_latency", &ClosedLoopOptions::fixed_latency)
      .def_readwrite("disturbances", &ClosedLoopOptions::disturbances)
      .def_readwrite("implicit_damping", &ClosedLoopOptions::implicit_damping)
      .def_readwrite("log_every", &ClosedLoopOptions::log_every)
      .def_readwrite("latency_jitter", &ClosedLoopOptions::latency_jitter)
      .def_readwrite("late_plans", &ClosedLoopOptions::late_plans)
      .def_readwrite("seed", &ClosedLoopOptions::seed)
      .def_readwrite("real_time", &ClosedLoopOptions::real_time)
      .def_readwrite("keep_workers_awake", &ClosedLoopOptions::keep_workers_awake)
      .def_readwrite("realtime_priority", &ClosedLoopOptions::realtime_priority);
  py::class_<ClosedLoopLog>(m, "ClosedLoopLog", "What a closed-loop run recorded.")
      .def_property_readonly("t", [](const ClosedLoopLog& l) { return ToArray(l.t); })
      .def_property_readonly("q", [](const ClosedLoopLog& l) { return ToArray(l.q); })
      .def_property_readonly("v", [](const ClosedLoopLog& l) { return ToArray(l.v); })
      .def_property_readonly("u", [](const ClosedLoopLog& l) { return ToArray(l.u); })
      .def_property_readonly("contact", [](const ClosedLoopLog& l) { return ToArray(l.contact); })
      .def_property_readonly("replan_time",
                             [](const ClosedLoopLog& l) { return ToArray(l.replan_time); })
      .def_property_readonly("solve_time",
                             [](const ClosedLoopLog& l) { return ToArray(l.solve_time); })
      .def_readonly("solve_status", &ClosedLoopLog::solve_status)
      .def_readonly("num_rejected_plans", &ClosedLoopLog::num_rejected_plans)
      .def_readonly("num_late_plans", &ClosedLoopLog::num_late_plans)
      .def_readonly("num_skipped_replans", &ClosedLoopLog::num_skipped_replans)
      .def_readonly("num_nonfinite_commands", &ClosedLoopLog::num_nonfinite_commands)
      .def_readonly("control_period", &ClosedLoopLog::control_period)
      .def_readonly("failure", &ClosedLoopLog::failure)
      .def_readonly("failure_time", &ClosedLoopLog::failure_time)
      .def_readonly("realtime_error", &ClosedLoopLog::realtime_error)
      .def("mean_solve_time", &ClosedLoopLog::mean_solve_time)
      .def("max_solve_time", &ClosedLoopLog::max_solve_time)
      .def("percentile_solve_time", &ClosedLoopLog::percentile_solve_time, py::arg("p"))
      .def("fraction_on_time", &ClosedLoopLog::fraction_on_time)
      .def("to_csv", &ClosedLoopLog::ToCsv, py::arg("model"));
  m.def(
      "run_closed_loop",
      [](const Model& model, const ClosedLoopOptions& options, Controller& controller,
         sim::Plant& plant) {
        return RunWithoutGil(
            [&] { return mpc::RunClosedLoop(model, options, &controller, &plant); });
      },
      py::arg("model"), py::arg("options"), py::arg("controller"), py::arg("plant"),
      "Runs the controller against the plant from its current state (releases the GIL).");
}

}  // namespace

void BindMpc(py::module_& m) {
  BindOptions(m);
  BindPlan(m);
  BindController(m);
  BindClosedLoop(m);
}

}  // namespace idto::python
