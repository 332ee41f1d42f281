// idto-tradeoffs: measures what each speed/accuracy knob of idto buys and costs, and writes
// docs/tradeoffs.md with its tables and the PNG figures (gnuplot) from scratch.
//
//   idto-tradeoffs [--quick] [--out DIR] [--threads N] [--only ID[,ID...]]
//
// --out DIR writes DIR/tradeoffs.md and DIR/figures/tradeoffs_<id>.png (default: the source
// tree's docs/). --quick runs smaller sweeps with fewer iterations (a smoke test, < 60 s).
// Every number in the output is measured by this run, except the paper's reference numbers,
// which are labelled as the paper's.

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "common.hpp"
#include "idto_build_paths.hpp"
#include "report.hpp"
#include "studies.hpp"

namespace {

using idto::tradeoffs::Context;
using idto::tradeoffs::Finding;
using idto::tradeoffs::StudyResult;

const char kUsage[] =
    "usage: idto-tradeoffs [--quick] [--out DIR] [--threads N] [--only ID[,ID...]]\n"
    "\n"
    "Measures idto's speed/accuracy trade-offs and writes DIR/tradeoffs.md and\n"
    "DIR/figures/tradeoffs_<id>.png (default DIR: the source tree's docs/).\n"
    "\n"
    "  --quick        smaller sweeps and fewer iterations (smoke test, < 60 s)\n"
    "  --out DIR      output folder\n"
    "  --threads N    solver threads where threads are not the swept variable (default 2)\n"
    "  --only IDS     run only these studies: sensitivity, smoothing, derivatives,\n"
    "                 constraints, pruning, scaling (comma-separated)\n";

struct Study {
  std::string id;
  std::function<StudyResult(const Context&)> run;
};

std::string ExecutablePath(const char* argv0) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(argv0 ? argv0 : "") : self.string();
}

std::string MakeTempDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "idto-tradeoffs.XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  return pattern;
}

/// The summary: knobs ranked by what they buy and what they cost, from the studies' findings.
std::string Summary(const std::vector<Finding>& findings, const std::vector<std::string>& notes) {
  using idto::tradeoffs::Num;
  using idto::tradeoffs::Table;
  using idto::tradeoffs::Times;
  std::vector<Finding> free, lossy;
  for (const Finding& f : findings) (f.free ? free : lossy).push_back(f);
  const auto by_speedup = [](const Finding& a, const Finding& b) { return a.speedup > b.speedup; };
  std::sort(free.begin(), free.end(), by_speedup);
  std::sort(lossy.begin(), lossy.end(), by_speedup);
  std::ostringstream md;
  Table table({"cheaper setting", "measured on", "speed", "accuracy given up", "speedup"});
  // Cells may quote |x|: escape the bar for the Markdown table.
  const auto cell = [](std::string text) {
    for (size_t at = text.find('|'); at != std::string::npos; at = text.find('|', at + 2)) {
      text.insert(at, "\\");
    }
    return text;
  };
  for (const auto* group : {&free, &lossy}) {
    for (const Finding& f : *group) {
      table.Row({cell(f.knob), f.example, cell(f.speed), cell(f.accuracy), Times(f.speedup)});
    }
  }
  md << "Each row is one measured comparison from the sections below: first the knobs whose "
        "answer did not change (within the threshold stated in the row), then the ones that "
        "changed it, each group by speedup (time of the accurate setting / time of the cheaper "
        "one; below 1 means the \"cheaper\" setting was in fact slower here).\n\n"
     << table.Markdown() << "\n";
  const auto best_free =
      std::find_if(free.begin(), free.end(), [](const Finding& f) { return f.speedup > 1.05; });
  if (best_free != free.end()) {
    md << "**Most speed for no accuracy:** " << best_free->knob << " (" << best_free->example
       << "): " << Times(best_free->speedup) << " faster, and " << best_free->accuracy << ".";
    int others = 0;
    for (auto it = free.begin(); it != free.end(); ++it) {
      if (it != best_free && it->speedup > 1.05) ++others;
    }
    if (others > 0) {
      md << " " << others << " other comparison" << (others > 1 ? "s" : "")
         << " in the first group also gained more than 5% without changing the answer.";
    }
    md << "\n\n";
  } else {
    md << "**No knob gained more than 5% without changing the answer** in this run.\n\n";
  }
  if (!lossy.empty()) {
    const Finding& top = lossy.front();
    md << "**Largest speedup that changes the answer:** " << top.knob << " (" << top.example
       << "): " << Times(top.speedup) << ", at the cost of: " << top.accuracy << ".\n\n";
    std::vector<const Finding*> slower;
    for (const Finding& f : lossy) {
      if (f.speedup < 0.95) slower.push_back(&f);
    }
    if (!slower.empty()) {
      md << "Settings that were *slower* as well as less accurate here (avoid them): ";
      for (size_t i = 0; i < slower.size(); ++i) {
        md << (i ? "; " : "") << slower[i]->knob << " (" << slower[i]->example << ", "
           << Times(slower[i]->speedup) << ")";
      }
      md << ".\n\n";
    }
  }
  if (!notes.empty()) {
    md << "**Other measured effects:**\n\n";
    for (const std::string& note : notes) md << "- " << note << "\n";
    md << "\n";
  }
  return md.str();
}

/// Reads the command line into `context`, `out_dir` and `only`. Returns the exit code when the
/// program should stop here: 0 after --help, 2 on a bad argument.
std::optional<int> ParseArguments(int argc, char** argv, Context* context, std::string* out_dir,
                                  std::vector<std::string>* only) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << arg << " needs a value\n" << kUsage;
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      std::cout << kUsage;
      return 0;
    } else if (arg == "--quick") {
      context->quick = true;
      context->repeats = 1;
    } else if (arg == "--out") {
      *out_dir = value();
    } else if (arg == "--threads") {
      const std::string text = value();
      context->threads = std::atoi(text.c_str());
      if (context->threads < 1) {
        std::cerr << "--threads is '" << text << "'; expected an integer >= 1\n" << kUsage;
        return 2;
      }
    } else if (arg == "--only") {
      std::stringstream list(value());
      std::string id;
      while (std::getline(list, id, ',')) only->push_back(id);
    } else {
      std::cerr << "unknown argument " << arg << "\n" << kUsage;
      return 2;
    }
  }
  return std::nullopt;
}

/// Creates `out_dir`/figures and points `context` at it, at the examples, at a fresh scratch
/// folder and at gnuplot (warning when it is missing).
void PrepareOutput(const std::string& out_dir, const char* argv0, Context* context) {
  std::filesystem::create_directories(out_dir + "/figures");
  context->figure_dir = std::filesystem::absolute(out_dir + "/figures").string();
  context->figure_link_prefix = "figures/";
  context->share_dirs = idto::DefaultShareDirs(IDTO_SOURCE_SHARE_DIR, ExecutablePath(argv0));
  context->data_dir = MakeTempDir();
  context->gnuplot = idto::tradeoffs::HaveGnuplot();
  if (!context->gnuplot) {
    std::cerr << "idto-tradeoffs: warning: gnuplot not found; writing the tables without "
                 "figures\n";
  }
}

/// The studies that ran, in order, each with its seconds and the load average when it started.
struct StudyRuns {
  std::vector<StudyResult> results;
  std::vector<double> seconds;
  std::vector<std::string> loads;
};

/// Runs the studies named in `only` (all when it is empty) in the order of `studies`, printing
/// each one's time.
StudyRuns RunStudies(const std::vector<Study>& studies, const std::vector<std::string>& only,
                     const Context& context) {
  StudyRuns runs;
  for (const Study& study : studies) {
    if (!only.empty() && std::find(only.begin(), only.end(), study.id) == only.end()) continue;
    std::cout << "idto-tradeoffs: " << study.id << " ..." << std::flush;
    const auto t0 = std::chrono::steady_clock::now();
    runs.loads.push_back(idto::tradeoffs::ReadLoadAverage());
    runs.results.push_back(study.run(context));
    runs.seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::cout << " " << idto::tradeoffs::Num(runs.seconds.back(), 3) << " s" << std::endl;
  }
  return runs;
}

/// How the whole run was produced, as the page records it.
struct RunRecord {
  std::string command;  // the command line, from "idto-tradeoffs"
  idto::tradeoffs::MachineInfo machine;
  double total_seconds{0.0};
  std::string load_end;  // the load average after the last study
};

/// The page's title and introduction: what it measures and how this run produced it.
std::string Introduction(const RunRecord& run, const Context& context) {
  const idto::tradeoffs::MachineInfo& machine = run.machine;
  std::ostringstream md;
  md << "# Speed/accuracy trade-offs\n\n"
     << "<!-- Generated by idto-tradeoffs (benchmarks/tradeoffs/); do not edit by hand: run "
        "./scripts/tradeoffs. -->\n\n"
     << "idto has knobs that trade speed for accuracy: the contact model's stiffness, "
        "stiction velocity and smoothing, the derivative method (analytic or finite "
        "differences), penalty or Lagrange "
        "multipliers for the unactuated DoFs, the contact pruning tolerance, the number of "
        "threads and the horizon. This page measures each one on the examples "
        "(`examples/<name>/<name>.yaml`), so you can choose. Every number and figure on it "
        "was produced by one run of `idto-tradeoffs` (regenerate everything with "
        "`./scripts/tradeoffs`); the only numbers not measured by that run are the paper's, "
        "labelled as such. Timings come from a shared machine and vary from run to run; "
        "compare numbers within one table rather than across runs. To reduce the effect of other "
        "work on the machine, timed solves are repeated ("
     << context.repeats
     << " times unless a section says otherwise; solves are deterministic) and keep, per "
        "iteration and phase, the smallest time measured; the solves of section 1 are not "
        "repeated.\n\n"
     << "**How this was produced.** `" << run.command << "` on " << machine.cores << " cores ("
     << machine.cpu << "), " << machine.kernel << ", " << machine.compiler << ", "
     << machine.build_type << " build, " << machine.date << "; load average " << machine.loadavg
     << " at the start and " << run.load_end << " at the end (1, 5, 15 min; "
     << "other work on the machine slows the timings); OMP_WAIT_POLICY=" << machine.omp_wait_policy
     << "; " << context.threads << " solver threads unless threads are the variable; total "
     << idto::tradeoffs::Num(run.total_seconds, 3) << " s.";
  if (context.quick) {
    md << " **Quick mode:** smaller sweeps and fewer iterations than the full run; a smoke "
          "test, not results to quote.";
  }
  md << "\n\n";
  return md.str();
}

/// The table of contents: a line per study (with its time and load), then the summary's.
std::string Contents(const StudyRuns& runs) {
  std::ostringstream md;
  md << "## Contents\n\n";
  for (size_t i = 0; i < runs.results.size(); ++i) {
    md << i + 1 << ". " << runs.results[i].title << " (" << idto::tradeoffs::Num(runs.seconds[i], 3)
       << " s; load average " << runs.loads[i] << " when it started)\n";
  }
  md << runs.results.size() + 1
     << ". Summary: which knob buys the most speed for the least "
        "accuracy\n\n";
  return md.str();
}

/// The studies' sections, each ending with how it was produced, then the summary section of
/// all their findings and notes.
std::string Sections(const StudyRuns& runs, const RunRecord& run, const Context& context) {
  const idto::tradeoffs::MachineInfo& machine = run.machine;
  std::ostringstream md;
  std::vector<Finding> findings;
  std::vector<std::string> notes;
  for (size_t i = 0; i < runs.results.size(); ++i) {
    const StudyResult& result = runs.results[i];
    md << "## " << i + 1 << ". " << result.title << "\n\n"
       << result.markdown << "*How this section was produced: `" << run.command
       << "` (this section alone: `idto-tradeoffs --only " << result.id
       << (context.quick ? " --quick" : "") << "`), " << machine.cores << " cores (" << machine.cpu
       << "), " << machine.compiler << ", " << machine.date << "; load average " << runs.loads[i]
       << " when it started; " << idto::tradeoffs::Num(runs.seconds[i], 3) << " s.*\n\n";
    findings.insert(findings.end(), result.findings.begin(), result.findings.end());
    notes.insert(notes.end(), result.notes.begin(), result.notes.end());
  }
  md << "## " << runs.results.size() + 1
     << ". Summary: which knob buys the most speed for the least accuracy\n\n"
     << Summary(findings, notes);
  return md.str();
}

}  // namespace

int main(int argc, char** argv) {
  Context context;
  std::string out_dir;
  std::vector<std::string> only;
  if (const std::optional<int> exit_code = ParseArguments(argc, argv, &context, &out_dir, &only)) {
    return *exit_code;
  }

  const std::vector<Study> studies = {
      {"sensitivity", idto::tradeoffs::RunSensitivityStudy},
      {"smoothing", idto::tradeoffs::RunSmoothingStudy},
      {"derivatives", idto::tradeoffs::RunDerivativeStudy},
      {"constraints", idto::tradeoffs::RunConstraintStudy},
      {"pruning", idto::tradeoffs::RunPruningStudy},
      {"scaling", idto::tradeoffs::RunScalingStudy},
  };
  for (const std::string& id : only) {
    if (std::none_of(studies.begin(), studies.end(), [&](const Study& s) { return s.id == id; })) {
      std::cerr << "--only: unknown study '" << id << "'\n" << kUsage;
      return 2;
    }
  }

  try {
    if (out_dir.empty()) out_dir = std::string(IDTO_SOURCE_DIR) + "/docs";
    PrepareOutput(out_dir, argc > 0 ? argv[0] : "", &context);

    RunRecord run;
    run.machine = idto::tradeoffs::ReadMachineInfo();
    const auto start = std::chrono::steady_clock::now();
    const StudyRuns runs = RunStudies(studies, only, context);
    run.total_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.load_end = idto::tradeoffs::ReadLoadAverage();
    run.command = "idto-tradeoffs";
    for (int i = 1; i < argc; ++i) run.command += std::string(" ") + argv[i];

    const std::string md_path = out_dir + "/tradeoffs.md";
    idto::tradeoffs::WriteFile(
        md_path, Introduction(run, context) + Contents(runs) + Sections(runs, run, context));
    std::filesystem::remove_all(context.data_dir);
    std::cout << "idto-tradeoffs: wrote " << md_path << " in "
              << idto::tradeoffs::Num(run.total_seconds, 3) << " s" << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "idto-tradeoffs: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
