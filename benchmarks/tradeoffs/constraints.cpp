// Penalty weights vs Lagrange multipliers for the unactuated-DoF constraint h(q) = 0.

#include <cmath>
#include <fstream>
#include <sstream>

#include "studies.hpp"

namespace idto::tradeoffs {
namespace {

struct Run {
  std::string label;  // "Lagrange", "penalty w = 1e4", ...
  bool lagrange{false};
  double weight{0.0};  // penalty weight in effect (0 for Lagrange)
  SolveResult solve;
  double cost{0.0};       // L with the YAML weights
  double max_force{0.0};  // max |tau_unactuated|
  TaskMeasure task;
};

/// True when `b` gives the same answer as `a` within the thresholds stated in the findings:
/// final cost within 0.1%, Σh² within a factor 10 (or both below 1e-12), same task success.
bool SameAnswer(const Run& a, const Run& b) {
  const double va = a.solve.summary.constraint_violation;
  const double vb = b.solve.summary.constraint_violation;
  const bool violation =
      (va < 1e-12 && vb < 1e-12) || (va > 0.0 && vb > 0.0 && std::max(va / vb, vb / va) <= 10.0);
  return std::abs(a.cost - b.cost) <= 1e-3 * std::abs(a.cost) && violation &&
         a.task.success == b.task.success;
}

/// The section's opening: the two methods, the settings of the runs and what the columns mean.
std::string Introduction(const Context& context) {
  std::ostringstream md;
  md << "The unactuated generalized forces h(q) (the base or passive-joint rows of every τ_k) "
        "must vanish. `ConstraintMethod::kPenalty` adds ½ δt w Σh² to the cost (w = "
        "`penalty_weight`, or R's own entries on those DoFs when it is 0); "
        "`kLagrangeMultipliers` solves for multipliers each iteration with a dense "
        "(N·n_u)² system (docs/solver.md). Each example runs with its YAML settings except "
        "the method and weight ("
     << context.threads << " threads";
  if (context.quick) md << "; quick mode: at most 40 iterations";
  md << "). \"Final cost L\" is evaluated with the YAML weights for every run (R's own entries "
        "on the unactuated DoFs, no penalty override), so the rows compare on one scale; Σh² "
        "is the constraint violation after the last iteration and max |τ_u| the largest "
        "unactuated generalized force along the solution (N or N m). ms / iteration is the "
        "median over iterations that computed derivatives (the multipliers in parentheses); "
        "rejected steps are cheaper.\n\n";
  return md.str();
}

/// One run of `config` with `base` but the constraint method and penalty weight replaced; `own`
/// is R's own weight on the unactuated DoFs (the penalty's weight when `weight` is 0).
Run SolveWith(const Context& context, const ExampleConfig& config, const SolverOptions& base,
              double own, const std::string& label, ConstraintMethod method, double weight) {
  SolverOptions o = base;
  o.constraint_method = method;
  o.penalty_weight = weight;
  Run r;
  r.label = label;
  r.lagrange = method == ConstraintMethod::kLagrangeMultipliers;
  r.weight = r.lagrange ? 0.0 : (weight > 0.0 ? weight : own);
  r.solve = SolveRepeated(config, config.problem, o, context.repeats);
  r.cost = PlainCost(config, config.problem, r.solve.solution.q);
  r.max_force = MaxUnactuatedForce(config, config.problem, r.solve.solution);
  r.task = MeasureTask(config, config.problem, r.solve.solution);
  return r;
}

/// The runs of one example: Lagrange multipliers, the penalty with R's own weight, then each
/// swept weight that is not R's own, in increasing order.
std::vector<Run> RunMethods(const Context& context, const ExampleConfig& config,
                            const SolverOptions& base, double own,
                            const std::vector<double>& weights) {
  std::vector<Run> runs;
  runs.push_back(SolveWith(context, config, base, own, "Lagrange multipliers",
                           ConstraintMethod::kLagrangeMultipliers, 0.0));
  runs.push_back(SolveWith(context, config, base, own, "penalty, w = R's own (" + G(own) + ")",
                           ConstraintMethod::kPenalty, 0.0));
  for (double w : weights) {
    if (w != own) {
      runs.push_back(SolveWith(context, config, base, own, "penalty, w = " + G(w),
                               ConstraintMethod::kPenalty, w));
    }
  }
  return runs;
}

/// The "ms / iteration" cell: the median full iteration, and for multipliers their mean share.
std::string MsPerIteration(const Run& r) {
  const SolverSummary& s = r.solve.summary;
  std::string ms = Ms(MedianFullIterationSeconds(s));
  if (r.lagrange) {
    double multipliers = 0.0;
    int n = 0;
    for (const IterationSummary& it : s.log) {
      if (it.time_hessian > 0.0) {
        multipliers += it.time_multipliers;
        ++n;
      }
    }
    ms += " (" + Ms(n > 0 ? multipliers / n : 0.0) + ")";
  }
  return ms;
}

/// An example's heading and its table, a row per run.
std::string ExampleTable(const std::string& name, const ExampleConfig& config,
                         const SolverOptions& base, size_t num_unactuated,
                         const std::vector<Run>& runs) {
  std::ostringstream md;
  md << "**" << name << "** (nq = " << config.model.nq() << ", N = " << config.problem.num_steps
     << ", " << num_unactuated
     << " unactuated DoFs; YAML method: " << ConstraintMethodName(config.solver.constraint_method)
     << ", at most " << base.max_iterations << " iterations). Task: " << runs[0].task.name
     << "; success: " << runs[0].task.criterion << ".\n\n";
  Table table({"method", "termination (iterations)", "solve time (s)",
               "iterations (s) to within 1% of the final cost", "ms / iteration", "Σh²",
               "max \\|τ_u\\|", "final cost L", "task measure", "task success"});
  for (const Run& r : runs) {
    const SolverSummary& s = r.solve.summary;
    table.Row(
        {r.label, TerminationTypeName(s.termination) + " (" + std::to_string(s.iterations) + ")",
         Num(s.solve_time, 3), ConvergenceText(s), MsPerIteration(r), Sci(s.constraint_violation),
         Sci(r.max_force), Num(r.cost, 5), Num(r.task.value, 3), r.task.success ? "yes" : "no"});
  }
  md << table.Markdown() << "\n";
  return md.str();
}

/// The computed reading of an example's runs: Lagrange against the paper's penalty (R's own
/// weight), the best penalty weight by violation among those that do the task, whether a larger
/// weight always ended with a smaller violation and, on the spinner, the paper's finding.
std::string Reading(const std::string& name, const std::vector<Run>& runs) {
  std::ostringstream md;
  const Run& lm = runs[0];
  const Run& paper = runs[1];
  const Run* best = nullptr;
  for (size_t i = 1; i < runs.size(); ++i) {
    if (!runs[i].task.success) continue;
    if (best == nullptr ||
        runs[i].solve.summary.constraint_violation < best->solve.summary.constraint_violation) {
      best = &runs[i];
    }
  }
  const double t_lm = MedianFullIterationSeconds(lm.solve.summary);
  const double t_pen = MedianFullIterationSeconds(paper.solve.summary);
  md << "Reading: an iteration with multipliers costs " << Ms(t_lm) << " ms against " << Ms(t_pen)
     << " ms with the penalty (" << Times(t_lm / t_pen) << "); Σh² ends at "
     << Sci(lm.solve.summary.constraint_violation) << " with multipliers and "
     << Sci(paper.solve.summary.constraint_violation) << " with R's own penalty weight. ";
  if (best != nullptr) {
    md << "Among the penalty runs that do the task, the smallest violation is "
       << Sci(best->solve.summary.constraint_violation) << " (" << best->label << ", "
       << Num(best->solve.summary.solve_time, 3) << " s).";
  } else {
    md << "No penalty weight of this sweep does the task.";
  }
  // runs[2..] are the swept weights in increasing order.
  const Run* exception = nullptr;
  for (size_t i = 3; i < runs.size() && exception == nullptr; ++i) {
    if (runs[i].solve.summary.constraint_violation >
        runs[i - 1].solve.summary.constraint_violation) {
      exception = &runs[i];
      md << " A larger penalty weight did not always end with a smaller violation: w = "
         << G(runs[i].weight) << " ended at " << Sci(runs[i].solve.summary.constraint_violation)
         << ", w = " << G(runs[i - 1].weight) << " at "
         << Sci(runs[i - 1].solve.summary.constraint_violation) << ".";
    }
  }
  if (exception == nullptr && runs.size() > 3) {
    md << " Over the swept weights, each larger weight ended with a smaller violation.";
  }
  if (name == "spinner") {
    md << " The paper (§6.2) found Lagrange multipliers much better than the penalty on its "
          "spinner, where the penalty \"was not sufficient to drive the finger to touch the "
          "spinner\". ";
    const Convergence c = ConvergedWithin(paper.solve.summary, 0.01);
    if (lm.task.success && !paper.task.success) {
      md << "Here too the penalty with R's own weight falls short of the task: it turns the "
            "spinner by "
         << Num(paper.task.value, 3) << " rad (Lagrange: " << Num(lm.task.value, 3)
         << " rad) and ends with Σh² = " << Sci(paper.solve.summary.constraint_violation)
         << " after " << paper.solve.summary.iterations << " iterations ("
         << TerminationTypeName(paper.solve.summary.termination) << "; within 1% of its "
         << "final cost after " << c.iterations << ").";
    } else {
      md << "Here that does not hold: task success " << (lm.task.success ? "yes" : "no")
         << " with multipliers and " << (paper.task.success ? "yes" : "no")
         << " with R's own penalty weight.";
    }
  }
  md << "\n\n";
  return md.str();
}

/// The summary's finding for an example: the penalty with R's own weight `own` (runs[1])
/// instead of Lagrange multipliers (runs[0]).
Finding PenaltyFinding(const std::string& name, double own, const std::vector<Run>& runs) {
  const Run& lm = runs[0];
  const Run& paper = runs[1];
  const double t_lm = MedianFullIterationSeconds(lm.solve.summary);
  const double t_pen = MedianFullIterationSeconds(paper.solve.summary);
  Finding f;
  f.knob = "penalty (w = R's own " + G(own) + ") instead of Lagrange multipliers";
  f.example = name;
  f.speedup = t_lm / t_pen;
  f.speed = Ms(t_lm) + " → " + Ms(t_pen) + " ms per iteration; solve " +
            Num(lm.solve.summary.solve_time, 3) + " → " + Num(paper.solve.summary.solve_time, 3) +
            " s";
  f.free = SameAnswer(lm, paper);
  f.accuracy = "Σh² " + Sci(lm.solve.summary.constraint_violation) + " → " +
               Sci(paper.solve.summary.constraint_violation) + ", final cost " + Num(lm.cost, 4) +
               " → " + Num(paper.cost, 4) + ", task success " + (lm.task.success ? "yes" : "no") +
               " → " + (paper.task.success ? "yes" : "no") +
               (f.free ? " (same answer: cost within 0.1%, Σh² within 10×)" : "");
  return f;
}

/// The figure, Σh² per iteration in a panel per example, and its Markdown link ("" when gnuplot
/// is missing or fails).
std::string Figure(const Context& context,
                   const std::vector<std::pair<std::string, std::vector<Run>>>& all) {
  if (!context.gnuplot) return "";
  const std::string png = context.figure_dir + "/tradeoffs_constraints.png";
  std::ostringstream gp;
  const int panels = static_cast<int>(all.size());
  gp << GnuplotHeader(png, 480 * panels + 80, 480) << "set multiplot layout 1," << panels
     << "\nset logscale y\nset format y \"10^{%T}\"\nset xlabel \"iteration\"\n"
     << "set ylabel \"Σh² (constraint violation)\"\nset key bottom left font \",9\"\n";
  for (const auto& [name, runs] : all) {
    gp << "set title \"" << name << "\"\nplot ";
    for (size_t i = 0; i < runs.size(); ++i) {
      const std::string file =
          context.data_dir + "/constraints_" + name + "_" + std::to_string(i) + ".csv";
      std::ofstream out(file);
      for (const IterationSummary& it : runs[i].solve.summary.log) {
        // Below 1e-14 (before any contact) the curves carry no information.
        if (it.constraint_violation > 1e-14) {
          out << it.iteration << ',' << it.constraint_violation << '\n';
        }
      }
      gp << (i ? ", " : "") << GnuplotQuote(file) << " using 1:2 with lines lw "
         << (runs[i].lagrange ? 3 : 1.5) << (runs[i].lagrange ? " lc rgb \"black\"" : "")
         << " title " << GnuplotQuote(runs[i].label) << " noenhanced";
    }
    gp << "\n";
  }
  gp << "unset multiplot\n";
  if (!RunGnuplot(context.data_dir, "constraints", gp.str())) return "";
  return "![Constraint violation per iteration, penalty weights and Lagrange multipliers](" +
         context.figure_link_prefix + "tradeoffs_constraints.png)\n\n";
}

}  // namespace

StudyResult RunConstraintStudy(const Context& context) {
  StudyResult result;
  result.id = "constraints";
  result.title = "Penalty vs Lagrange multipliers";
  const std::vector<std::string> examples =
      context.quick ? std::vector<std::string>{"spinner"}
                    : std::vector<std::string>{"spinner", "hopper", "quadruped"};
  const std::vector<double> weights =
      context.quick ? std::vector<double>{1e3, 1e5} : std::vector<double>{1e2, 1e3, 1e4, 1e5, 1e6};
  std::ostringstream md;
  md << Introduction(context);

  std::vector<std::pair<std::string, std::vector<Run>>> all;
  for (const std::string& name : examples) {
    const ExampleConfig config = LoadExample(context, name);
    const std::vector<int> unactuated = config.problem.UnactuatedDofs(config.model);
    const double own = unactuated.empty() ? 0.0 : config.problem.R(unactuated.front());
    SolverOptions base = config.solver;
    base.num_threads = context.threads;
    if (context.quick) base.max_iterations = std::min(base.max_iterations, 40);

    const std::vector<Run> runs = RunMethods(context, config, base, own, weights);
    md << ExampleTable(name, config, base, unactuated.size(), runs) << Reading(name, runs);
    result.findings.push_back(PenaltyFinding(name, own, runs));
    all.push_back({name, runs});
  }
  md << Figure(context, all);
  result.markdown = md.str();
  return result;
}

}  // namespace idto::tradeoffs
