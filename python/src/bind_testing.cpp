// idto._idto._testing: C++ helpers for the tests and the overhead benchmark.

#include <chrono>

#include "solver_glue.hpp"

namespace idto::python {

void BindTesting(py::module_& m) {
  m.def(
      "time_warm_start",
      [](TrajectoryOptimizer& o, int repeats) {
        // The C++ side of the overhead benchmark: `repeats` calls of SolveWarmStart, each timed
        // alone, without the GIL (as the Python path runs it).
        std::vector<double> seconds;
        Trajectory traj;
        py::gil_scoped_release release;
        for (int i = 0; i < repeats; ++i) {
          const auto t0 = std::chrono::steady_clock::now();
          const SolverSummary s = o.SolveWarmStart(&traj);
          const auto t1 = std::chrono::steady_clock::now();
          seconds.push_back(std::chrono::duration<double>(t1 - t0).count());
          (void)s;
        }
        return seconds;
      },
      py::arg("optimizer"), py::arg("repeats"),
      "Seconds of each of `repeats` SolveWarmStart calls made from C++.");
  m.def(
      "solve_in_cpp",
      [](const Model& model, const ProblemDefinition& problem, const SolverOptions& options,
         py::handle q_guess) {
        // A solve with no Python in the loop (no signal callback), for bitwise comparisons.
        const auto guess = ToVectors(q_guess, "solve_in_cpp", "q_guess", problem.num_steps + 1,
                                     model.nq(), "N + 1, nq");
        Trajectory traj;
        SolverSummary s;
        {
          py::gil_scoped_release release;
          TrajectoryOptimizer o(model, problem, options);
          s = o.Solve(guess, &traj);
        }
        return SummaryAndTrajectory(std::move(s), std::move(traj));
      },
      py::arg("model"), py::arg("problem"), py::arg("options"), py::arg("q_guess"));
}

}  // namespace idto::python
