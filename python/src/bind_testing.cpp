// idto._idto._testing: C++ helpers for the tests and the overhead benchmark.

#include <chrono>
#include <ctime>
#include <utility>

#include "solver_glue.hpp"

namespace idto::python {
namespace {

double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

void BindTesting(py::module_& m) {
  m.def(
      "time_warm_start",
      [](TrajectoryOptimizer& o, int repeats) {
        // The C++ side of the overhead benchmark: `repeats` calls of SolveWarmStart, each timed
        // alone (wall-clock and this thread's CPU time), without the GIL as the Python path.
        std::vector<std::pair<double, double>> seconds;
        Trajectory traj;
        py::gil_scoped_release release;
        for (int i = 0; i < repeats; ++i) {
          const auto t0 = std::chrono::steady_clock::now();
          const double c0 = ThreadCpuSeconds();
          const SolverSummary s = o.SolveWarmStart(&traj);
          const double c1 = ThreadCpuSeconds();
          const auto t1 = std::chrono::steady_clock::now();
          seconds.emplace_back(std::chrono::duration<double>(t1 - t0).count(), c1 - c0);
          (void)s;
        }
        return seconds;
      },
      py::arg("optimizer"), py::arg("repeats"),
      "(wall, thread CPU) seconds of each of `repeats` SolveWarmStart calls made from C++.");
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
