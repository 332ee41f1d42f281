// idto-run: solves the trajectory optimization problem of an example configuration (YAML) and
// reports the result.
//
//   idto-run CONFIG.yaml|NAME [--max-iterations N] [--threads N]
//            [--constraints none|penalty|lagrange] [--derivatives analytic|forward|central]
//            [--mpc [--real-time] [--keep-workers-awake] [--realtime-priority P]]
//            [--summary-json FILE]
//            [--trajectory-csv FILE] [--stats-csv FILE] [--html FILE] [--quiet]
//
// NAME is an example's name: examples/NAME/NAME.yaml under $IDTO_SHARE_DIR, the source tree (for
// programs run from the build tree) or <bin>/../share/idto (the install tree).
//
// The initial guess is the configuration's `problem.initial_guess` (default: a linear
// interpolation from q_init to the last nominal configuration, quaternions slerped).
//
// Exit codes: 0 the solve finished (whatever its termination type: see the summary), 1 an error
// (bad configuration file, invalid options, unwritable output, a plant that is not available),
// 2 bad command-line arguments.
//
// --mpc runs the example in closed loop (the config's `mpc:` section, docs/config.md): the
// real-time-iteration controller re-plans at the control rate against a plant (MuJoCo when
// available, else the built-in stiff-contact plant), with the latency model of
// idto::mpc::RunClosedLoop; the JSON summary gains an "mpc" object (solve-time statistics,
// fraction of steps on time, the task measured on the closed-loop trajectory).

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/command_line.hpp"
#include "idto/config/config.hpp"
#include "idto/config/mpc_config.hpp"
#include "idto/core/csv.hpp"
#include "idto/idto.hpp"
#include "idto/mpc/closed_loop.hpp"
#include "idto/sim/plant.hpp"
#include "idto/solver/trajectory_optimizer.hpp"
#include "idto/viz/html_animation.hpp"
#include "idto_build_paths.hpp"
#include "run/json_writer.hpp"
#include "run/metrics.hpp"
#include "run/metrics_closed_loop.hpp"
#include "run/outputs.hpp"

namespace {

using idto::ConstraintMethod;
using idto::DerivativeMethod;
using idto::ExampleConfig;
using idto::IterationSummary;
using idto::SolverSummary;
using idto::Trajectory;
using idto::examples::JsonWriter;

using idto::examples::kExitOk;
using idto::examples::UsageError;

const char kUsage[] =
    "usage: idto-run CONFIG.yaml|NAME [options]\n"
    "\n"
    "Solves an example's trajectory optimization problem and reports the result.\n"
    "NAME is an example name (e.g. pendulum, acrobot): examples/NAME/NAME.yaml in\n"
    "$IDTO_SHARE_DIR, the source tree or <bin>/../share/idto.\n"
    "\n"
    "options:\n"
    "  --max-iterations N                 override solver.max_iterations (N >= 0; not with --mpc)\n"
    "  --threads N                        override solver.num_threads (N >= 1)\n"
    "  --constraints none|penalty|lagrange  override solver.constraint_method\n"
    "  --derivatives analytic|forward|central\n"
    "                                     override solver.derivative_method\n"
    "  --mpc                              closed-loop MPC against a plant (the mpc: section)\n"
    "  --real-time                        with --mpc: pace the loop to the wall clock\n"
    "                                     (mpc.real_time), as a controller on a robot runs\n"
    "  --keep-workers-awake               with --mpc: solver threads wait awake between\n"
    "                                     re-plans (mpc.keep_workers_awake)\n"
    "  --realtime-priority P              with --mpc: the loop and solver threads run under\n"
    "                                     SCHED_FIFO at priority P in [1, 99] (0: off;\n"
    "                                     mpc.realtime_priority); needs root or CAP_SYS_NICE\n"
    "  --summary-json FILE                write the JSON summary to FILE\n"
    "  --trajectory-csv FILE              write t, q, v, tau per time step to FILE\n"
    "  --stats-csv FILE                   write the per-iteration statistics to FILE\n"
    "  --html FILE                        write a 3D viewer page of the plan (or, with --mpc,\n"
    "                                     the closed-loop motion with the plan as a ghost)\n"
    "  --quiet                            no iteration table\n"
    "  -h, --help                         this message\n"
    "\n"
    "exit codes: 0 solved (any termination), 1 error, 2 bad arguments\n";

struct Arguments {
  std::string config;
  std::optional<int> max_iterations;
  std::optional<int> threads;
  std::optional<ConstraintMethod> constraints;
  std::optional<DerivativeMethod> derivatives;
  bool mpc{false};
  bool real_time{false};
  bool keep_workers_awake{false};
  std::optional<int> realtime_priority;
  bool quiet{false};
  bool help{false};
  std::string summary_json;
  std::string trajectory_csv;
  std::string stats_csv;
  std::string html;
};

bool ParseInt(const std::string& text, int* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  const long parsed = std::strtol(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size() || parsed < -1000000000L || parsed > 1000000000L) {
    return false;
  }
  *value = static_cast<int>(parsed);
  return true;
}

/// The value of --constraints.
ConstraintMethod ParseConstraintMethod(const std::string& text) {
  if (text == "none") return ConstraintMethod::kNone;
  if (text == "penalty") return ConstraintMethod::kPenalty;
  if (text == "lagrange") return ConstraintMethod::kLagrangeMultipliers;
  throw UsageError{"--constraints is '" + text + "'; expected none, penalty or lagrange"};
}

/// The value of --derivatives.
DerivativeMethod ParseDerivativeMethod(const std::string& text) {
  if (text == "analytic") return DerivativeMethod::kAnalytic;
  if (text == "forward") return DerivativeMethod::kForwardDifferences;
  if (text == "central") return DerivativeMethod::kCentralDifferences;
  throw UsageError{"--derivatives is '" + text + "'; expected analytic, forward or central"};
}

Arguments ParseArguments(int argc, char** argv) {
  Arguments args;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    std::string value;
    bool has_inline_value = false;
    if (arg.rfind("--", 0) == 0) {
      const auto eq = arg.find('=');
      if (eq != std::string::npos) {
        value = arg.substr(eq + 1);
        arg = arg.substr(0, eq);
        has_inline_value = true;
      }
    }
    const auto take_value = [&]() -> std::string {
      if (has_inline_value) return value;
      if (i + 1 >= argc) throw UsageError{arg + " needs a value"};
      return argv[++i];
    };
    const auto take_int = [&](int min_value) {
      const std::string text = take_value();
      int n = 0;
      if (!ParseInt(text, &n) || n < min_value) {
        throw UsageError{arg + " is '" + text +
                         "'; expected an integer >= " + std::to_string(min_value)};
      }
      return n;
    };
    const auto no_value = [&]() {
      if (has_inline_value) throw UsageError{arg + " takes no value"};
    };
    if (arg == "-h" || arg == "--help") {
      no_value();
      args.help = true;
    } else if (arg == "--max-iterations") {
      args.max_iterations = take_int(0);
    } else if (arg == "--threads") {
      args.threads = take_int(1);
    } else if (arg == "--constraints") {
      args.constraints = ParseConstraintMethod(take_value());
    } else if (arg == "--derivatives") {
      args.derivatives = ParseDerivativeMethod(take_value());
    } else if (arg == "--mpc") {
      no_value();
      args.mpc = true;
    } else if (arg == "--real-time") {
      no_value();
      args.real_time = true;
    } else if (arg == "--keep-workers-awake") {
      no_value();
      args.keep_workers_awake = true;
    } else if (arg == "--realtime-priority") {
      args.realtime_priority = take_int(0);
      if (*args.realtime_priority > idto::mpc::kMaxRealtimePriority) {
        throw UsageError{"--realtime-priority is " + std::to_string(*args.realtime_priority) +
                         "; expected 0 (off) or a SCHED_FIFO priority in [1, " +
                         std::to_string(idto::mpc::kMaxRealtimePriority) + "]"};
      }
    } else if (arg == "--quiet") {
      no_value();
      args.quiet = true;
    } else if (arg == "--summary-json") {
      args.summary_json = take_value();
    } else if (arg == "--trajectory-csv") {
      args.trajectory_csv = take_value();
    } else if (arg == "--stats-csv") {
      args.stats_csv = take_value();
    } else if (arg == "--html") {
      args.html = take_value();
    } else if (arg.size() > 1 && arg[0] == '-') {
      throw UsageError{"unknown option " + arg};
    } else {
      positional.push_back(arg);
    }
  }
  if (args.help) return args;
  if (args.real_time && !args.mpc) throw UsageError{"--real-time needs --mpc"};
  // The closed loop counts its iterations with mpc.initial_iterations and
  // mpc.iterations_per_step; a flag that silently did nothing would mislead.
  if (args.max_iterations && args.mpc) {
    throw UsageError{
        "--max-iterations does not apply with --mpc (set mpc.initial_iterations, the cold "
        "start's, and mpc.iterations_per_step, each re-plan's, in the file)"};
  }
  if (args.keep_workers_awake && !args.mpc) throw UsageError{"--keep-workers-awake needs --mpc"};
  if (args.realtime_priority && !args.mpc) throw UsageError{"--realtime-priority needs --mpc"};
  if (positional.empty()) throw UsageError{"missing CONFIG.yaml or example NAME"};
  if (positional.size() > 1) throw UsageError{"unexpected argument " + positional[1]};
  args.config = positional[0];
  return args;
}

std::string ExecutablePath(const char* argv0) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) return self.string();
  return argv0 != nullptr ? std::string(argv0) : std::string();
}

std::string StepTypeName(idto::DoglegStep step) {
  switch (step) {
    case idto::DoglegStep::kNewton:
      return "newton";
    case idto::DoglegStep::kCauchy:
      return "cauchy";
    case idto::DoglegStep::kDogleg:
      return "dogleg";
    case idto::DoglegStep::kNone:
      return "none";
  }
  return "unknown";
}

// ---------------------------------------------------------------------------- iteration table

void PrintTableHeader(std::ostream& out) {
  char line[256];
  std::snprintf(line, sizeof(line), "%5s %13s %13s %10s %10s %10s %10s %4s %7s %10s %9s\n", "iter",
                "cost", "merit", "|g|", "|p|", "radius", "rho", "acc", "step", "viol", "ms");
  out << line;
}

void PrintTableRow(std::ostream& out, const IterationSummary& it) {
  char line[256];
  std::snprintf(line, sizeof(line),
                "%5d %13.6e %13.6e %10.3e %10.3e %10.3e %10.3e %4s %7s %10.3e %9.3f\n",
                it.iteration, it.cost, it.merit, it.gradient_norm, it.step_norm, it.trust_radius,
                it.ratio, it.accepted ? "yes" : (it.growth_guard ? "grd" : "no"),
                StepTypeName(it.step_type).c_str(), it.constraint_violation, 1e3 * it.time_total);
  out << line;
  out.flush();
}

// ---------------------------------------------------------------------------- JSON

/// The task measures as the members of a JSON object (the caller opens and closes it).
void WriteMetrics(const idto::examples::TaskResult& task, JsonWriter* json) {
  for (const idto::examples::Metric& metric : task.metrics) {
    json->Key(metric.name);
    if (metric.is_array || metric.values.size() != 1) {
      json->NumberArray(metric.values);
    } else {
      json->Number(metric.values[0]);
    }
  }
}

/// The summary keys common to both modes (design.md §5b): example, file, termination,
/// iterations, costs, violation, times. In --mpc mode they describe the initial (cold) solve.
void WriteSolveFields(const ExampleConfig& config, const std::string& config_path,
                      const SolverSummary& summary, JsonWriter* json) {
  json->Key("example");
  json->String(config.name);
  json->Key("config_file");
  json->String(config_path);
  json->Key("termination");
  json->String(idto::TerminationTypeName(summary.termination));
  json->Key("message");
  json->String(summary.message);
  json->Key("iterations");
  json->Int(summary.iterations);
  json->Key("initial_cost");
  json->Number(summary.initial_cost);
  json->Key("final_cost");
  json->Number(summary.final_cost);
  json->Key("constraint_violation");
  json->Number(summary.constraint_violation);
  json->Key("solve_time_s");
  json->Number(summary.solve_time);
  json->Key("mean_iteration_time_s");
  json->Number(summary.mean_iteration_time());
}

std::string MakeSummaryJson(const ExampleConfig& config, const std::string& config_path,
                            const idto::SolverOptions& options, const SolverSummary& summary,
                            const Trajectory& solution, const idto::examples::TaskResult& task) {
  JsonWriter json;
  json.BeginObject();
  WriteSolveFields(config, config_path, summary, &json);
  json.Key("constraint_method");
  json.String(ConstraintMethodName(options.constraint_method));
  json.Key("num_threads");
  json.Int(options.num_threads);
  json.Key("max_iterations");
  json.Int(options.max_iterations);
  json.Key("time_step");
  json.Number(config.problem.time_step);
  json.Key("num_steps");
  json.Int(config.problem.num_steps);
  json.Key("nq");
  json.Int(config.model.nq());
  json.Key("nv");
  json.Int(config.model.nv());
  json.Key("q_final");
  json.NumberArray(solution.q.back());
  json.Key("v_final");
  json.NumberArray(solution.v.back());
  json.Key("metrics");
  json.BeginObject();
  WriteMetrics(task, &json);
  json.EndObject();
  json.Key("task_success");
  json.Bool(task.task_success);
  json.Key("task_success_criterion");
  json.String(task.criterion);
  json.Key("log");
  json.BeginArray();
  for (const IterationSummary& it : summary.log) {
    json.BeginObject();
    json.Key("iteration");
    json.Int(it.iteration);
    json.Key("cost");
    json.Number(it.cost);
    json.Key("merit");
    json.Number(it.merit);
    json.Key("gradient_norm");
    json.Number(it.gradient_norm);
    json.Key("step_norm");
    json.Number(it.step_norm);
    json.Key("scaled_step_norm");
    json.Number(it.scaled_step_norm);
    json.Key("trust_radius");
    json.Number(it.trust_radius);
    json.Key("ratio");
    json.Number(it.ratio);
    json.Key("accepted");
    json.Bool(it.accepted);
    json.Key("growth_guard");
    json.Bool(it.growth_guard);
    json.Key("step_type");
    json.String(StepTypeName(it.step_type));
    json.Key("constraint_violation");
    json.Number(it.constraint_violation);
    json.Key("trial_cost");
    json.Number(it.trial_cost);
    json.Key("time_s");
    json.Number(it.time_total);
    json.Key("time_derivatives_s");
    json.Number(it.time_derivatives);
    json.Key("time_cost_s");
    json.Number(it.time_cost);
    json.Key("time_hessian_s");
    json.Number(it.time_hessian);
    json.Key("time_factorization_s");
    json.Number(it.time_factorization);
    json.Key("time_multipliers_s");
    json.Number(it.time_multipliers);
    json.Key("time_contact_s");  // within derivatives and cost; CPU time summed over threads
    json.Number(it.time_contact);
    json.EndObject();
  }
  json.EndArray();
  json.EndObject();
  return json.str();
}

// ---------------------------------------------------------------------------- CSV

std::string MakeTrajectoryCsv(const ExampleConfig& config, const Trajectory& solution) {
  const idto::Model& model = config.model;
  std::ostringstream out;
  out << "t";
  for (const std::string& label : idto::examples::CoordinateLabels(model, true))
    out << ',' << idto::CsvField("q:" + label);
  const std::vector<std::string> velocity_labels = idto::examples::CoordinateLabels(model, false);
  for (const std::string& label : velocity_labels) out << ',' << idto::CsvField("v:" + label);
  for (const std::string& label : velocity_labels) out << ',' << idto::CsvField("tau:" + label);
  out << "\n";
  const auto write = [&out](double x) { out << ',' << JsonWriter::FormatNumber(x); };
  for (std::size_t k = 0; k < solution.q.size(); ++k) {
    out << JsonWriter::FormatNumber(static_cast<double>(k) * config.problem.time_step);
    for (int i = 0; i < model.nq(); ++i) write(solution.q[k](i));
    for (int i = 0; i < model.nv(); ++i) write(k < solution.v.size() ? solution.v[k](i) : 0.0);
    for (int i = 0; i < model.nv(); ++i) {
      write(k < solution.tau.size() && solution.tau[k].size() == model.nv() ? solution.tau[k](i)
                                                                            : 0.0);
    }
    out << "\n";
  }
  return out.str();
}

void WriteFile(const std::string& path, const std::string& text, const char* what) {
  std::ofstream out(path);
  if (out) out << text;
  if (!out) {
    throw idto::FileError(path, "", path + ": cannot write the " + std::string(what));
  }
}

std::string FormatVector(const Eigen::VectorXd& x) {
  std::ostringstream out;
  out << "[";
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    out << (i ? ", " : "") << JsonWriter::FormatNumber(x(i));
  }
  out << "]";
  return out.str();
}

/// Prints the task measures and task_success (the result section of both modes).
void PrintTask(const idto::examples::TaskResult& task) {
  for (const idto::examples::Metric& metric : task.metrics) {
    std::cout << "  " << metric.name << ": ";
    if (metric.is_array || metric.values.size() != 1) {
      std::cout << FormatVector(Eigen::Map<const Eigen::VectorXd>(
          metric.values.data(), static_cast<Eigen::Index>(metric.values.size())));
    } else {
      std::cout << JsonWriter::FormatNumber(metric.values[0]);
    }
    std::cout << "\n";
  }
  std::cout << "  task_success: " << (task.task_success ? "true" : "false") << " ("
            << task.criterion << ")\n";
}

/// The viewer page (--html): the frames, with the problem's contact forces.
void WriteHtml(const Arguments& args, const ExampleConfig& config,
               const idto::ProblemDefinition& problem,
               const std::vector<idto::AnimationFrame>& frames) {
  idto::HtmlAnimationOptions html;
  html.title = "idto: " + config.name + (args.mpc ? " (closed loop; ghost: the plan)" : "");
  if (problem.enable_contact) html.contact = problem.contact;
  idto::WriteHtmlAnimation(config.model, frames, html, args.html);
  std::cout << "wrote " << args.html << "\n";
}

/// Loads the configuration; what its URDF files hold that idto ignores by design (UrdfWarning)
/// goes to stderr.
ExampleConfig LoadConfig(const std::string& config_path,
                         const std::vector<std::string>& share_dirs) {
  ExampleConfig config = idto::LoadExampleConfig(config_path, share_dirs);
  for (const idto::UrdfWarning& w : config.urdf_warnings) {
    std::cerr << "idto-run: warning: " << w.ToString() << "\n";
  }
  return config;
}

/// The output files of the command line, with their flags.
std::vector<std::pair<std::string, std::string>> OutputFiles(const Arguments& args) {
  return {{"--summary-json", args.summary_json},
          {"--trajectory-csv", args.trajectory_csv},
          {"--stats-csv", args.stats_csv},
          {"--html", args.html}};
}

int Run(const Arguments& args, const char* argv0) {
  std::vector<std::string> share_dirs =
      idto::DefaultShareDirs(IDTO_SOURCE_SHARE_DIR, ExecutablePath(argv0));
  share_dirs.push_back(IDTO_INSTALL_SHARE_DIR);
  const std::string config_path = idto::FindExampleConfig(args.config, share_dirs);
  ExampleConfig config = LoadConfig(config_path, share_dirs);

  idto::SolverOptions options = config.solver;
  if (args.max_iterations) options.max_iterations = *args.max_iterations;
  if (args.threads) options.num_threads = *args.threads;
  if (args.constraints) options.constraint_method = *args.constraints;
  if (args.derivatives) options.derivative_method = *args.derivatives;
  options.verbosity = 0;  // the table below replaces the solver's own printing
  std::string why;
  if (!options.IsValid(&why)) {
    throw idto::InvalidArgument("idto-run: invalid solver options: " + why);
  }

  // Fail before solving on an output that cannot be written or would clobber another file.
  idto::examples::CheckOutputPaths(OutputFiles(args), config_path, config);
  for (const std::string& file : {args.summary_json, args.trajectory_csv, args.stats_csv}) {
    if (!file.empty()) WriteFile(file, "", "output file");
  }
  if (!args.html.empty()) idto::CheckHtmlAnimationPath(args.html);

  const idto::ProblemDefinition& problem = config.problem;
  std::cout << "idto-run " << IDTO_VERSION_STRING << ": " << config.name << " (" << config_path
            << ")\n";
  if (!config.description.empty()) std::cout << "  " << config.description << "\n";
  std::cout << "  model '" << config.model.name() << "': nq = " << config.model.nq()
            << ", nv = " << config.model.nv() << "; N = " << problem.num_steps
            << ", dt = " << problem.time_step
            << " s, horizon = " << problem.num_steps * problem.time_step << " s\n"
            << "  constraints: " << ConstraintMethodName(options.constraint_method)
            << ", threads: " << options.num_threads
            << ", max iterations: " << options.max_iterations
            << ", initial guess: " << idto::InitialGuessTypeName(config.initial_guess) << "\n";

  idto::TrajectoryOptimizer optimizer(config.model, problem, options);
  if (!args.quiet) {
    PrintTableHeader(std::cout);
    optimizer.AddCallback([](const IterationSummary& it) {
      PrintTableRow(std::cout, it);
      return idto::CallbackReturn::kContinue;
    });
  }
  const std::vector<Eigen::VectorXd> guess = idto::MakeInitialGuess(config);
  Trajectory solution;
  const SolverSummary summary = optimizer.Solve(guess, &solution);
  // Overflow at the guess: nothing to write (JSON has no inf); refuse, naming the key.
  if (!std::isfinite(summary.initial_cost)) throw idto::InvalidArgument(summary.message);
  const idto::examples::TaskResult task = idto::examples::EvaluateTask(config, solution);

  std::cout << summary.BriefReport() << "\n";
  std::cout << "result:\n";
  std::cout << "  termination: " << idto::TerminationTypeName(summary.termination);
  if (!summary.message.empty()) std::cout << " (" << summary.message << ")";
  std::cout << "\n  iterations: " << summary.iterations << "\n"
            << "  cost: " << JsonWriter::FormatNumber(summary.initial_cost) << " -> "
            << JsonWriter::FormatNumber(summary.final_cost) << "\n"
            << "  constraint violation: " << JsonWriter::FormatNumber(summary.constraint_violation)
            << "\n"
            << "  solve time: " << summary.solve_time << " s (mean "
            << 1e3 * summary.mean_iteration_time() << " ms per iteration)\n"
            << "  q_N: " << FormatVector(solution.q.back()) << "\n";
  PrintTask(task);

  if (!args.summary_json.empty()) {
    WriteFile(args.summary_json,
              MakeSummaryJson(config, config_path, options, summary, solution, task),
              "JSON summary");
    std::cout << "wrote " << args.summary_json << "\n";
  }
  if (!args.trajectory_csv.empty()) {
    WriteFile(args.trajectory_csv, MakeTrajectoryCsv(config, solution), "trajectory CSV");
    std::cout << "wrote " << args.trajectory_csv << "\n";
  }
  if (!args.stats_csv.empty()) {
    WriteFile(args.stats_csv, summary.ToCsv(), "stats CSV");
    std::cout << "wrote " << args.stats_csv << "\n";
  }
  if (!args.html.empty()) {
    WriteHtml(args, config, problem,
              idto::MakeAnimationFrames(solution.q, solution.v, problem.time_step));
  }
  return kExitOk;
}

// ---------------------------------------------------------------------------- MPC

/// The JSON summary of a closed-loop run (idto-run --mpc --summary-json).
void WriteMpcSummaryJson(const Arguments& args, const ExampleConfig& config,
                         const std::string& config_path, const idto::MpcConfig& mpc,
                         const SolverSummary& first, const idto::mpc::ClosedLoopLog& log,
                         const Eigen::VectorXd& q_final, const idto::examples::TaskResult& task) {
  JsonWriter json;
  json.BeginObject();
  WriteSolveFields(config, config_path, first, &json);
  json.Key("q_final");
  json.NumberArray(q_final);
  json.Key("mpc");
  json.BeginObject();
  json.Key("plant");
  json.String(mpc.plant);
  json.Key("control_rate_hz");
  json.Number(mpc.controller.control_rate);
  json.Key("iterations_per_step");
  json.Int(mpc.controller.iterations_per_step);
  json.Key("duration_s");
  json.Number(mpc.closed_loop.duration);
  json.Key("num_replans");
  json.Int(static_cast<long long>(log.solve_time.size()));
  json.Key("rejected_plans");
  json.Int(log.num_rejected_plans);
  json.Key("mean_solve_time_s");
  json.Number(log.mean_solve_time());
  json.Key("p95_solve_time_s");
  json.Number(log.percentile_solve_time(95));
  json.Key("max_solve_time_s");
  json.Number(log.max_solve_time());
  json.Key("fraction_on_time");
  json.Number(log.fraction_on_time());
  json.Key("plant_failure");
  json.String(log.failure);
  json.Key("realtime_priority");
  json.Int(mpc.closed_loop.realtime_priority);
  json.Key("realtime_error");
  json.String(log.realtime_error);
  json.Key("metrics");
  json.BeginObject();
  WriteMetrics(task, &json);
  json.EndObject();
  json.Key("task_success");
  json.Bool(task.task_success);
  json.EndObject();
  json.Key("metrics");
  json.BeginObject();
  json.EndObject();
  json.Key("task_success");
  json.Bool(task.task_success);
  json.Key("log");
  json.BeginArray();
  json.EndArray();
  json.EndObject();
  WriteFile(args.summary_json, json.str(), "JSON summary");
  std::cout << "wrote " << args.summary_json << "\n";
}

int RunMpc(const Arguments& args, const char* argv0) {
  std::vector<std::string> share_dirs =
      idto::DefaultShareDirs(IDTO_SOURCE_SHARE_DIR, ExecutablePath(argv0));
  share_dirs.push_back(IDTO_INSTALL_SHARE_DIR);
  const std::string config_path = idto::FindExampleConfig(args.config, share_dirs);
  ExampleConfig config = LoadConfig(config_path, share_dirs);
  idto::MpcConfig mpc = idto::ParseMpcConfig(config);
  if (args.real_time) mpc.closed_loop.real_time = true;
  if (args.keep_workers_awake) mpc.closed_loop.keep_workers_awake = true;
  if (args.realtime_priority) mpc.closed_loop.realtime_priority = *args.realtime_priority;
  idto::SolverOptions options = config.mpc_solver.value_or(config.solver);
  if (args.threads) options.num_threads = *args.threads;
  if (args.constraints) options.constraint_method = *args.constraints;
  if (args.derivatives) options.derivative_method = *args.derivatives;
  options.verbosity = 0;
  idto::examples::CheckOutputPaths(OutputFiles(args), config_path, config);
  for (const std::string& file : {args.summary_json, args.trajectory_csv, args.stats_csv}) {
    if (!file.empty()) WriteFile(file, "", "output file");
  }
  if (!args.html.empty()) idto::CheckHtmlAnimationPath(args.html);
  const idto::Model& model = config.model;
  std::cout << "idto-run " << IDTO_VERSION_STRING << ": " << config.name << " --mpc ("
            << config_path << ")\n"
            << "  plant: " << mpc.plant << ", control rate " << mpc.controller.control_rate
            << " Hz, " << mpc.controller.iterations_per_step << " iteration(s) per step, "
            << mpc.closed_loop.duration << " s" << (mpc.closed_loop.real_time ? " (real time)" : "")
            << (mpc.closed_loop.keep_workers_awake ? " (workers awake)" : "")
            << (mpc.closed_loop.realtime_priority > 0
                    ? " (SCHED_FIFO " + std::to_string(mpc.closed_loop.realtime_priority) + ")"
                    : "")
            << ", threads " << options.num_threads << "\n";
  std::unique_ptr<idto::sim::Plant> plant = mpc.plant == "mujoco"
                                                ? idto::sim::MakeMujocoPlant(model, mpc.mujoco)
                                                : idto::sim::MakeBuiltinPlant(model, mpc.builtin);
  // The controller's problem (mpc.problem overrides, if any) also gives the plant's start.
  const idto::ProblemDefinition& problem = idto::ControllerProblem(config);
  plant->Reset(problem.q_init, problem.v_init);
  // SCHED_FIFO from before the first solve, so that the solver's worker threads start under it
  // (measured steadier beside a busy process than workers switched at the loop's start).
  idto::mpc::RealtimeScheduling realtime(mpc.closed_loop.realtime_priority);
  idto::mpc::Controller controller(idto::ControllerModel(config), problem, options, mpc.controller);
  const SolverSummary first =
      controller.Initialize(idto::ControllerInitialGuess(config), mpc.initial_iterations);
  std::cout << "  initial plan: " << first.BriefReport() << "\n";
  const idto::mpc::ClosedLoopLog log =
      idto::mpc::RunClosedLoop(model, mpc.closed_loop, &controller, plant.get());
  const idto::examples::TaskResult task = idto::examples::EvaluateClosedLoopTask(config, log);
  if (!log.realtime_error.empty()) {
    std::cout << "  warning: real-time scheduling not granted: " << log.realtime_error << "\n";
  }
  if (!log.failure.empty()) {
    std::cout << "  plant failed at t = " << log.failure_time << " s: " << log.failure << "\n";
  }
  std::cout << "result (closed loop):\n"
            << "  re-plans: " << log.solve_time.size() << ", rejected: " << log.num_rejected_plans
            << "\n"
            << "  solve time: mean " << 1e3 * log.mean_solve_time() << " ms, p95 "
            << 1e3 * log.percentile_solve_time(95) << " ms, max " << 1e3 * log.max_solve_time()
            << " ms; period " << 1e3 * log.control_period << " ms; on time "
            << 100.0 * log.fraction_on_time() << " %\n"
            << "  q_final: " << FormatVector(plant->q()) << "\n";
  PrintTask(task);
  if (!args.summary_json.empty()) {
    WriteMpcSummaryJson(args, config, config_path, mpc, first, log, plant->q(), task);
  }
  if (!args.trajectory_csv.empty()) {
    WriteFile(args.trajectory_csv, log.ToCsv(model), "closed-loop trajectory CSV");
    std::cout << "wrote " << args.trajectory_csv << "\n";
  }
  if (!args.stats_csv.empty()) {
    std::ostringstream out;
    out << "replan_time,solve_time,status\n";
    for (size_t i = 0; i < log.solve_time.size(); ++i) {
      out << log.replan_time[i] << "," << log.solve_time[i] << "," << log.solve_status[i] << "\n";
    }
    WriteFile(args.stats_csv, out.str(), "solve-time CSV");
    std::cout << "wrote " << args.stats_csv << "\n";
  }
  if (!args.html.empty()) WriteHtml(args, config, problem, idto::MakeAnimationFrames(log));
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  return idto::examples::RunCommandLine<Arguments>(
      "idto-run", kUsage, argc, argv, ParseArguments, [&](const Arguments& args) {
        if (args.mpc) return RunMpc(args, argc > 0 ? argv[0] : nullptr);
        return Run(args, argc > 0 ? argv[0] : nullptr);
      });
}
