#pragma once

// Running solver calls without the GIL, with Python callbacks and Ctrl-C (used by the solver
// and MPC bindings).

#include "convert.hpp"

namespace idto::python {

/// Installed first on every TrajectoryOptimizer made from Python: on the main thread, takes the
/// GIL after each iteration and runs Python's signal handlers (PyErr_CheckSignals); a raised
/// exception (KeyboardInterrupt from Ctrl-C) aborts the solve and is raised after it.
CallbackReturn CheckSignalsCallback(const IterationSummary& summary);

/// A C++ callback that calls the Python callable `fn` (with the GIL) with the iteration's
/// summary. `fn` returns None or True (continue), False (terminate) or a CallbackReturn; an
/// exception aborts the solve and is raised after it.
IterationCallback MakePythonCallback(py::object fn);

/// Runs f() without the GIL, then raises any error a callback stored. f returns a value.
template <typename F>
auto RunWithoutGil(F&& f) -> decltype(f()) {
  ClearPendingError();
  decltype(f()) result;
  {
    py::gil_scoped_release release;
    result = f();
  }
  RaisePendingError();
  return result;
}

/// The (summary, trajectory) tuple solve() returns.
py::tuple SummaryAndTrajectory(SolverSummary summary, Trajectory trajectory);

}  // namespace idto::python
