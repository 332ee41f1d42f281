// Analytic derivatives vs forward and central differences for d tau / d q: gradient error
// against a high-accuracy reference (derivative_reference.cpp), the step sweep of the two
// difference schemes, convergence and time per iteration.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "derivative_reference.hpp"
#include "studies.hpp"

namespace idto::tradeoffs {
namespace {

/// The early iterate at which the gradient errors are compared for the summary.
constexpr int kMiddleIterations = 10;
/// An error below this multiple of the reference's error estimate is not resolved.
constexpr double kResolution = 3.0;

enum MethodIndex { kA = 0, kF = 1, kC = 2 };
constexpr int kNumMethods = 3;
constexpr DerivativeMethod kMethods[kNumMethods] = {DerivativeMethod::kAnalytic,
                                                    DerivativeMethod::kForwardDifferences,
                                                    DerivativeMethod::kCentralDifferences};
const char* const kMethodNames[kNumMethods] = {"analytic", "forward", "central"};

const double kSqrtEps = std::sqrt(std::numeric_limits<double>::epsilon());
const double kCbrtEps = std::cbrt(std::numeric_limits<double>::epsilon());

/// Relative steps of the step sweep (the two defaults included) and their column labels.
struct SweepStep {
  double step;
  std::string label;
};
std::vector<SweepStep> SweepSteps() {
  return {{1e-4, "1.0e-4"}, {1e-5, "1.0e-5"}, {kCbrtEps, "∛ε = " + Sci(kCbrtEps)},
          {1e-6, "1.0e-6"}, {1e-7, "1.0e-7"}, {kSqrtEps, "√ε = " + Sci(kSqrtEps, 3)},
          {1e-8, "1.0e-8"}, {1e-9, "1.0e-9"}};
}

struct MethodRun {
  SolveResult solve;
  double cost{0.0};
  TaskMeasure task;
};

/// Gradient errors at one point (absolute; divide by norm for the relative ones).
struct PointErrors {
  std::string name;
  double norm{0.0};       // ‖g_ref‖
  double reference{0.0};  // the reference's error estimate
  double error[kNumMethods]{};
  double central_sqrt_eps{0.0};  // central differences at relative step √ε
};

struct ExampleRun {
  std::string name;
  int nq{0}, N{0};
  MethodRun runs[kNumMethods];
  PointErrors points[3];  // initial guess, after kMiddleIterations, solution (analytic)
  // Step sweep at points[1]: relative error per SweepSteps() entry, forward [0], central [1].
  std::vector<double> sweep[2];
  int cost_evaluations{0};
};

/// "1.2e4×" for large ratios, "35×" otherwise.
std::string Ratio(double x) { return x >= 1e4 ? Sci(x) + "×" : Times(x); }

/// Gradient errors at the three points, pruning off (L then has no pruning steps): the initial
/// guess, an early iterate (the gradient is still large) and the solution (the gradient is
/// small: errors there set how far the solver can converge).
void MeasureGradients(const ExampleConfig& config, const SolverOptions& options,
                      const std::vector<Eigen::VectorXd>& solution, ExampleRun* run) {
  ProblemDefinition smooth = config.problem;
  smooth.contact.force_tolerance = 0.0;
  TrajectoryOptimizer optimizer(config.model, smooth, options);
  SolverOptions early_options = options;
  early_options.max_iterations = kMiddleIterations;
  early_options.fixed_iterations = true;
  const std::vector<Eigen::VectorXd> points[3] = {
      MakeInitialGuess(config), Solve(config, config.problem, early_options).solution.q, solution};
  const std::string names[3] = {"initial guess",
                                "after " + std::to_string(kMiddleIterations) + " iterations",
                                "solution (analytic)"};
  const std::vector<SweepStep> steps = SweepSteps();
  for (int p = 0; p < 3; ++p) {
    const Reference ref = ReferenceGradient(&optimizer, points[p]);
    run->cost_evaluations += ref.cost_evaluations;
    PointErrors& e = run->points[p];
    e.name = names[p];
    e.norm = ref.g.norm();
    e.reference = ref.error;
    for (int m = 0; m < kNumMethods; ++m) {
      // Central differences at cbrt(eps), the step this comparison is about (the library's
      // central default on contact problems is sqrt(eps) since it).
      e.error[m] =
          GradientError(&optimizer, points[p], kMethods[m], ref.g, m == kC ? kCbrtEps : 0.0);
    }
    e.central_sqrt_eps = GradientError(&optimizer, points[p], DerivativeMethod::kCentralDifferences,
                                       ref.g, kSqrtEps);
    if (p != 1) continue;
    for (int s = 0; s < 2; ++s) {
      for (const SweepStep& step : steps) {
        run->sweep[s].push_back(
            GradientError(&optimizer, points[p], kMethods[kF + s], ref.g, step.step) / e.norm);
      }
    }
  }
}

/// The solves with each method (each example's YAML settings) and the gradient errors.
ExampleRun MeasureExample(const Context& context, const std::string& name) {
  const ExampleConfig config = LoadExample(context, name);
  SolverOptions options = config.solver;
  options.num_threads = context.threads;
  if (context.quick) options.max_iterations = std::min(options.max_iterations, 40);
  ExampleRun run;
  run.name = name;
  run.nq = config.model.nq();
  run.N = config.problem.num_steps;
  for (int m = 0; m < kNumMethods; ++m) {
    SolverOptions o = options;
    o.derivative_method = kMethods[m];
    // Separate passes for every method, so the derivative phase is timed on its own and the
    // methods differ in the derivatives only (trial derivatives: docs/benchmarks.md).
    o.trial_derivatives = false;
    if (m == kC) o.finite_difference_step = kCbrtEps;  // as in the gradient table
    MethodRun& r = run.runs[m];
    r.solve = SolveRepeated(config, config.problem, o, context.repeats);
    r.cost = PlainCost(config, config.problem, r.solve.solution.q);
    r.task = MeasureTask(config, config.problem, r.solve.solution);
  }
  options.derivative_method = DerivativeMethod::kAnalytic;
  MeasureGradients(config, options, run.runs[kA].solve.solution.q, &run);
  return run;
}

std::string Introduction(const Context& context, const std::vector<std::string>& examples) {
  std::ostringstream md;
  md << "∂τ/∂q (`SolverOptions::derivative_method`, docs/solver.md, \"Derivatives\") is "
        "computed in one of three ways. **Analytic** (`DerivativeMethod::kAnalytic`, the "
        "default) is exact: the analytic derivatives of the inverse dynamics (RNEA) plus the "
        "analytic derivative of every contact pair's forces, one evaluation per time step; only "
        "the geometry of pairs answered by FCL (the shape pairs without a closed form, such as "
        "box–box or cylinder–box) is differentiated by per-pair central differences, and the "
        "examples here have no such pair (their shapes are spheres, a box in allegro and in "
        "bimanual, and the ground). **Forward differences** (`kForwardDifferences`, relative "
        "step √ε ≈ "
     << Sci(kSqrtEps) << ", one perturbed inverse dynamics per coordinate) and **central "
     << "differences** (`kCentralDifferences`, twice the inverse dynamics; here at relative step "
        "∛ε ≈ "
     << Sci(kCbrtEps)
     << ", its default without contact: since this comparison the default with contact is √ε) "
        "remain options; `SolverOptions::finite_difference_step` "
        "overrides their relative step. The other parts of the gradient are analytic with every "
        "method. The **gradient error** is ‖g − g_ref‖ for the solver's gradient g "
        "(`TrajectoryOptimizer::EvalGradient`, with the chosen method) against a reference "
        "g_ref that uses none of the solver's derivatives: the derivative of the cost L(q) "
        "itself (`EvalCost`) along each coordinate, from one-sided differences "
        "(L(q + s h e_i) − L(q)) / (s h) at h = h₀, h₀/2, h₀/4, h₀/8 extrapolated to h → 0 by "
        "Richardson (eliminating the h, h² and h³ terms), on both sides s = ±1, averaged; h₀ = "
        "10⁻⁴ or 10⁻⁵ × max(1, |q_i|), whichever gives the smaller error estimate. Why "
        "one-sided: L is only C¹ where the dissipation d(v_n) switches branches, and a contact "
        "resting or sliding on a surface sits exactly at v_n = 0, where central differences "
        "converge only as O(h); a one-sided difference is smooth up to the point. Where L is C¹ "
        "both sides converge to the same derivative, so half their difference (with the "
        "tableau's last correction) estimates the reference's own error: the \"reference "
        "error\" column. A gradient error below about "
     << Num(kResolution, 1)
     << "× the reference error is not resolved: the reference cannot tell it from zero, so an "
        "exact gradient shows up there as an error about the size of the reference's. Contact "
        "pruning is off (`force_tolerance = 0`) for these comparisons so that L has no pruning "
        "steps, and so are trial derivatives (`trial_derivatives = false`, which only the "
        "analytic method has: every method then evaluates and differentiates in separate passes, "
        "and the derivative phase is timed on its own; their speed-up is in docs/benchmarks.md, "
        "session 35). The points are the example's initial guess, the iterate after "
     << kMiddleIterations
     << " iterations with the default (analytic) derivatives (where ‖g‖ is still large) and "
        "the analytic solution below (where ‖g‖ is small, so the relative error is large: that "
        "error is what limits how far a solve can converge). The last column is central "
        "differences at relative step √ε instead of ∛ε. The solves use each "
        "example's YAML settings (its constraint method, iteration limit and default "
        "tolerances), "
     << context.threads << " threads";
  if (context.quick) md << ", at most 40 iterations (quick mode)";
  md << "; examples: ";
  for (size_t i = 0; i < examples.size(); ++i) md << (i ? ", " : "") << examples[i];
  md << ".\n\n";
  return md.str();
}

void AddGradientRows(const ExampleRun& run, Table* table) {
  for (const PointErrors& p : run.points) {
    const auto cell = [&](double e) { return Sci(e) + " (" + Sci(e / p.norm) + ")"; };
    table->Row({run.name + " (" + std::to_string(run.nq) + ", " + std::to_string(run.N) + ")",
                p.name, Sci(p.norm), cell(p.error[kA]), cell(p.reference), cell(p.error[kF]),
                cell(p.error[kC]), cell(p.central_sqrt_eps)});
  }
}

void AddSweepRows(const ExampleRun& run, Table* table) {
  for (int s = 0; s < 2; ++s) {
    std::vector<std::string> row{run.name, kMethodNames[kF + s]};
    for (double e : run.sweep[s]) row.push_back(Sci(e));
    row.push_back(Sci(run.points[1].reference / run.points[1].norm));
    table->Row(row);
  }
}

/// `text` with every '|' escaped for a Markdown table cell.
std::string EscapeBars(std::string text) {
  for (size_t at = text.find('|'); at != std::string::npos; at = text.find('|', at + 2)) {
    text.insert(at, "\\");
  }
  return text;
}

void AddSolveRows(const ExampleRun& run, Table* table) {
  for (int m = 0; m < kNumMethods; ++m) {
    const MethodRun& r = run.runs[m];
    table->Row({run.name, kMethodNames[m],
                TerminationTypeName(r.solve.summary.termination) + " (" +
                    std::to_string(r.solve.summary.iterations) + ")",
                Num(r.solve.summary.solve_time, 3), ConvergenceText(r.solve.summary),
                Ms(MedianFullIterationSeconds(r.solve.summary)) + " (" +
                    Ms(MedianDerivativeSeconds(r.solve.summary)) + ")",
                Num(r.cost, 5), Sci(r.solve.summary.constraint_violation),
                EscapeBars(r.task.name) + " = " + Num(r.task.value, 3),
                r.task.success ? "yes" : "no"});
  }
}

/// One finding: `cheap` instead of `accurate`, measured on one example.
Finding Compare(const ExampleRun& run, int cheap, int accurate, const std::string& knob) {
  const MethodRun& a = run.runs[accurate];
  const MethodRun& c = run.runs[cheap];
  Finding f;
  f.knob = knob;
  f.example = run.name;
  const double t_a = MedianFullIterationSeconds(a.solve.summary);
  const double t_c = MedianFullIterationSeconds(c.solve.summary);
  f.speedup = t_a / t_c;
  f.speed = Ms(t_a) + " → " + Ms(t_c) + " ms per iteration; solve " +
            Num(a.solve.summary.solve_time, 3) + " → " + Num(c.solve.summary.solve_time, 3) +
            " s (" + std::to_string(a.solve.summary.iterations) + " → " +
            std::to_string(c.solve.summary.iterations) + " iterations)";
  const double cost_change = std::abs(c.cost - a.cost) / std::abs(a.cost);
  f.free = cost_change < 1e-3 && c.task.success == a.task.success;
  const PointErrors& p = run.points[1];
  const auto error = [&](int m) {
    return Sci(p.error[m] / p.norm) +
           (p.error[m] < kResolution * p.reference ? " (below the reference's resolution)" : "");
  };
  f.accuracy = "relative gradient error after " + std::to_string(kMiddleIterations) +
               " iterations " + error(accurate) + " → " + error(cheap) + "; final cost " +
               (cost_change < 1e-3 ? "within" : "off by") + " " + Num(100.0 * cost_change, 2) +
               "% (threshold 0.1%); task success " + (a.task.success ? "yes" : "no") + " → " +
               (c.task.success ? "yes" : "no");
  return f;
}

/// "at the initial guess", "after 10 iterations", "at the solution".
std::string AtPoint(int p) {
  if (p == 0) return "at the initial guess";
  if (p == 1) return "after " + std::to_string(kMiddleIterations) + " iterations";
  return "at the solution";
}

/// "a", "a and b", "a, b and c".
std::string JoinAnd(const std::vector<std::string>& items) {
  std::string text;
  for (size_t i = 0; i < items.size(); ++i) {
    text += (i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + items[i];
  }
  return text;
}

/// Verdicts over the points of all examples, for the overall reading.
struct Tally {
  int shown{0}, limited{0}, below{0};                 // analytic vs forward, 100x
  int better{0}, worse{0}, within{0}, unresolved{0};  // central at √ε vs ∛ε
};

/// Forward error / analytic error at each point, and whether the analytic gradient is shown to
/// be at least 100x more accurate.
std::string AnalyticReading(const ExampleRun& run, Tally* tally) {
  std::ostringstream r;
  r << "Forward / analytic gradient error (measured ratio):";
  std::vector<std::string> shown, limited, below;
  for (int p = 0; p < 3; ++p) {
    const PointErrors& e = run.points[p];
    const double a = e.error[kA], f = e.error[kF], ref = e.reference;
    r << (p ? "; " : " ") << AtPoint(p) << " " << Ratio(f / a);
    if (a < kResolution * ref) {
      const double bound = f / ref;
      r << " (analytic error below the reference's resolution; ratio ≥ forward/reference = "
        << Ratio(bound) << (f < kResolution * ref ? ": forward's error is below it too" : "")
        << ")";
      (bound >= 100.0 ? shown : limited).push_back(AtPoint(p));
    } else if (f / a >= 100.0) {
      shown.push_back(AtPoint(p));
    } else {
      below.push_back(AtPoint(p) + " (" + Ratio(f / a) + ")");
    }
  }
  r << ". **Analytic at least 100× more accurate than forward differences: "
    << (shown.empty() ? "shown at none of the 3 points" : "yes " + JoinAnd(shown)) << "**";
  if (!limited.empty()) {
    r << "; limited by the reference's own error " << JoinAnd(limited)
      << " (forward's error is less than 100× the reference's there)";
  }
  if (!below.empty()) r << "; resolved and less than 100× " << JoinAnd(below);
  r << ".";
  tally->shown += static_cast<int>(shown.size());
  tally->limited += static_cast<int>(limited.size());
  tally->below += static_cast<int>(below.size());
  return r.str();
}

/// Central differences at √ε against ∛ε at each point.
std::string CentralStepReading(const ExampleRun& run, Tally* tally) {
  std::ostringstream r;
  r << "Central differences at √ε (relative step " << Sci(kSqrtEps, 3) << ") vs ∛ε ("
    << Sci(kCbrtEps) << "), relative error:";
  int better = 0, worse = 0, within = 0, unresolved = 0;
  for (int p = 0; p < 3; ++p) {
    const PointErrors& e = run.points[p];
    const double s = e.central_sqrt_eps, c = e.error[kC], limit = kResolution * e.reference;
    r << (p ? "; " : " ") << AtPoint(p) << " " << Sci(s / e.norm) << " vs " << Sci(c / e.norm);
    const double ratio = std::max(c, e.reference) / std::max(s, e.reference);
    if (s < limit && c < limit) {
      ++unresolved;
      r << " (both below the reference's resolution)";
    } else if (ratio > kResolution) {
      ++better;
      r << " (√ε " << (s < limit ? "at least " : "") << Ratio(ratio) << " more accurate)";
    } else if (ratio < 1.0 / kResolution) {
      ++worse;
      r << " (∛ε " << (c < limit ? "at least " : "") << Ratio(1.0 / ratio) << " more accurate)";
    } else {
      ++within;
      r << " (within " << Num(kResolution, 1) << "×)";
    }
  }
  r << ". ";
  tally->better += better;
  tally->worse += worse;
  tally->within += within;
  tally->unresolved += unresolved;
  if (better > 0 && worse == 0) {
    r << "So √ε is the better central step on " << run.name << " (more than " << Num(kResolution, 1)
      << "× more accurate at " << better << " of 3 points, worse at none).";
  } else if (worse > 0 && better == 0) {
    r << "So ∛ε is the better central step on " << run.name << " (more than " << Num(kResolution, 1)
      << "× more accurate at " << worse << " of 3 points, worse at none).";
  } else if (better > 0) {
    r << "Neither step is better everywhere on " << run.name << ": √ε wins at " << better
      << " points, ∛ε at " << worse << ".";
  } else {
    r << "The two steps are equivalent on " << run.name << " at the reference's resolution.";
  }
  return r.str();
}

/// The step sweep's best steps and the speed and answers of the three solves.
std::string SweepAndSpeedReading(const ExampleRun& run) {
  std::ostringstream r;
  const std::vector<SweepStep> steps = SweepSteps();
  for (int s = 0; s < 2; ++s) {
    const std::vector<double>& e = run.sweep[s];
    const size_t best = std::min_element(e.begin(), e.end()) - e.begin();
    r << (s == 0 ? "Step sweep after " + std::to_string(kMiddleIterations) + " iterations: forward"
                 : "; central")
      << " at best " << Sci(e[best]) << " (relative step " << steps[best].label << ")";
  }
  double t[kNumMethods];
  for (int m = 0; m < kNumMethods; ++m)
    t[m] = MedianFullIterationSeconds(run.runs[m].solve.summary);
  r << ". Per iteration: analytic " << Ms(t[kA]) << " ms, forward " << Ms(t[kF]) << ", central "
    << Ms(t[kC]) << " (time of forward / analytic " << Times(t[kF] / t[kA])
    << ", central / analytic " << Times(t[kC] / t[kA]) << "); final cost L";
  for (int m = 0; m < kNumMethods; ++m) {
    r << (m ? ", " : " ") << Num(run.runs[m].cost, 5) << " (" << kMethodNames[m] << ")";
  }
  r << "; task success";
  for (int m = 0; m < kNumMethods; ++m) {
    r << (m ? " / " : " ") << (run.runs[m].task.success ? "yes" : "no");
  }
  r << ".";
  return r.str();
}

/// The verdicts over all examples, and the per-iteration speed of analytic vs forward.
std::string OverallReading(const std::vector<ExampleRun>& runs, const Tally& t) {
  const int points = 3 * static_cast<int>(runs.size());
  double slowest = 1e300, fastest = 0.0;
  int faster = 0;
  for (const ExampleRun& run : runs) {
    const double ratio = MedianFullIterationSeconds(run.runs[kF].solve.summary) /
                         MedianFullIterationSeconds(run.runs[kA].solve.summary);
    slowest = std::min(slowest, ratio);
    fastest = std::max(fastest, ratio);
    if (ratio > 1.0) ++faster;
  }
  std::ostringstream md;
  md << "**Over the " << runs.size() << " example" << (runs.size() > 1 ? "s" : "") << " (" << points
     << " points).** The analytic gradient is shown at least 100× more accurate than "
     << "forward differences at " << t.shown << " of " << points << " points; at " << t.limited
     << " the reference's own error limits the comparison (forward's error is less than 100× "
        "the reference's, so no ratio of 100 can be resolved); at "
     << t.below
     << " it is resolved and less than 100×. Against forward-mode automatic differentiation of "
        "the whole cost, which has no such floor (tests/examples/gradient_oracle_test.cpp; "
        "docs/solver.md, \"Derivatives\"), the analytic gradient is exact to round-off and more "
        "than 100× more accurate than forward differences at every point that test checks (the "
        "initial guess and the iterate after 10 iterations of the spinner, hopper, quadruped, "
        "Allegro and bi-manual). Central differences at √ε are more than "
     << Num(kResolution, 1) << "× more accurate than at ∛ε at " << t.better << " points, more than "
     << Num(kResolution, 1) << "× less accurate at " << t.worse << ", within "
     << Num(kResolution, 1) << "× at " << t.within << " and both unresolved at " << t.unresolved
     << ": ";
  if (t.better > 0 && t.worse == 0) {
    md << "on these contact problems √ε is the better central step wherever the difference is "
          "resolved.";
  } else if (t.worse > 0 && t.better == 0) {
    md << "on these contact problems ∛ε is the better central step wherever the "
          "difference is resolved.";
  } else if (t.better > 0) {
    md << "neither central step is better on every point.";
  } else {
    md << "the two central steps cannot be told apart here.";
  }
  md << " An iteration with analytic derivatives was faster than with forward differences on "
     << faster << " of " << runs.size() << " examples (time of forward / analytic "
     << Times(slowest) << "–" << Times(fastest) << ").\n\n";
  return md.str();
}

/// Cost per iteration, one panel per example, one curve per method.
std::string Figure(const Context& context, const std::vector<ExampleRun>& runs) {
  const std::string png = context.figure_dir + "/tradeoffs_derivatives.png";
  const int panels = static_cast<int>(runs.size());
  const int columns = std::min(panels, 3), rows = (panels + 2) / 3;
  std::ostringstream gp;
  gp << GnuplotHeader(png, 480 * columns + 60, 420 * rows + 30) << "set multiplot layout " << rows
     << "," << columns << "\nset logscale y\nset xlabel \"iteration\"\n"
     << "set ylabel \"cost L\"\nset key top right\n";
  const char* const colors[kNumMethods] = {"#7570b3", "#d95f02", "#1b9e77"};
  const int widths[kNumMethods] = {5, 3, 1};
  for (const ExampleRun& run : runs) {
    gp << "set title \"" << run.name << ": cost per iteration\"\nplot ";
    for (int m = 0; m < kNumMethods; ++m) {
      const std::string file =
          context.data_dir + "/derivatives_" + run.name + "_" + kMethodNames[m] + ".csv";
      std::ofstream out(file);
      for (const IterationSummary& it : run.runs[m].solve.summary.log) {
        out << it.iteration << ',' << it.cost << '\n';
      }
      gp << (m ? ", " : "") << GnuplotQuote(file) << " using 1:2 with lines lw " << widths[m]
         << " lc rgb \"" << colors[m] << "\" title \"" << kMethodNames[m] << "\"";
    }
    gp << "\n";
  }
  gp << "unset multiplot\n";
  if (!RunGnuplot(context.data_dir, "derivatives", gp.str())) return "";
  return "![Cost per iteration, analytic derivatives vs forward and central differences](" +
         context.figure_link_prefix + "tradeoffs_derivatives.png)\n\n";
}

}  // namespace

StudyResult RunDerivativeStudy(const Context& context) {
  StudyResult result;
  result.id = "derivatives";
  result.title = "Analytic derivatives vs forward and central differences";
  const std::vector<std::string> examples =
      context.quick
          ? std::vector<std::string>{"spinner"}
          : std::vector<std::string>{"spinner", "hopper", "quadruped", "allegro", "bimanual"};
  std::vector<ExampleRun> runs;
  for (const std::string& name : examples) runs.push_back(MeasureExample(context, name));

  Table grad({"example (nq, N)", "point", "‖g_ref‖", "analytic: ‖g − g_ref‖ (relative)",
              "reference error (relative)", "forward: ‖g − g_ref‖ (relative)",
              "central: ‖g − g_ref‖ (relative)", "central at √ε: ‖g − g_ref‖ (relative)"});
  std::vector<std::string> sweep_header{"example", "scheme"};
  for (const SweepStep& step : SweepSteps()) sweep_header.push_back("step " + step.label);
  sweep_header.push_back("reference error");
  Table sweep(sweep_header);
  Table solve({"example", "method", "termination (iterations)", "solve time (s)",
               "iterations (s) to within 1% of the final cost",
               "ms / iteration (median, derivatives)", "final cost L", "Σh²", "task measure",
               "task success"});
  for (const ExampleRun& run : runs) {
    AddGradientRows(run, &grad);
    AddSweepRows(run, &sweep);
    AddSolveRows(run, &solve);
    result.findings.push_back(Compare(run, kA, kF, "analytic instead of forward differences"));
    result.findings.push_back(Compare(run, kF, kC, "forward instead of central differences"));
  }

  std::ostringstream md;
  md << Introduction(context, examples) << grad.Markdown() << "\n";
  md << "**Step sweep.** The relative gradient error of the two difference schemes at the "
        "iterate after "
     << kMiddleIterations
     << " iterations with `SolverOptions::finite_difference_step` set to each relative step "
        "(√ε ≈ "
     << Sci(kSqrtEps) << ", the forward default and the central one with contact, and ∛ε ≈ "
     << Sci(kCbrtEps)
     << ", the central default without contact, are both columns). Truncation error falls in "
        "proportion to the step "
        "(forward) or its square (central) until round-off, about ε/step, takes over. Where "
        "contact friction acts inside its stiction band, τ changes over a length of about "
        "v_s δt in q, and the default steps are then truncation-limited: both schemes can come "
        "out alike at their defaults, while a smaller central step can be far more accurate at "
        "the same cost. The analytic gradient has no step.\n\n"
     << sweep.Markdown() << "\n"
     << solve.Markdown() << "\n";
  Tally tally;
  for (const ExampleRun& run : runs) {
    md << "- **" << run.name << "**\n  - " << AnalyticReading(run, &tally) << "\n  - "
       << CentralStepReading(run, &tally) << "\n  - " << SweepAndSpeedReading(run) << "\n";
  }
  md << "\n" << OverallReading(runs, tally);
  if (context.gnuplot) md << Figure(context, runs);
  result.markdown = md.str();
  return result;
}

}  // namespace idto::tradeoffs
