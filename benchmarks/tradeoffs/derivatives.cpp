// Forward vs central differences for d tau / d q: gradient error against a high-accuracy
// reference, convergence and time per iteration.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "studies.hpp"

namespace idto::tradeoffs {
namespace {

/// Richardson extrapolation to h -> 0 of the one-sided difference (L(s h) - L(0)) / (s h) at
/// h = h0, h0/2, h0/4, h0/8 (a full tableau: the h, h^2 and h^3 error terms are eliminated).
/// One-sided, so it stays valid where L is only C^1 at the point itself. *estimate is the last
/// correction of the tableau.
template <typename F>
double OneSidedRichardson(const F& cost, double f0, double side, double h0, double* estimate) {
  constexpr int kSteps = 4;
  double r[kSteps][kSteps];
  for (int j = 0; j < kSteps; ++j) {
    const double h = side * h0 / static_cast<double>(1 << j);
    r[j][0] = (cost(h) - f0) / h;
  }
  for (int m = 1; m < kSteps; ++m) {
    const double factor = static_cast<double>(1 << m);
    for (int j = 0; j + m < kSteps; ++j) {
      r[j][m] = (factor * r[j + 1][m - 1] - r[j][m - 1]) / (factor - 1.0);
    }
  }
  *estimate = std::abs(r[0][kSteps - 1] - r[1][kSteps - 2]);
  return r[0][kSteps - 1];
}

/// Initial steps of the reference, relative to max(1, |q_i|); per coordinate the one with the
/// smaller error estimate wins.
constexpr double kReferenceSteps[] = {1e-4, 1e-5};
/// The early iterate at which the gradient errors are compared for the summary.
constexpr int kMiddleIterations = 10;

struct Reference {
  Eigen::VectorXd g;  // the reference gradient
  double error{0.0};  // |per-coordinate error estimates|_2
  int cost_evaluations{0};
};

/// The gradient of the cost L(q) with respect to q_1..q_N from L alone (none of the solver's
/// derivatives): per coordinate, the mean of the forward-side and backward-side extrapolations.
/// Where L is C^1 both sides converge to the derivative, so half their difference (with the
/// tableau corrections) estimates the reference's error.
Reference ReferenceGradient(TrajectoryOptimizer* optimizer, std::vector<Eigen::VectorXd> q) {
  const int N = static_cast<int>(q.size()) - 1;
  const int nq = static_cast<int>(q[0].size());
  Reference ref;
  ref.g.resize(N * nq);
  const double f0 = optimizer->EvalCost(q);
  double error2 = 0.0;
  for (int k = 1; k <= N; ++k) {
    for (int i = 0; i < nq; ++i) {
      const double x = q[k](i);
      const auto cost = [&](double h) {
        q[k](i) = x + h;
        const double value = optimizer->EvalCost(q);
        q[k](i) = x;
        ++ref.cost_evaluations;
        return value;
      };
      double best = 0.0, best_error = std::numeric_limits<double>::infinity();
      for (double step : kReferenceSteps) {
        const double h0 = step * std::max(1.0, std::abs(x));
        double e_plus = 0.0, e_minus = 0.0;
        const double plus = OneSidedRichardson(cost, f0, 1.0, h0, &e_plus);
        const double minus = OneSidedRichardson(cost, f0, -1.0, h0, &e_minus);
        const double error = std::max({0.5 * std::abs(plus - minus), e_plus, e_minus});
        if (error < best_error) {
          best_error = error;
          best = 0.5 * (plus + minus);
        }
      }
      ref.g((k - 1) * nq + i) = best;
      error2 += best_error * best_error;
    }
  }
  ref.error = std::sqrt(error2);
  return ref;
}

/// ‖g − reference‖ for the solver's gradient with `method` and relative step `step` (0: the
/// scheme's default).
double GradientError(TrajectoryOptimizer* optimizer, const std::vector<Eigen::VectorXd>& q,
                     DerivativeMethod method, const Eigen::VectorXd& reference, double step = 0.0) {
  optimizer->mutable_options().derivative_method = method;
  optimizer->mutable_options().finite_difference_step = step;
  Eigen::VectorXd g;
  optimizer->EvalGradient(q, &g);
  optimizer->mutable_options().finite_difference_step = 0.0;
  return (g - reference).norm();
}

/// Relative steps of the step sweep.
constexpr double kSweepSteps[] = {1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9};

struct MethodRun {
  SolveResult solve;
  double cost{0.0};
  TaskMeasure task;
  double error_middle{0.0};      // relative gradient error after kMiddleIterations iterations
  double reference_middle{0.0};  // relative error estimate of the reference there
  // Step sweep at that point: relative error per kSweepSteps entry.
  std::vector<double> sweep;
};

}  // namespace

StudyResult RunDerivativeStudy(const Context& context) {
  StudyResult result;
  result.id = "derivatives";
  result.title = "Forward vs central differences";
  const std::vector<std::string> examples =
      context.quick ? std::vector<std::string>{"spinner"}
                    : std::vector<std::string>{"spinner", "hopper", "quadruped"};
  std::ostringstream md;
  md << "∂τ/∂q is computed by finite differences (docs/solver.md, \"Derivatives\"): forward "
        "(`DerivativeMethod::kForwardDifferences`, the default, relative step √ε ≈ 1.5e-8) or "
        "central (`kCentralDifferences`, step ∛ε ≈ 6e-6, twice the inverse dynamics). The "
        "other parts of the gradient are analytic. The **gradient error** is "
        "‖g − g_ref‖ for the solver's gradient g (`TrajectoryOptimizer::EvalGradient`, which "
        "uses the chosen scheme) against a reference g_ref that uses none of the solver's "
        "derivatives: the derivative of the cost L(q) itself (`EvalCost`) along each "
        "coordinate, from one-sided differences (L(q + s h e_i) − L(q)) / (s h) at h = h₀, h₀/2, "
        "h₀/4, h₀/8 extrapolated to h → 0 by Richardson (eliminating the h, h² and h³ terms), "
        "on both sides s = ±1, averaged; h₀ = 10⁻⁴ or 10⁻⁵ × max(1, |q_i|), whichever gives "
        "the smaller error estimate. Why one-sided: L is only C¹ where the dissipation d(v_n) "
        "switches branches, and a contact resting or sliding on a surface sits exactly at v_n = 0, "
        "where central "
        "differences converge only as O(h); a one-sided difference is smooth up to the "
        "point. Where L is C¹ both sides converge to the same derivative, so half their "
        "difference (with the tableau's last correction) estimates the reference's own "
        "error: the \"reference error\" column; a gradient error below it is not resolved. "
        "Contact pruning is off (`force_tolerance = 0`) for these "
        "comparisons so that L has no pruning steps. The points are the example's initial "
        "guess, the iterate after "
     << kMiddleIterations
     << " forward-difference iterations (where ‖g‖ is still large) and the forward-difference "
        "solution below (where ‖g‖ is small, so the relative error is large: that error is "
        "what limits how far a solve can converge). The solves use each example's YAML "
        "settings (its constraint method, iteration limit and default tolerances), "
     << context.threads << " threads";
  if (context.quick) md << ", at most 40 iterations (quick mode)";
  md << ".\n\n";

  Table grad({"example (nq, N)", "point", "‖g_ref‖", "reference error (relative)",
              "forward: ‖g − g_ref‖ (relative)", "central: ‖g − g_ref‖ (relative)"});
  int total_evaluations = 0;
  std::vector<std::string> sweep_header{"example", "scheme"};
  for (double step : kSweepSteps) sweep_header.push_back("step " + Sci(step));
  sweep_header.push_back("reference error");
  Table sweep(sweep_header);
  Table solve({"example", "method", "termination (iterations)", "solve time (s)",
               "iterations (s) to within 1% of the final cost",
               "ms / iteration (median, derivatives)", "final cost L", "Σh²", "task measure",
               "task success"});
  std::vector<std::pair<std::string, std::vector<IterationSummary>>> curves;
  std::vector<std::string> readings;
  for (const std::string& name : examples) {
    const ExampleConfig config = LoadExample(context, name);
    SolverOptions options = config.solver;
    options.num_threads = context.threads;
    if (context.quick) options.max_iterations = std::min(options.max_iterations, 40);

    MethodRun runs[2];
    const DerivativeMethod methods[2] = {DerivativeMethod::kForwardDifferences,
                                         DerivativeMethod::kCentralDifferences};
    for (int m = 0; m < 2; ++m) {
      SolverOptions o = options;
      o.derivative_method = methods[m];
      runs[m].solve = SolveRepeated(config, config.problem, o, context.repeats);
      runs[m].cost = PlainCost(config, config.problem, runs[m].solve.solution.q);
      runs[m].task = MeasureTask(config, config.problem, runs[m].solve.solution);
      curves.push_back({name + (m == 0 ? ", forward" : ", central"), runs[m].solve.summary.log});
    }

    // Gradient errors, pruning off, at the initial guess, an early iterate (the gradient is
    // still large) and the solution (the gradient is small: errors there set how far the
    // solver can converge).
    ProblemDefinition smooth = config.problem;
    smooth.contact.force_tolerance = 0.0;
    TrajectoryOptimizer optimizer(config.model, smooth, options);
    SolverOptions early_options = options;
    early_options.max_iterations = kMiddleIterations;
    early_options.fixed_iterations = true;
    const std::vector<Eigen::VectorXd> points[3] = {
        MakeInitialGuess(config), Solve(config, config.problem, early_options).solution.q,
        runs[0].solve.solution.q};
    const std::string point_names[3] = {
        "initial guess", "after " + std::to_string(kMiddleIterations) + " iterations",
        "solution (forward)"};
    for (int p = 0; p < 3; ++p) {
      const Reference ref = ReferenceGradient(&optimizer, points[p]);
      const double norm = ref.g.norm();
      const double forward =
          GradientError(&optimizer, points[p], DerivativeMethod::kForwardDifferences, ref.g);
      const double central =
          GradientError(&optimizer, points[p], DerivativeMethod::kCentralDifferences, ref.g);
      if (p == 1) {
        runs[0].error_middle = forward / norm;
        runs[1].error_middle = central / norm;
        runs[0].reference_middle = runs[1].reference_middle = ref.error / norm;
        for (int m = 0; m < 2; ++m) {
          std::vector<std::string> row{name, m == 0 ? "forward" : "central"};
          for (double step : kSweepSteps) {
            const DerivativeMethod method = m == 0 ? DerivativeMethod::kForwardDifferences
                                                   : DerivativeMethod::kCentralDifferences;
            runs[m].sweep.push_back(GradientError(&optimizer, points[p], method, ref.g, step) /
                                    norm);
            row.push_back(Sci(runs[m].sweep.back()));
          }
          row.push_back(Sci(ref.error / norm));
          sweep.Row(row);
        }
      }
      const auto cell = [&](double e) { return Sci(e) + " (" + Sci(e / norm) + ")"; };
      grad.Row({name + " (" + std::to_string(config.model.nq()) + ", " +
                    std::to_string(config.problem.num_steps) + ")",
                point_names[p], Sci(norm), cell(ref.error), cell(forward), cell(central)});
      total_evaluations += ref.cost_evaluations;
    }

    for (int m = 0; m < 2; ++m) {
      const MethodRun& r = runs[m];
      solve.Row({name, m == 0 ? "forward" : "central",
                 TerminationTypeName(r.solve.summary.termination) + " (" +
                     std::to_string(r.solve.summary.iterations) + ")",
                 Num(r.solve.summary.solve_time, 3), ConvergenceText(r.solve.summary),
                 Ms(MedianFullIterationSeconds(r.solve.summary)) + " (" +
                     Ms(MedianDerivativeSeconds(r.solve.summary)) + ")",
                 Num(r.cost, 5), Sci(r.solve.summary.constraint_violation),
                 r.task.name + " = " + Num(r.task.value, 3), r.task.success ? "yes" : "no"});
    }

    const MethodRun& fw = runs[0];
    const MethodRun& ce = runs[1];
    Finding f;
    f.knob = "forward instead of central differences";
    f.example = name;
    const double t_f = MedianFullIterationSeconds(fw.solve.summary);
    const double t_c = MedianFullIterationSeconds(ce.solve.summary);
    f.speedup = t_c / t_f;
    f.speed = Ms(t_c) + " → " + Ms(t_f) + " ms per iteration; solve " +
              Num(ce.solve.summary.solve_time, 3) + " → " + Num(fw.solve.summary.solve_time, 3) +
              " s (" + std::to_string(ce.solve.summary.iterations) + " → " +
              std::to_string(fw.solve.summary.iterations) + " iterations)";
    const double cost_change = std::abs(fw.cost - ce.cost) / std::abs(ce.cost);
    f.free = cost_change < 1e-3 && fw.task.success == ce.task.success;
    f.accuracy = "relative gradient error after " + std::to_string(kMiddleIterations) +
                 " iterations " + Sci(ce.error_middle) + " → " + Sci(fw.error_middle) +
                 "; final cost " + (cost_change < 1e-3 ? "within" : "off by") + " " +
                 Num(100.0 * cost_change, 2) + "% (threshold 0.1%); task success " +
                 (ce.task.success ? "yes" : "no") + " → " + (fw.task.success ? "yes" : "no");
    result.findings.push_back(f);

    // Computed reading for this example.
    std::ostringstream r;
    r << "**" << name << "**: after " << kMiddleIterations << " iterations the relative "
      << "gradient error is " << Sci(fw.error_middle) << " (forward) and " << Sci(ce.error_middle)
      << " (central), reference error " << Sci(fw.reference_middle) << ": ";
    if (fw.error_middle < 3.0 * fw.reference_middle &&
        ce.error_middle < 3.0 * fw.reference_middle) {
      r << "neither is resolved against the reference.";
    } else if (ce.error_middle < fw.error_middle / 3.0) {
      r << "central differences are " << Times(fw.error_middle / ce.error_middle)
        << " more accurate.";
    } else if (fw.error_middle < ce.error_middle / 3.0) {
      r << "forward differences are " << Times(ce.error_middle / fw.error_middle)
        << " more accurate.";
    } else {
      r << "the two are within a factor 3 of each other.";
    }
    // What the step sweep says: the best step of each scheme.
    for (int m = 0; m < 2; ++m) {
      const std::vector<double>& e = runs[m].sweep;
      const size_t best = std::min_element(e.begin(), e.end()) - e.begin();
      r << (m == 0 ? " Step sweep: forward" : "; central") << " at best " << Sci(e[best])
        << " (relative step " << Sci(kSweepSteps[best]) << ")";
    }
    r << ".";
    r << " Forward differences cost " << Ms(t_f) << " ms per iteration against " << Ms(t_c) << " ("
      << Times(f.speedup) << "); the solves end "
      << (f.free ? "with the same answer" : "differently") << " (final cost " << Num(ce.cost, 5)
      << " central, " << Num(fw.cost, 5) << " forward; task success "
      << (ce.task.success ? "yes" : "no") << " / " << (fw.task.success ? "yes" : "no") << ").";
    readings.push_back(r.str());
  }
  md << grad.Markdown() << "\n";
  md << "**Step sweep.** The same relative gradient error at the iterate after "
     << kMiddleIterations
     << " iterations with `SolverOptions::finite_difference_step` set to each relative step "
        "(the default is √ε ≈ 1.5e-8 forward, ∛ε ≈ 6e-6 central). Truncation error falls in "
        "proportion to the step (forward) or its square (central) until round-off, about "
        "ε/step, takes over. Where contact friction acts inside its stiction band, τ changes "
        "over a length of about v_s δt in q, and the default steps are then "
        "truncation-limited: both schemes can come out alike at their defaults, while a "
        "smaller central step is far more accurate at the same cost.\n\n"
     << sweep.Markdown() << "\n"
     << solve.Markdown() << "\n";

  // Computed reading.
  for (const std::string& r : readings) md << "- " << r << "\n";
  md << "\n";

  if (context.gnuplot) {
    const std::string png = context.figure_dir + "/tradeoffs_derivatives.png";
    std::ostringstream gp;
    const int panels = static_cast<int>(examples.size());
    gp << GnuplotHeader(png, 480 * panels + 60, 450) << "set multiplot layout 1," << panels
       << "\nset logscale y\nset xlabel \"iteration\"\nset ylabel \"cost L\"\n"
       << "set key top right\n";
    for (size_t e = 0; e < examples.size(); ++e) {
      gp << "set title \"" << examples[e] << ": cost per iteration\"\nplot ";
      for (int m = 0; m < 2; ++m) {
        const auto& curve = curves[2 * e + m];
        const std::string file = context.data_dir + "/derivatives_" + examples[e] +
                                 (m == 0 ? "_forward" : "_central") + ".csv";
        std::ofstream out(file);
        for (const IterationSummary& it : curve.second)
          out << it.iteration << ',' << it.cost << '\n';
        gp << (m ? ", " : "") << GnuplotQuote(file) << " using 1:2 with lines lw "
           << (m == 0 ? 4 : 2) << " lc rgb \"" << (m == 0 ? "#d95f02" : "#1b9e77") << "\" title \""
           << (m == 0 ? "forward" : "central") << "\"";
      }
      gp << "\n";
    }
    gp << "unset multiplot\n";
    if (RunGnuplot(context.data_dir, "derivatives", gp.str())) {
      md << "![Cost per iteration, forward vs central differences](" << context.figure_link_prefix
         << "tradeoffs_derivatives.png)\n\n";
    }
  }
  result.markdown = md.str();
  return result;
}

}  // namespace idto::tradeoffs
