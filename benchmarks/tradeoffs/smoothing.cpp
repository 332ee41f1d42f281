// Smoothing sigma: how much force the contact law applies at a distance, and what that buys
// in convergence on the spinner and the hopper.

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "idto/contact/contact_law.hpp"
#include "studies.hpp"

namespace idto::tradeoffs {
namespace {

struct Run {
  double sigma{0.0};
  SolveResult solve;
  double cost{0.0};
  TaskMeasure task;
  ContactImpulse impulse;
};

// Below this total normal impulse (N s) a solution has no contact to speak of.
constexpr double kNoContact = 1e-6;

double AtDistanceShare(const ContactImpulse& impulse) {
  return impulse.total >= kNoContact ? impulse.at_distance / impulse.total : std::nan("");
}

std::string ImpulseShare(const ContactImpulse& impulse) {
  const double share = AtDistanceShare(impulse);
  return std::isnan(share) ? "no contact" : Num(100.0 * share, 3) + "%";
}

/// The law itself: f_n = c(phi) d(v_n) at rest (d = 1) with `law`'s stiffness, at a few distances
/// for each sigma, and the pruning cut-off at `tolerance`; the section's opening.
std::string LawSection(ContactParameters law, double tolerance, const std::vector<double>& sigmas) {
  const std::vector<double> distances = {0.0, 0.001, 0.005, 0.01, 0.02, 0.05};
  std::vector<std::string> header{"σ (m)"};
  for (double phi : distances) header.push_back("φ = " + G(1e3 * phi) + " mm");
  header.push_back("pruning cut-off at " + G(tolerance) + " N");
  Table force(header);
  for (double sigma : sigmas) {
    law.smoothing = sigma;
    std::vector<std::string> row{G(sigma)};
    for (double phi : distances) {
      row.push_back(
          Sci(CalcContactForce(law, phi, 0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()).fn,
              2));
    }
    row.push_back(Num(100.0 * ContactCutoffDistance(law, tolerance), 3) + " cm");
    force.Row(row);
  }
  std::ostringstream md;
  md << "The normal force of the contact law is f_n = σ k log(1 + e^(−φ/σ)) · d(v_n) "
        "(`idto::CalcContactForce`, docs/contact.md): σ trades a smoother problem for force at "
        "a distance. Normal force (N) at rest (d = 1) at signed distance φ, with the spinner's "
        "k = "
     << Num(law.stiffness) << " N/m (f_n is proportional to k), computed by `CalcContactForce`; "
     << "the last column is the distance beyond which the engine prunes a pair "
        "(`ContactCutoffDistance` at the example's `force_tolerance`):\n\n"
     << force.Markdown() << "\n";
  return md.str();
}

/// Solves `config` with `options` once per sigma (the example's own settings, sigma replaced).
std::vector<Run> SolveSigmas(const Context& context, const ExampleConfig& config,
                             const SolverOptions& options, const std::vector<double>& sigmas) {
  std::vector<Run> runs;
  for (double sigma : sigmas) {
    ProblemDefinition problem = config.problem;
    problem.contact.parameters.smoothing = sigma;
    Run run;
    run.sigma = sigma;
    run.solve = SolveRepeated(config, problem, options, context.repeats);
    run.cost = PlainCost(config, problem, run.solve.solution.q);
    run.task = MeasureTask(config, problem, run.solve.solution);
    run.impulse = MeasureContactImpulse(config, problem, run.solve.solution);
    runs.push_back(run);
  }
  return runs;
}

/// An example's heading and its table, a row per sigma.
std::string ExampleTable(const std::string& name, const ExampleConfig& config,
                         const SolverOptions& options, const std::vector<Run>& runs) {
  const Run& any = runs.front();
  std::ostringstream md;
  md << "**" << name << "** (`examples/" << name << "/" << name
     << ".yaml`, σ replaced; its solver section: "
     << ConstraintMethodName(options.constraint_method) << ", at most " << options.max_iterations
     << " iterations, default tolerances, " << options.num_threads
     << " threads; default σ = " << G(config.problem.contact.parameters.smoothing)
     << " m, k = " << G(config.problem.contact.parameters.stiffness)
     << " N/m). Task: " << any.task.name << "; success: " << any.task.criterion
     << ". \"At a distance\" is the share of the normal contact impulse Σ f_n δt along the "
        "solution that comes from pairs that are apart (φ > 0):\n\n";
  Table table({"σ (m)", "termination (iterations)", "solve time (s)",
               "iterations (s) to within 1% of the final cost", "ms / iteration", "final cost L",
               "Σh²", any.task.name, "task success", "impulse at a distance"});
  for (const Run& r : runs) {
    table.Row({G(r.sigma),
               TerminationTypeName(r.solve.summary.termination) + " (" +
                   std::to_string(r.solve.summary.iterations) + ")",
               Num(r.solve.summary.solve_time, 3), ConvergenceText(r.solve.summary),
               Ms(MeanIterationSeconds(r.solve.summary)), Num(r.cost, 4),
               Sci(r.solve.summary.constraint_violation), Num(r.task.value, 3),
               r.task.success ? "yes" : "no", ImpulseShare(r.impulse)});
  }
  md << table.Markdown() << "\n";
  return md.str();
}

/// What an example's sweep did: the run with the example's own sigma, the quickest run (to
/// within 1% of its final cost) that did the task, the runs that failed, and of those the ones
/// without any contact.
struct Outcome {
  const Run* base{nullptr};
  const Run* fastest{nullptr};
  std::vector<const Run*> failed;
  std::vector<const Run*> no_contact;
};

/// Sorts an example's runs by outcome; `sigma0` is the example's own sigma.
Outcome Classify(const std::vector<Run>& runs, double sigma0) {
  Outcome outcome;
  for (const Run& r : runs) {
    if (std::abs(r.sigma - sigma0) < 1e-12) outcome.base = &r;
    if (!r.task.success) {
      outcome.failed.push_back(&r);
    } else if (outcome.fastest == nullptr ||
               ConvergedWithin(r.solve.summary, 0.01).seconds <
                   ConvergedWithin(outcome.fastest->solve.summary, 0.01).seconds) {
      outcome.fastest = &r;
    }
  }
  for (const Run* r : outcome.failed) {
    if (r->impulse.total < kNoContact) outcome.no_contact.push_back(r);
  }
  return outcome;
}

/// The failures without contact, said once, with the contact impulse of the initial guess (how
/// much the cost "sees" the contact the solver would have to find).
std::string NoContactReading(const ExampleConfig& config, const SolverOptions& options,
                             const std::vector<const Run*>& no_contact) {
  std::ostringstream md;
  md << " σ ∈ {";
  for (size_t i = 0; i < no_contact.size(); ++i) md << (i ? ", " : "") << G(no_contact[i]->sigma);
  md << "} m fail" << (no_contact.size() == 1 ? "s" : "")
     << " without any contact: the solver stopped after ";
  for (size_t i = 0; i < no_contact.size(); ++i) {
    ProblemDefinition problem = config.problem;
    problem.contact.parameters.smoothing = no_contact[i]->sigma;
    problem.contact.force_tolerance = 0.0;  // count the forces pruning would skip, too
    Trajectory guess;
    TrajectoryOptimizer(config.model, problem, options)
        .EvalTrajectory(MakeInitialGuess(config), &guess);
    md << (i ? ", " : "") << no_contact[i]->solve.summary.iterations << " iteration"
       << (no_contact[i]->solve.summary.iterations == 1 ? "" : "s") << " ("
       << TerminationTypeName(no_contact[i]->solve.summary.termination)
       << "; normal contact impulse along the initial guess, unpruned: "
       << Sci(MeasureContactImpulse(config, problem, guess).total) << " N s)";
  }
  md << ": with that little force at the initial distance the cost has almost no slope "
        "toward contact.";
  return md.str();
}

/// The computed reading of an example's sweep: which sigmas do the task, which is fastest,
/// what fails below.
std::string Reading(const ExampleConfig& config, const SolverOptions& options,
                    const std::vector<Run>& runs, const Outcome& outcome) {
  std::ostringstream md;
  md << "Reading: ";
  if (outcome.fastest == nullptr) {
    md << "no σ of this sweep did the task.";
  } else {
    md << "the task succeeds for σ ∈ {";
    bool first = true;
    for (const Run& r : runs) {
      if (!r.task.success) continue;
      md << (first ? "" : ", ") << G(r.sigma);
      first = false;
    }
    const Convergence c = ConvergedWithin(outcome.fastest->solve.summary, 0.01);
    md << "} m; the quickest of those to come within 1% of its final cost is σ = "
       << G(outcome.fastest->sigma) << " m (" << c.iterations << " iterations, "
       << Num(c.seconds, 3) << " s; impulse at a distance "
       << ImpulseShare(outcome.fastest->impulse) << ").";
  }
  for (const Run* r : outcome.failed) {
    if (r->impulse.total < kNoContact) continue;  // said once, below
    md << " σ = " << G(r->sigma) << " m fails the task: " << r->task.name << " "
       << Num(r->task.value, 3) << ", Σh² = " << Sci(r->solve.summary.constraint_violation)
       << " after " << r->solve.summary.iterations << " iterations ("
       << TerminationTypeName(r->solve.summary.termination) << ").";
  }
  if (!outcome.no_contact.empty()) md << NoContactReading(config, options, outcome.no_contact);
  return md.str();
}

/// The summary's note on the sigmas whose solves ended without any contact.
std::string NoContactNote(const std::string& name, const std::vector<const Run*>& no_contact) {
  std::string values;
  for (size_t i = 0; i < no_contact.size(); ++i) {
    values += (i ? ", " : "") + G(no_contact[i]->sigma);
  }
  return "Smoothing (" + name + "): with σ ∈ {" + values +
         "} m the solver stopped without any contact along its solution "
         "and the task failed: too little force at a distance to pull the "
         "optimizer into contact.";
}

/// The summary's finding: the quickest sigma that did the task instead of the example's own.
Finding FastestSigmaFinding(const std::string& name, double sigma0, const Run& base,
                            const Run& fastest) {
  Finding f;
  f.knob = "σ = " + G(fastest.sigma) + " m instead of " + G(sigma0) + " m";
  f.example = name;
  const Convergence b = ConvergedWithin(base.solve.summary, 0.01);
  const Convergence q = ConvergedWithin(fastest.solve.summary, 0.01);
  f.speedup = b.seconds / q.seconds;
  f.speed = "to within 1% of the final cost: " + std::to_string(b.iterations) + " → " +
            std::to_string(q.iterations) + " iterations, " + Num(b.seconds, 3) + " → " +
            Num(q.seconds, 3) + " s";
  f.accuracy = "impulse at a distance " + ImpulseShare(base.impulse) + " → " +
               ImpulseShare(fastest.impulse) + "; " + base.task.name + " " +
               Num(base.task.value, 3) + " → " + Num(fastest.task.value, 3);
  f.free = false;
  return f;
}

/// Writes the law's normal force against the distance (cm), a column per sigma, to `path`.
void WriteLawData(const std::string& path, ContactParameters law,
                  const std::vector<double>& sigmas) {
  std::ofstream out(path);
  for (int i = 0; i <= 200; ++i) {
    const double phi = -0.01 + 0.1 * i / 200.0;
    out << 100.0 * phi;
    for (double sigma : sigmas) {
      law.smoothing = sigma;
      out << ','
          << CalcContactForce(law, phi, 0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()).fn;
    }
    out << '\n';
  }
}

/// The figure (the law's force against the distance; per example, the time to converge and the
/// impulse at a distance against sigma) and its Markdown link ("" when gnuplot fails).
std::string Figure(const Context& context, const ContactParameters& law,
                   const std::vector<double>& sigmas, const std::vector<std::string>& examples,
                   const std::map<std::string, std::vector<Run>>& runs) {
  const std::string law_data = context.data_dir + "/smoothing_law.csv";
  WriteLawData(law_data, law, sigmas);
  std::ostringstream gp;
  const std::string png = context.figure_dir + "/tradeoffs_smoothing.png";
  gp << GnuplotHeader(png, 1500, 470) << "set multiplot layout 1,3\n"
     << "set title \"normal force at rest, k = " << law.stiffness << " N/m\"\n"
     << "set logscale y\nset format y \"10^{%T}\"\nset yrange [1e-10:10]\n"
     << "set xlabel \"signed distance φ (cm)\"\nset ylabel \"f_n (N)\"\nset key bottom left\n"
     << "plot ";
  for (size_t i = 0; i < sigmas.size(); ++i) {
    gp << (i ? ", " : "") << GnuplotQuote(law_data) << " using 1:" << i + 2
       << " with lines lw 2 title \"σ = " << sigmas[i] << " m\"";
  }
  gp << "\nunset yrange\nset logscale x\nset format x \"%g\"\n"
     << "set xlabel \"smoothing σ (m)\"\n";
  for (const std::string& name : examples) {
    std::ofstream data(context.data_dir + "/smoothing_" + name + ".csv");
    for (const Run& r : runs.at(name)) {
      data << r.sigma << ',' << ConvergedWithin(r.solve.summary, 0.01).seconds << ','
           << r.solve.summary.iterations << ',' << 100.0 * AtDistanceShare(r.impulse) << ','
           << (r.task.success ? 1 : 0) << '\n';
    }
  }
  gp << "set title \"time to within 1% of the final cost (filled: task done, open: failed)\"\n"
     << "set ylabel \"s\"\nset format y \"%g\"\nset key bottom right\nplot ";
  const char* colors[] = {"#1b9e77", "#d95f02", "#7570b3"};
  for (size_t i = 0; i < examples.size(); ++i) {
    const std::string file = GnuplotQuote(context.data_dir + "/smoothing_" + examples[i] + ".csv");
    gp << (i ? ", " : "") << file << " using 1:2 with lines lw 2 lc rgb \"" << colors[i % 3]
       << "\" title \"" << examples[i] << "\", " << file
       << " using 1:($5 > 0 ? $2 : NaN) with points pt 7 ps 1.5 lc rgb \"" << colors[i % 3]
       << "\" notitle, " << file << " using 1:($5 > 0 ? NaN : $2) with points pt 6 ps 1.5 "
       << "lc rgb \"" << colors[i % 3] << "\" notitle";
  }
  gp << "\nset title \"share of the contact impulse at a distance (φ > 0)\"\n"
     << "set ylabel \"%\"\nset format y \"%g\"\nset key bottom right\nplot ";
  for (size_t i = 0; i < examples.size(); ++i) {
    gp << (i ? ", " : "") << GnuplotQuote(context.data_dir + "/smoothing_" + examples[i] + ".csv")
       << " using 1:4 with linespoints lw 2 pt 7 lc rgb \"" << colors[i % 3] << "\" title \""
       << examples[i] << "\"";
  }
  gp << "\nunset multiplot\n";
  if (!RunGnuplot(context.data_dir, "smoothing", gp.str())) return "";
  return "![Force at a distance, solve time and impulse at a distance vs σ](" +
         context.figure_link_prefix + "tradeoffs_smoothing.png)\n\n";
}

}  // namespace

StudyResult RunSmoothingStudy(const Context& context) {
  StudyResult result;
  result.id = "smoothing";
  result.title = "Smoothing σ: force at a distance vs convergence";
  const std::vector<double> sigmas =
      context.quick ? std::vector<double>{0.002, 0.01, 0.05}
                    : std::vector<double>{0.001, 0.002, 0.005, 0.01, 0.02, 0.05};
  const std::vector<std::string> examples = context.quick
                                                ? std::vector<std::string>{"spinner"}
                                                : std::vector<std::string>{"spinner", "hopper"};
  std::ostringstream md;
  // The law with the spinner's stiffness and pruning tolerance.
  const ExampleConfig spinner = LoadExample(context, "spinner");
  md << LawSection(spinner.problem.contact.parameters, spinner.problem.contact.force_tolerance,
                   sigmas);

  // Solves with the example's own settings, sigma replaced.
  std::map<std::string, std::vector<Run>> runs;
  for (const std::string& name : examples) {
    const ExampleConfig config = name == "spinner" ? spinner : LoadExample(context, name);
    SolverOptions options = config.solver;
    options.num_threads = context.threads;
    if (context.quick) options.max_iterations = 60;
    runs[name] = SolveSigmas(context, config, options, sigmas);
    md << ExampleTable(name, config, options, runs[name]);

    const double sigma0 = config.problem.contact.parameters.smoothing;
    const Outcome outcome = Classify(runs[name], sigma0);
    md << Reading(config, options, runs[name], outcome);
    if (!outcome.no_contact.empty()) {
      result.notes.push_back(NoContactNote(name, outcome.no_contact));
    }
    if (outcome.base != nullptr && outcome.fastest != nullptr && outcome.fastest != outcome.base) {
      result.findings.push_back(FastestSigmaFinding(name, sigma0, *outcome.base, *outcome.fastest));
    }
    md << "\n\n";
  }
  if (context.gnuplot) {
    md << Figure(context, spinner.problem.contact.parameters, sigmas, examples, runs);
  }
  result.markdown = md.str();
  return result;
}

}  // namespace idto::tradeoffs
