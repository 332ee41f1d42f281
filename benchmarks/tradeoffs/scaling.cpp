// Threads and horizon: time per iteration.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "studies.hpp"

namespace idto::tradeoffs {
namespace {

/// Seconds per iteration that computed derivatives (median) and of its derivative and
/// multiplier phases, the smallest over `repeats` solves (the least disturbed by other work on
/// the machine), and the last solve.
struct Timing {
  double iteration{0.0}, derivatives{0.0}, multipliers{0.0};
  SolveResult last;
};

Timing TimeIterations(const ExampleConfig& config, const ProblemDefinition& problem,
                      const SolverOptions& options, int repeats) {
  Timing t;
  t.iteration = t.derivatives = t.multipliers = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeats; ++r) {
    t.last = Solve(config, problem, options);
    const double iteration = MedianFullIterationSeconds(t.last.summary);
    if (iteration < t.iteration) {
      t.iteration = iteration;
      t.derivatives = MedianDerivativeSeconds(t.last.summary);
      std::vector<double> multipliers;
      for (const IterationSummary& it : t.last.summary.log) {
        if (it.time_hessian > 0.0) multipliers.push_back(it.time_multipliers);
      }
      std::sort(multipliers.begin(), multipliers.end());
      t.multipliers = multipliers.empty() ? 0.0 : multipliers[multipliers.size() / 2];
    }
  }
  return t;
}

bool Identical(const Trajectory& a, const Trajectory& b) {
  if (a.q.size() != b.q.size()) return false;
  for (size_t k = 0; k < a.q.size(); ++k) {
    if (a.q[k] != b.q[k]) return false;
  }
  return true;
}

/// Least-squares slope of log(time) against log(N) over the points with N >= n_min.
double Exponent(const std::vector<int>& n, const std::vector<double>& t, int n_min) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int m = 0;
  for (size_t i = 0; i < n.size(); ++i) {
    if (n[i] < n_min || !std::isfinite(t[i])) continue;
    const double x = std::log(n[i]), y = std::log(t[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++m;
  }
  if (m < 2) return std::nan("");
  return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

/// The thread study: 1 vs 2 threads per example, a table, a reading and one finding each.
std::string ThreadsSection(const Context& context, StudyResult* result) {
  const int iterations = context.quick ? 4 : 20;
  const int repeats = context.quick ? 1 : 5;
  std::ostringstream md;
  const std::string load_at_start = ReadLoadAverage();
  const std::vector<std::string> examples =
      context.quick
          ? std::vector<std::string>{"spinner", "quadruped"}
          : std::vector<std::string>{"spinner", "hopper", "quadruped", "allegro", "bimanual"};
  md << "**Threads.** `SolverOptions::num_threads` parallelizes the per-step work (derivatives, "
        "cost, Hessian rows) over time steps; the penalty method's Cholesky is serial, the "
        "multipliers' KKT factorization and solve run in two halves on two threads (blocks of "
        "nq + n_u >= 8, N >= 8). Each example with its YAML settings, "
     << iterations << " iterations (`fixed_iterations`) from its initial guess, 1 and 2 "
     << "threads, trial derivatives off (`solver.trial_derivatives: false`: the derivative phase "
        "timed on its own); median time of the iterations that computed derivatives, the "
        "smallest of "
     << repeats << " solve" << (repeats > 1 ? "s" : "") << " (derivative phase in parentheses). "
     << "\"Identical\" compares the trajectories of the two runs bit for bit.\n\n";
  Table threads({"example (nq, N, method)", "1 thread: ms / iteration", "2 threads: ms / iteration",
                 "speedup", "derivative share (1 thread)", "identical results"});
  for (const std::string& name : examples) {
    const ExampleConfig config = LoadExample(context, name);
    SolverOptions options = config.solver;
    options.max_iterations = iterations;
    options.fixed_iterations = true;
    options.trial_derivatives = false;  // the derivative phase timed on its own
    options.num_threads = 1;
    const Timing one = TimeIterations(config, config.problem, options, repeats);
    options.num_threads = 2;
    const Timing two = TimeIterations(config, config.problem, options, repeats);
    const bool identical = Identical(one.last.solution, two.last.solution) &&
                           one.last.summary.final_cost == two.last.summary.final_cost;
    threads.Row(
        {name + " (" + std::to_string(config.model.nq()) + ", " +
             std::to_string(config.problem.num_steps) + ", " +
             ConstraintMethodName(config.solver.constraint_method) + ")",
         Ms(one.iteration) + " (" + Ms(one.derivatives) + ")",
         Ms(two.iteration) + " (" + Ms(two.derivatives) + ")", Times(one.iteration / two.iteration),
         Num(100.0 * one.derivatives / one.iteration, 2) + "%", identical ? "yes" : "**no**"});
    Finding f;
    f.knob = "2 threads instead of 1";
    f.example = name;
    f.speedup = one.iteration / two.iteration;
    f.speed = Ms(one.iteration) + " → " + Ms(two.iteration) + " ms per iteration";
    f.free = identical;
    f.accuracy = identical ? "none: bitwise-identical trajectory and cost"
                           : "the trajectory differs from the 1-thread run";
    result->findings.push_back(f);
  }
  md << threads.Markdown() << "\n";
  {
    double best = 0.0, worst = 1e300;
    std::string best_name, worst_name;
    bool all_identical = true;
    for (const Finding& f : result->findings) {
      if (f.speedup > best) best = f.speedup, best_name = f.example;
      if (f.speedup < worst) worst = f.speedup, worst_name = f.example;
      all_identical = all_identical && f.free;
    }
    const MachineInfo machine = ReadMachineInfo();
    const double load = std::atof(load_at_start.c_str());
    md << "Reading: 2 threads gave " << Times(worst) << " (" << worst_name << ") to " << Times(best)
       << " (" << best_name << ") per iteration on this " << machine.cores
       << "-core machine; the results were "
       << (all_identical ? "bit-for-bit identical in every case"
                         : "**not** identical in every case (see the table)")
       << ". The derivative share is the part of a 1-thread iteration spent computing the "
          "derivatives (analytic, the default), the bulk of the parallel work (the cost and the "
          "Hessian rows are parallel too, and the KKT system in two halves; the penalty method's "
          "Cholesky is not).";
    if (best < 1.2 && load >= machine.cores - 0.5) {
      md << " The 1-minute load average was " << load_at_start << " when this study started, "
         << "on " << machine.cores
         << " cores: other work kept the cores busy, so a second "
            "thread had little idle time to use (compare docs/benchmarks.md, measured on a "
            "quiet machine).";
    }
    md << "\n\n";
  }
  return md.str();
}

/// Time per iteration against N on one example (one column per method and thread count).
struct Series {
  std::string label;
  int example{0};
  std::vector<int> n;
  std::vector<double> ms;
};

/// One example of the horizon study: its table, fitted exponents, note and series.
std::string HorizonExample(const Context& context, const std::string& name,
                           const std::string& horizon_text, int example,
                           const std::vector<int>& horizons, int horizon_iterations,
                           int horizon_repeats, std::vector<Series>* series, StudyResult* result) {
  std::ostringstream md;
  Table table({"N", "penalty, 1 thread", "penalty, 2 threads", "Lagrange, 2 threads"});
  Series p1{name + ", penalty, 1 thread", example, {}, {}};
  Series p2{name + ", penalty, 2 threads", example, {}, {}};
  Series lm{name + ", Lagrange, 2 threads", example, {}, {}};
  int nu = 0;
  for (int n : horizons) {
    std::vector<std::pair<std::string, std::string>> edits{
        {horizon_text, "num_steps: " + std::to_string(n)}};
    const ExampleConfig config = LoadEditedExample(context, name, edits);
    nu = static_cast<int>(config.problem.UnactuatedDofs(config.model).size());
    SolverOptions options = config.solver;
    options.max_iterations = horizon_iterations;
    options.fixed_iterations = true;
    options.constraint_method = ConstraintMethod::kPenalty;
    options.num_threads = 1;
    const Timing a = TimeIterations(config, config.problem, options, horizon_repeats);
    options.num_threads = 2;
    const Timing b = TimeIterations(config, config.problem, options, horizon_repeats);
    options.constraint_method = ConstraintMethod::kLagrangeMultipliers;
    const Timing c = TimeIterations(config, config.problem, options, horizon_repeats);
    const std::string lm_cell = Ms(c.iteration) + " (" + Ms(c.multipliers) + ")";
    lm.n.push_back(n);
    lm.ms.push_back(1e3 * c.iteration);
    p1.n.push_back(n);
    p1.ms.push_back(1e3 * a.iteration);
    p2.n.push_back(n);
    p2.ms.push_back(1e3 * b.iteration);
    table.Row({std::to_string(n), Ms(a.iteration), Ms(b.iteration), lm_cell});
  }
  md << "*" << name << "* (n_u = " << nu << "), ms per iteration:\n\n" << table.Markdown();
  const int n_min = horizons.size() > 3 ? 40 : horizons.front();
  md << "\nFitted time ∝ N^p over N ≥ " << n_min
     << ": penalty p = " << Num(Exponent(p1.n, p1.ms, n_min), 2) << " (1 thread), "
     << Num(Exponent(p2.n, p2.ms, n_min), 2) << " (2 threads)";
  if (lm.n.size() >= 2) {
    md << "; Lagrange p = " << Num(Exponent(lm.n, lm.ms, n_min), 2) << " (N ≤ " << lm.n.back()
       << ")";
  }
  md << ".\n\n";
  {
    std::ostringstream note;
    note << "Horizon (" << name << "): time per iteration grows as N^"
         << Num(Exponent(p1.n, p1.ms, n_min), 2) << " with the penalty (1 thread)";
    if (lm.n.size() >= 2) {
      note << " and N^" << Num(Exponent(lm.n, lm.ms, n_min), 2)
           << " with Lagrange multipliers (2 threads; at N = " << lm.n.back() << ": "
           << Num(lm.ms.back(), 3) << " ms against " << Num(p2.ms[lm.n.size() - 1], 3)
           << " ms with the penalty on 2 threads)";
    }
    note << ".";
    result->notes.push_back(note.str());
  }
  series->push_back(p1);
  series->push_back(p2);
  if (!lm.n.empty()) series->push_back(lm);
  return md.str();
}

/// Time per iteration vs horizon, every series in one log-log plot.
std::string HorizonFigure(const Context& context, const std::vector<Series>& series,
                          const std::vector<int>& horizons, int horizon_iterations) {
  const std::string png = context.figure_dir + "/tradeoffs_scaling.png";
  std::ostringstream gp;
  gp << GnuplotHeader(png, 1000, 600) << "set title \"time per iteration vs horizon ("
     << horizon_iterations << " iterations, median)\"\n"
     << "set logscale xy\nset format y \"10^{%T}\"\nset xlabel \"N (time steps)\"\n"
     << "set xrange [" << horizons.front() * 0.8 << ":" << horizons.back() * 1.25 << "]\n"
     << "set ylabel \"ms per iteration\"\nset key outside right font \",9\"\nplot ";
  for (size_t i = 0; i < series.size(); ++i) {
    const std::string file = context.data_dir + "/scaling_" + std::to_string(i) + ".csv";
    std::ofstream out(file);
    for (size_t j = 0; j < series[i].n.size(); ++j) {
      out << series[i].n[j] << ',' << series[i].ms[j] << '\n';
    }
    const bool lagrange = series[i].label.find("Lagrange") != std::string::npos;
    const bool one = series[i].label.find("1 thread") != std::string::npos;
    gp << (i ? ", " : "") << GnuplotQuote(file) << " using 1:2 with linespoints lw 2 pt "
       << (lagrange ? 5 : 7) << " dt " << (one ? 2 : 1) << " lc " << 1 + series[i].example
       << " title " << GnuplotQuote(series[i].label) << " noenhanced";
  }
  gp << "\n";
  if (!RunGnuplot(context.data_dir, "scaling", gp.str())) return "";
  return "![Time per iteration vs horizon](" + context.figure_link_prefix +
         "tradeoffs_scaling.png)\n\n";
}

/// The horizon study: time per iteration against N, penalty and Lagrange multipliers.
std::string HorizonSection(const Context& context, StudyResult* result) {
  std::ostringstream md;
  const std::vector<int> horizons =
      context.quick ? std::vector<int>{10, 40, 160} : std::vector<int>{10, 20, 40, 80, 160, 320};
  const std::vector<std::pair<std::string, std::string>> horizon_examples =
      context.quick
          ? std::vector<std::pair<std::string, std::string>>{{"spinner", "horizon: 2.0"}}
          : std::vector<std::pair<std::string, std::string>>{{"spinner", "horizon: 2.0"},
                                                             {"hopper", "horizon: 2.0"},
                                                             {"quadruped", "horizon: 1.0"}};
  const int horizon_iterations = context.quick ? 3 : 10;
  const int horizon_repeats = context.quick ? 1 : 2;
  md << "**Horizon.** The same examples with `num_steps` = N instead of their horizon (δt "
        "unchanged, so the plan covers N δt; the nominal is stretched over it), "
     << horizon_iterations << " iterations, median per iteration as above, smallest of "
     << horizon_repeats
     << ". The Lagrange iteration's multiplier phase (the KKT factorization and solve, which "
        "include the Hessian's) is in parentheses.\n\n";
  std::vector<Series> series;
  for (size_t e = 0; e < horizon_examples.size(); ++e) {
    md << HorizonExample(context, horizon_examples[e].first, horizon_examples[e].second,
                         static_cast<int>(e), horizons, horizon_iterations, horizon_repeats,
                         &series, result);
  }
  md << "Both methods are linear in N in theory: the penalty method factors a block-pentadiagonal "
        "Hessian (O(N nq³)), the multipliers a block-banded KKT system with the unknowns of each "
        "step interleaved (O(N (nq + n_u)³), docs/solver.md). The paper's Fig. 6 shows the "
        "multipliers cubic in N: that is the dense A H⁻¹ Aᵀ route, N·n_u square, which idto keeps "
        "only as a test oracle. The fitted exponents above are what this machine measured.\n\n";

  if (context.gnuplot) md << HorizonFigure(context, series, horizons, horizon_iterations);
  return md.str();
}

}  // namespace

StudyResult RunScalingStudy(const Context& context) {
  StudyResult result;
  result.id = "scaling";
  result.title = "Threads and horizon";
  result.markdown = ThreadsSection(context, &result);
  result.markdown += HorizonSection(context, &result);
  return result;
}

}  // namespace idto::tradeoffs
