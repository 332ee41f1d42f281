// Contact pruning tolerance (ContactOptions::force_tolerance): time per contact evaluation and
// per solver iteration against the force error and the change of the solver's answer.

#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "idto/contact/contact_engine.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/multibody/data.hpp"
#include "studies.hpp"

namespace idto::tradeoffs {
namespace {

using Clock = std::chrono::steady_clock;

struct Row {
  double tolerance{0.0};
  double cutoff{0.0};        // the law's cut-off distance at this tolerance (m)
  double pairs{0.0};         // pairs evaluated per evaluation (mean)
  double eval_seconds{0.0};  // per contact evaluation
  double force_error{0.0};   // max |F_ext - F_ext(no pruning)| entry (N or N m)
  double iteration_seconds{0.0};
  double q_change{0.0};     // max |q - q(no pruning)| after the solve
  double cost_change{0.0};  // relative change of the final cost
};

/// Evaluates `engine` at every state and returns seconds per evaluation (repeated until at
/// least `min_seconds` have passed), the mean number of evaluated pairs and the body forces.
double TimeEvaluations(const Model& model, const ContactEngine& engine,
                       const std::vector<Eigen::VectorXd>& q, const std::vector<Eigen::VectorXd>& v,
                       double min_seconds, double* pairs, std::vector<BodyForces>* forces) {
  std::vector<Data> data;
  for (size_t k = 0; k < q.size(); ++k) {
    data.emplace_back(model);
    ForwardKinematics(model, q[k], v[k], &data.back());
  }
  ContactData contact = engine.MakeData(model);
  forces->clear();
  double active = 0.0;
  for (const Data& d : data) {
    engine.Evaluate(model, d, &contact);
    forces->push_back(contact.F_ext);
    active += contact.num_active;
  }
  *pairs = active / static_cast<double>(data.size());
  long evaluations = 0;
  const Clock::time_point start = Clock::now();
  double elapsed = 0.0;
  do {
    for (const Data& d : data) engine.Evaluate(model, d, &contact);
    evaluations += static_cast<long>(data.size());
    elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  } while (elapsed < min_seconds);
  return elapsed / static_cast<double>(evaluations);
}

/// The sweep's settings: full or quick.
struct Sweep {
  std::vector<double> tolerances;
  int iterations{0};        // solver iterations (fixed) per solve
  double min_seconds{0.0};  // least time spent timing the contact evaluations
};

/// A scene's no-pruning levels, drawn dashed in the figure.
struct Plotted {
  std::string name;
  double eval_us_off{0.0}, iteration_ms_off{0.0};
};

/// The section's opening: what is measured per scene and tolerance.
std::string Introduction(const Context& context, int iterations) {
  std::ostringstream md;
  md << "`ContactOptions::force_tolerance` (YAML `scene.contact.force_tolerance`, default 1e-8 N; "
        "0 disables pruning) skips a pair when a bounding-sphere bound on its distance puts it "
        "beyond `ContactCutoffDistance`, where the compliance force is below the tolerance "
        "(docs/contact.md, \"Pruning\"). Per scene: the states (q_k, v_k) of the example's "
        "trajectory after "
     << iterations
     << " solver iterations (no pruning) are evaluated with each tolerance: time per contact "
        "evaluation (`ContactEngine::Evaluate`, one thread, forward kinematics excluded), "
        "pairs evaluated, and the force error = the largest entry of |F_ext − F_ext(no "
        "pruning)| over all states (N or N m). Then the solver runs "
     << iterations << " iterations (`fixed_iterations`, the YAML method, " << context.threads
     << " threads) from the initial guess with that tolerance: median time per iteration "
        "(over iterations that computed derivatives; the smallest of "
     << context.repeats
     << " solves), and how far its answer moved against "
        "no pruning: max |q − q(no pruning)| over the trajectory and the relative change of "
        "the final cost. The cut-off is the example's (largest) contact law's distance for "
        "that tolerance.\n\n";
  return md.str();
}

/// A row per tolerance of `sweep` (the first is 0, no pruning: the states, forces and answer
/// the others are compared with). `num_pairs` is set to the scene's admitted pairs.
std::vector<Row> MeasureScene(const Context& context, const ExampleConfig& config,
                              const Sweep& sweep, int* num_pairs) {
  SolverOptions options = config.solver;
  options.max_iterations = sweep.iterations;
  options.fixed_iterations = true;
  options.num_threads = context.threads;

  std::vector<Row> rows;
  SolveResult off;
  std::vector<BodyForces> forces_off;
  std::vector<Eigen::VectorXd> states_q, states_v;
  for (double tolerance : sweep.tolerances) {
    ProblemDefinition problem = config.problem;
    problem.contact.force_tolerance = tolerance;
    const ContactEngine engine(config.model, problem.contact);
    *num_pairs = engine.num_pairs();
    Row row;
    row.tolerance = tolerance;
    row.cutoff = tolerance > 0.0 ? ContactCutoffDistance(problem.contact.parameters, tolerance)
                                 : std::numeric_limits<double>::infinity();
    // Timing: the smallest median over `repeats` solves (the least disturbed by other work).
    SolveResult solve = Solve(config, problem, options);
    row.iteration_seconds = MedianFullIterationSeconds(solve.summary);
    for (int r = 1; r < context.repeats; ++r) {
      row.iteration_seconds =
          std::min(row.iteration_seconds,
                   MedianFullIterationSeconds(Solve(config, problem, options).summary));
    }
    if (tolerance == 0.0) {
      off = solve;
      // The states the contact evaluations are timed on: k = 1..N of the unpruned solve.
      states_q.assign(solve.solution.q.begin() + 1, solve.solution.q.end());
      states_v.assign(solve.solution.v.begin() + 1, solve.solution.v.end());
    }
    std::vector<BodyForces> forces;
    row.eval_seconds = TimeEvaluations(config.model, engine, states_q, states_v, sweep.min_seconds,
                                       &row.pairs, &forces);
    if (tolerance == 0.0) forces_off = forces;
    for (size_t k = 0; k < forces.size(); ++k) {
      row.force_error =
          std::max(row.force_error, (forces[k] - forces_off[k]).cwiseAbs().maxCoeff());
    }
    for (size_t k = 0; k < solve.solution.q.size(); ++k) {
      row.q_change =
          std::max(row.q_change, (solve.solution.q[k] - off.solution.q[k]).cwiseAbs().maxCoeff());
    }
    row.cost_change = std::abs(solve.summary.final_cost - off.summary.final_cost) /
                      std::abs(off.summary.final_cost);
    rows.push_back(row);
  }
  return rows;
}

/// A scene's heading and its table, a row per tolerance.
std::string SceneTable(const std::string& name, const ExampleConfig& config, int num_pairs,
                       int iterations, const std::vector<Row>& rows) {
  std::ostringstream md;
  md << "**" << name << "** (" << num_pairs << " admitted pairs, nq = " << config.model.nq()
     << ", N = " << config.problem.num_steps << ", "
     << ConstraintMethodName(config.solver.constraint_method) << "):\n\n";
  Table table({"force_tolerance (N)", "cut-off (m)", "pairs evaluated", "µs / evaluation",
               "force error", "ms / solver iteration",
               "max \\|Δq\\| after " + std::to_string(iterations) + " iterations",
               "final cost change"});
  for (const Row& r : rows) {
    table.Row({r.tolerance == 0.0 ? "0 (off)" : G(r.tolerance),
               r.tolerance == 0.0 ? "∞" : Num(r.cutoff, 3), Num(r.pairs, 3),
               Num(1e6 * r.eval_seconds, 3), Sci(r.force_error), Ms(r.iteration_seconds),
               Sci(r.q_change), Sci(r.cost_change)});
  }
  md << table.Markdown() << "\n";
  return md.str();
}

/// The computed reading of a scene's rows: the default against no pruning, and the largest
/// tolerance whose answer still did not move by more than kSameAnswer. Adds their findings.
std::string Reading(const std::string& name, int iterations, const std::vector<Row>& rows,
                    std::vector<Finding>* findings) {
  constexpr double kSameAnswer = 1e-6;
  std::ostringstream md;
  const Row& none = rows[0];
  const Row* deflt = nullptr;
  const Row* largest_same = nullptr;
  for (const Row& r : rows) {
    if (r.tolerance == 1e-8) deflt = &r;
    if (r.tolerance > 0.0 && r.q_change <= kSameAnswer) largest_same = &r;
  }
  if (deflt != nullptr) {
    md << "Reading: the default 1e-8 N evaluates " << Num(deflt->pairs, 3) << " of "
       << Num(none.pairs, 3) << " pairs, " << Times(none.eval_seconds / deflt->eval_seconds)
       << " faster per contact evaluation and "
       << Times(none.iteration_seconds / deflt->iteration_seconds)
       << " per solver iteration, with a force error of " << Sci(deflt->force_error)
       << " and the trajectory moved by " << Sci(deflt->q_change) << ". ";
    Finding f;
    f.knob = "pruning at 1e-8 N (default) instead of none";
    f.example = name;
    f.speedup = none.iteration_seconds / deflt->iteration_seconds;
    f.speed = Ms(none.iteration_seconds) + " → " + Ms(deflt->iteration_seconds) +
              " ms per iteration (contact evaluation " + Num(1e6 * none.eval_seconds, 3) + " → " +
              Num(1e6 * deflt->eval_seconds, 3) + " µs)";
    f.free = deflt->q_change <= kSameAnswer;
    f.accuracy = "force error " + Sci(deflt->force_error) + ", max |Δq| " + Sci(deflt->q_change) +
                 " after " + std::to_string(iterations) + " iterations" +
                 (f.free ? " (≤ 1e-6: same answer)" : "");
    findings->push_back(f);
  }
  if (largest_same != nullptr && deflt != nullptr && largest_same->tolerance > 1e-8) {
    const double gain = deflt->iteration_seconds / largest_same->iteration_seconds;
    md << "The largest tolerance of this sweep that moved the trajectory by at most "
       << G(kSameAnswer) << " is " << G(largest_same->tolerance) << " N ("
       << Times(deflt->eval_seconds / largest_same->eval_seconds) << " per contact evaluation and "
       << Times(gain) << " per iteration against the default).";
  }
  if (largest_same != nullptr && deflt != nullptr && largest_same->tolerance > 1e-8 &&
      deflt->iteration_seconds / largest_same->iteration_seconds > 1.1) {
    Finding f;
    f.knob = "pruning at " + G(largest_same->tolerance) + " N instead of 1e-8 N";
    f.example = name;
    f.speedup = deflt->iteration_seconds / largest_same->iteration_seconds;
    f.speed = Ms(deflt->iteration_seconds) + " → " + Ms(largest_same->iteration_seconds) +
              " ms per iteration";
    f.free = true;
    f.accuracy = "force error " + Sci(largest_same->force_error) + ", max |Δq| " +
                 Sci(largest_same->q_change) + " (≤ 1e-6: same answer)";
    findings->push_back(f);
  }
  if ((largest_same == nullptr || largest_same->tolerance <= 1e-8) && deflt != nullptr) {
    md << "Every tolerance above the default moved the trajectory by more than " << G(kSameAnswer)
       << ".";
  }
  md << "\n\n";
  return md.str();
}

/// Writes a scene's pruned rows for the figure and returns its no-pruning levels.
Plotted WriteSceneData(const Context& context, const std::string& name,
                       const std::vector<Row>& rows) {
  std::ofstream data(context.data_dir + "/pruning_" + name + ".csv");
  for (const Row& r : rows) {
    if (r.tolerance > 0.0) {
      data << r.tolerance << ',' << 1e6 * r.eval_seconds << ',' << r.force_error << ','
           << 1e3 * r.iteration_seconds << ',' << r.q_change << '\n';
    }
  }
  return {name, 1e6 * rows[0].eval_seconds, 1e3 * rows[0].iteration_seconds};
}

/// The figure (evaluation time, force error and iteration time against the tolerance, a curve
/// per scene) and its Markdown link ("" when gnuplot fails).
std::string Figure(const Context& context, const std::vector<Plotted>& plotted) {
  const char* colors[] = {"#1b9e77", "#d95f02", "#7570b3", "#e7298a"};
  const std::string png = context.figure_dir + "/tradeoffs_pruning.png";
  std::ostringstream gp;
  gp << GnuplotHeader(png, 1500, 470) << "set multiplot layout 1,3\n"
     << "set logscale x\nset format x \"10^{%T}\"\nset xlabel \"force\\\\_tolerance (N)\"\n"
     << "set key top right font \",9\"\n";
  // off: 0 none, 1 evaluation time, 2 iteration time (the no-pruning level, dashed).
  const auto panel = [&](const std::string& title, const std::string& ylabel, int column, int off,
                         bool log_y) {
    gp << "set title \"" << title << "\"\nset ylabel \"" << ylabel << "\"\n"
       << (log_y ? "set logscale y\nset format y \"10^{%T}\"\n"
                 : "unset logscale y\nset format y \"%g\"\n")
       << "plot ";
    for (size_t i = 0; i < plotted.size(); ++i) {
      const Plotted& p = plotted[i];
      const std::string file = context.data_dir + "/pruning_" + p.name + ".csv";
      gp << (i ? ", " : "") << GnuplotQuote(file) << " using 1:" << column
         << " with linespoints lw 2 pt 7 lc rgb \"" << colors[i % 4] << "\" title \"" << p.name
         << "\" noenhanced";
      if (off != 0) {
        gp << ", " << (off == 1 ? p.eval_us_off : p.iteration_ms_off)
           << " with lines dt 2 lc rgb \"" << colors[i % 4] << "\" notitle";
      }
    }
    gp << "\n";
  };
  panel("time per contact evaluation (dashed: no pruning)", "µs", 2, 1, true);
  panel("force error against no pruning", "N or N m", 3, 0, true);
  panel("time per solver iteration (dashed: no pruning)", "ms", 4, 2, false);
  gp << "unset multiplot\n";
  if (!RunGnuplot(context.data_dir, "pruning", gp.str())) return "";
  return "![Contact evaluation time, force error and solver iteration time vs pruning "
         "tolerance](" +
         context.figure_link_prefix + "tradeoffs_pruning.png)\n\n";
}

}  // namespace

StudyResult RunPruningStudy(const Context& context) {
  StudyResult result;
  result.id = "pruning";
  result.title = "Contact pruning tolerance";
  const std::vector<std::string> scenes =
      context.quick
          ? std::vector<std::string>{"quadruped"}
          : std::vector<std::string>{"quadruped", "quadruped_hills", "allegro", "bimanual"};
  Sweep sweep;
  sweep.tolerances = context.quick ? std::vector<double>{0.0, 1e-8, 1e-2}
                                   : std::vector<double>{0.0, 1e-8, 1e-6, 1e-4, 1e-2, 1.0};
  sweep.iterations = context.quick ? 5 : 20;
  sweep.min_seconds = context.quick ? 0.005 : 0.05;
  std::vector<Plotted> plotted;
  std::ostringstream md;
  md << Introduction(context, sweep.iterations);

  for (const std::string& name : scenes) {
    const ExampleConfig config = LoadExample(context, name);
    int num_pairs = 0;
    const std::vector<Row> rows = MeasureScene(context, config, sweep, &num_pairs);
    md << SceneTable(name, config, num_pairs, sweep.iterations, rows)
       << Reading(name, sweep.iterations, rows, &result.findings);
    if (context.gnuplot) plotted.push_back(WriteSceneData(context, name, rows));
  }
  if (context.gnuplot) md << Figure(context, plotted);
  result.markdown = md.str();
  return result;
}

}  // namespace idto::tradeoffs
