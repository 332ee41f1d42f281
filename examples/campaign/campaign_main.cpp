// idto-campaign: runs an example's closed loop many times under randomized conditions and
// reports the success rate (docs/mpc.md, "Campaigns").
//
//   idto-campaign NAME --runs N --seed S [--jobs J] [--json FILE] [--markdown FILE]
//                 [--threads T] [--iterations-per-step K] [--latency S] [--jitter S] [--max-impulse
//                 X] [--mismatch F]
//                 [--noise F] [--initial F]
//   idto-campaign NAME --run-index I --seed S --json FILE [--trajectory-csv FILE]
//                 (one run: seed S + I; its closed-loop log as CSV)
//   idto-campaign --merge FILE... [--json FILE] [--markdown FILE]
//
// Run i uses the seed S + i: its conditions (campaign.hpp) and everything random in its closed
// loop follow from it, so a run is reproducible bit for bit (fixed latencies). With --jobs J,
// the runs go to J child processes at a time (this program with --run-index), whose JSON files
// are merged like --merge does: a large campaign can be fanned out across machines the same
// way, by running index ranges anywhere and merging the files.
//
// Exit codes: 0 done (whatever the success rate), 1 an error, 2 bad command-line arguments.

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "campaign/campaign.hpp"
#include "campaign/campaign_report.hpp"
#include "common/command_line.hpp"
#include "idto/config/config.hpp"
#include "idto/sim/plant.hpp"
#include "idto_build_paths.hpp"

extern char** environ;

namespace {

using idto::campaign::CampaignSettings;
using idto::campaign::RunResult;

using idto::examples::kExitOk;
using idto::examples::UsageError;

const char kUsage[] =
    "usage: idto-campaign NAME --runs N --seed S [options]\n"
    "       idto-campaign NAME --run-index I --seed S --json FILE [options]\n"
    "       idto-campaign --merge FILE... [--json FILE] [--markdown FILE]\n"
    "\n"
    "Runs NAME's closed loop against MuJoCo N times; run i draws its conditions (push, friction,\n"
    "masses, initial state, sensor noise, latency jitter) from the seed S + i.\n"
    "NAME: spinner, quadruped, quadruped_hills, hopper, bimanual_lift, allegro.\n"
    "\n"
    "options:\n"
    "  --runs N            number of runs (N >= 1)\n"
    "  --seed S            seed of run 0 (an integer >= 0)\n"
    "  --jobs J            run J child processes at a time (J >= 1, default 1: in process)\n"
    "  --run-index I       run only run I (seed S + I) and write it with --json\n"
    "  --trajectory-csv FILE\n"
    "                      with --run-index: also write the run's closed-loop log (t, q,\n"
    "                      v, u, contacts) as CSV\n"
    "  --merge FILE...     merge JSON files written by idto-campaign (runs or shards)\n"
    "  --json FILE         write the runs and the summary as JSON\n"
    "  --markdown FILE     write the summary as Markdown tables\n"
    "  --threads T         controller solver threads (T >= 1, default 1)\n"
    "  --iterations-per-step K\n"
    "                      solver iterations per control step (K >= 1, default: the\n"
    "                      example's mpc.iterations_per_step)\n"
    "  --latency S         fixed latency of every re-plan, s (default: per example)\n"
    "  --jitter S          plus uniform [0, S] s per re-plan (default: twice the latency)\n"
    "  --max-impulse X     largest push impulse, N s (default: per example)\n"
    "  --mismatch F        friction and masses within 1 -+ F (0 <= F < 1, default 0.3)\n"
    "  --noise F           sensor noise times F (F >= 0; 0: none; default 1: 1 mm or mrad,\n"
    "                      2 % of |v| with a floor of 1e-3)\n"
    "  --initial F         initial-state perturbation times F (F >= 0; default 1: 1 mrad on\n"
    "                      the joints, 0.05 on every velocity)\n"
    "  --quiet             no line per run\n"
    "  -h, --help          this message\n"
    "\n"
    "exit codes: 0 done, 1 error, 2 bad arguments\n";

struct Arguments {
  std::string name;
  std::optional<int> runs, jobs, run_index, threads, iterations_per_step;
  std::optional<std::uint64_t> seed;
  std::optional<double> latency, jitter, max_impulse, mismatch, noise, initial;
  std::vector<std::string> merge;
  bool merging{false};
  std::string json, markdown, trajectory_csv;
  bool quiet{false};
  bool help{false};
};

[[noreturn]] void Bad(const std::string& flag, const std::string& value,
                      const std::string& expected) {
  throw UsageError{flag + " is '" + value + "'; expected " + expected};
}

int ParseInt(const std::string& flag, const std::string& text, int min_value) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || v < min_value || v > 1000000000L) {
    Bad(flag, text, "an integer >= " + std::to_string(min_value));
  }
  return static_cast<int>(v);
}

std::uint64_t ParseSeed(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || text[0] == '-' || *end != '\0' || errno != 0) {
    Bad(flag, text, "an integer >= 0 (at most 2^64 - 1)");
  }
  return v;
}

double ParseNonNegative(const std::string& flag, const std::string& text, double below) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || v < 0.0 || v >= below) {
    Bad(flag, text,
        below < 1e300 ? "a number in [0, " + std::to_string(below) + ")" : "a number >= 0");
  }
  return v;
}

// Whether two paths name one file (the same text, or the same file once resolved).
bool SamePath(const std::string& a, const std::string& b) {
  if (a == b) return true;
  std::error_code error;
  const auto first = std::filesystem::weakly_canonical(a, error);
  if (error) return false;
  const auto second = std::filesystem::weakly_canonical(b, error);
  return !error && first == second;
}

// Two outputs on one path would overwrite each other, and an output on a merged input would
// replace a shard: refuse, naming the options.
void CheckDistinctOutputs(const Arguments& a) {
  const std::vector<std::pair<std::string, std::string>> outputs = {
      {"--json", a.json}, {"--markdown", a.markdown}, {"--trajectory-csv", a.trajectory_csv}};
  for (size_t i = 0; i < outputs.size(); ++i) {
    if (outputs[i].second.empty()) continue;
    for (size_t j = i + 1; j < outputs.size(); ++j) {
      if (!outputs[j].second.empty() && SamePath(outputs[i].second, outputs[j].second)) {
        throw UsageError{outputs[i].first + " and " + outputs[j].first + " name the same file '" +
                         outputs[j].second + "'"};
      }
    }
    for (const std::string& input : a.merge) {
      if (SamePath(outputs[i].second, input)) {
        throw UsageError{outputs[i].first + " names '" + outputs[i].second +
                         "', a file given to --merge: write the merged result elsewhere"};
      }
    }
  }
}

Arguments ParseArguments(int argc, char** argv) {
  Arguments a;
  const double kNoLimit = 1e308;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw UsageError{arg + " needs a value"};
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      a.help = true;
    } else if (arg == "--quiet") {
      a.quiet = true;
    } else if (arg == "--runs") {
      a.runs = ParseInt(arg, value(), 1);
    } else if (arg == "--jobs") {
      a.jobs = ParseInt(arg, value(), 1);
    } else if (arg == "--run-index") {
      a.run_index = ParseInt(arg, value(), 0);
    } else if (arg == "--threads") {
      a.threads = ParseInt(arg, value(), 1);
    } else if (arg == "--iterations-per-step") {
      a.iterations_per_step = ParseInt(arg, value(), 1);
    } else if (arg == "--seed") {
      a.seed = ParseSeed(arg, value());
    } else if (arg == "--latency") {
      a.latency = ParseNonNegative(arg, value(), kNoLimit);
    } else if (arg == "--jitter") {
      a.jitter = ParseNonNegative(arg, value(), kNoLimit);
    } else if (arg == "--max-impulse") {
      a.max_impulse = ParseNonNegative(arg, value(), kNoLimit);
    } else if (arg == "--mismatch") {
      a.mismatch = ParseNonNegative(arg, value(), 1.0);
    } else if (arg == "--noise") {
      a.noise = ParseNonNegative(arg, value(), kNoLimit);
    } else if (arg == "--initial") {
      a.initial = ParseNonNegative(arg, value(), kNoLimit);
    } else if (arg == "--json") {
      a.json = value();
    } else if (arg == "--markdown") {
      a.markdown = value();
    } else if (arg == "--trajectory-csv") {
      a.trajectory_csv = value();
    } else if (arg == "--merge") {
      a.merging = true;
      while (i + 1 < argc && std::strncmp(argv[i + 1], "--", 2) != 0) a.merge.push_back(argv[++i]);
      if (a.merge.empty()) throw UsageError{"--merge needs at least one FILE"};
    } else if (arg.rfind("-", 0) == 0) {
      throw UsageError{"unknown option '" + arg + "'"};
    } else if (a.name.empty()) {
      a.name = arg;
    } else {
      throw UsageError{"unexpected argument '" + arg + "' (NAME is already '" + a.name + "')"};
    }
  }
  if (a.help) return a;
  if (a.merging) {
    if (!a.name.empty() || a.runs || a.seed || a.run_index || a.jobs) {
      throw UsageError{"--merge takes only FILEs, --json and --markdown"};
    }
    CheckDistinctOutputs(a);
    return a;
  }
  if (a.name.empty()) throw UsageError{"missing NAME (e.g. spinner)"};
  const std::vector<std::string> names = idto::campaign::CampaignExamples();
  if (std::find(names.begin(), names.end(), a.name) == names.end()) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    Bad("NAME", a.name, "one of " + list);
  }
  if (!a.seed) throw UsageError{"missing --seed S"};
  if (a.run_index) {
    if (a.runs || a.jobs) throw UsageError{"--run-index runs one run: no --runs or --jobs"};
    if (a.json.empty()) throw UsageError{"--run-index needs --json FILE"};
  } else if (!a.runs) {
    throw UsageError{"missing --runs N"};
  } else if (!a.trajectory_csv.empty()) {
    throw UsageError{"--trajectory-csv needs --run-index (one run's log)"};
  }
  CheckDistinctOutputs(a);
  return a;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read '" + path + "'");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

std::string ExecutablePath(const char* argv0) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(argv0 ? argv0 : "") : self.string();
}

CampaignSettings Settings(const Arguments& a) {
  CampaignSettings s = idto::campaign::DefaultSettings(a.name);
  if (a.threads) s.threads = *a.threads;
  if (a.iterations_per_step) s.iterations_per_step = *a.iterations_per_step;
  if (a.latency) {
    s.latency = *a.latency;
    s.jitter = 2.0 * s.latency;
  }
  if (a.jitter) s.jitter = *a.jitter;
  if (a.max_impulse) s.max_impulse = *a.max_impulse;
  if (a.mismatch) s.mismatch = *a.mismatch;
  if (a.noise) {
    s.noise_position *= *a.noise;
    s.noise_velocity *= *a.noise;
    s.noise_velocity_floor *= *a.noise;
  }
  if (a.initial) {
    s.initial_position *= *a.initial;
    s.initial_velocity *= *a.initial;
  }
  return s;
}

/// The flags that fix the settings, for the child processes.
std::vector<std::string> SettingFlags(const Arguments& a) {
  std::vector<std::string> flags;
  const auto add = [&flags](const std::string& flag, const std::string& value) {
    flags.push_back(flag);
    flags.push_back(value);
  };
  const auto exact = [](double x) {
    char buffer[40];
    std::snprintf(buffer, sizeof(buffer), "%.17g", x);
    return std::string(buffer);
  };
  if (a.threads) add("--threads", std::to_string(*a.threads));
  if (a.iterations_per_step) add("--iterations-per-step", std::to_string(*a.iterations_per_step));
  if (a.latency) add("--latency", exact(*a.latency));
  if (a.jitter) add("--jitter", exact(*a.jitter));
  if (a.max_impulse) add("--max-impulse", exact(*a.max_impulse));
  if (a.mismatch) add("--mismatch", exact(*a.mismatch));
  if (a.noise) add("--noise", exact(*a.noise));
  if (a.initial) add("--initial", exact(*a.initial));
  return flags;
}

void PrintRun(const RunResult& r) {
  std::cout << "run " << r.run_index << " (seed " << r.conditions.seed
            << "): " << (r.success ? "success" : "failure: " + r.failure_mode) << "; push "
            << r.conditions.push_impulse << " N s at " << r.conditions.push_time << " s, friction x"
            << r.conditions.friction_scale << ", mass x" << r.conditions.total_mass_scale
            << ", late " << r.late_plans << ", skipped " << r.skipped_replans << ", rejected "
            << r.rejected_plans << std::endl;
}

/// Runs runs [0, n) in child processes, `jobs` at a time; returns their merged results.
std::vector<RunResult> RunChildren(const Arguments& a, const char* argv0) {
  const std::string exe = ExecutablePath(argv0);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("idto-campaign-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::vector<std::string> files(*a.runs), texts;
  int next = 0, running = 0, failed = 0;
  while (next < *a.runs || running > 0) {
    while (running < *a.jobs && next < *a.runs) {
      files[next] = (dir / ("run_" + std::to_string(next) + ".json")).string();
      std::vector<std::string> args = {exe,           a.name,
                                       "--run-index", std::to_string(next),
                                       "--seed",      std::to_string(*a.seed),
                                       "--json",      files[next],
                                       "--quiet"};
      for (const std::string& f : SettingFlags(a)) args.push_back(f);
      std::vector<char*> argv;
      for (std::string& s : args) argv.push_back(s.data());
      argv.push_back(nullptr);
      pid_t pid = 0;
      if (posix_spawn(&pid, exe.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
        throw std::runtime_error("cannot start '" + exe + "'");
      }
      ++running;
      ++next;
    }
    int status = 0;
    if (::wait(&status) > 0) {
      --running;
      if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) ++failed;
    }
  }
  if (failed > 0) throw std::runtime_error(std::to_string(failed) + " child run(s) failed");
  for (const std::string& f : files) texts.push_back(ReadText(f));
  CampaignSettings settings;
  std::vector<RunResult> runs;
  idto::campaign::MergeCampaigns(texts, files, &settings, &runs);
  std::filesystem::remove_all(dir);
  return runs;
}

void WriteOutputs(const Arguments& a, const CampaignSettings& settings,
                  const std::vector<RunResult>& runs) {
  if (!a.json.empty()) WriteText(a.json, idto::campaign::CampaignJson(settings, runs));
  const std::string markdown = idto::campaign::CampaignMarkdown(settings, runs);
  if (!a.markdown.empty()) WriteText(a.markdown, markdown);
  if (a.quiet || a.run_index) return;
  std::cout << markdown;
}

/// What the example's URDF files hold that idto ignores by design (UrdfWarning), on stderr.
void PrintUrdfWarnings(const idto::ExampleConfig& config) {
  for (const idto::UrdfWarning& w : config.urdf_warnings) {
    std::cerr << "idto-campaign: warning: " << w.ToString() << "\n";
  }
}

int Run(const Arguments& a, const char* argv0) {
  if (a.merging) {
    std::vector<std::string> texts;
    for (const std::string& f : a.merge) texts.push_back(ReadText(f));
    CampaignSettings settings;
    std::vector<RunResult> runs;
    idto::campaign::MergeCampaigns(texts, a.merge, &settings, &runs);
    std::cout << idto::campaign::CampaignMarkdown(settings, runs);
    if (!a.json.empty()) WriteText(a.json, idto::campaign::CampaignJson(settings, runs));
    if (!a.markdown.empty()) {
      WriteText(a.markdown, idto::campaign::CampaignMarkdown(settings, runs));
    }
    return kExitOk;
  }
  const CampaignSettings settings = Settings(a);
  if (!idto::sim::HaveMujoco()) throw std::runtime_error("idto was built without MuJoCo");
  std::vector<std::string> share_dirs =
      idto::DefaultShareDirs(IDTO_SOURCE_SHARE_DIR, ExecutablePath(argv0));
  share_dirs.push_back(IDTO_INSTALL_SHARE_DIR);
  const idto::ExampleConfig config =
      idto::LoadExampleConfig(idto::FindExampleConfig(a.name, share_dirs), share_dirs);
  // Once per campaign: the child processes (--run-index) load the same files.
  if (!a.run_index) PrintUrdfWarnings(config);
  std::vector<RunResult> runs;
  if (a.run_index) {
    std::string csv;
    runs.push_back(idto::campaign::RunOne(settings, config, *a.run_index, *a.seed + *a.run_index,
                                          a.trajectory_csv.empty() ? nullptr : &csv));
    if (!a.trajectory_csv.empty()) WriteText(a.trajectory_csv, csv);
  } else if (a.jobs.value_or(1) > 1) {
    runs = RunChildren(a, argv0);
    if (!a.quiet) {
      for (const RunResult& r : runs) PrintRun(r);
    }
  } else {
    for (int i = 0; i < *a.runs; ++i) {
      runs.push_back(idto::campaign::RunOne(settings, config, i, *a.seed + i));
      if (!a.quiet) PrintRun(runs.back());
    }
  }
  WriteOutputs(a, settings, runs);
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  return idto::examples::RunCommandLine<Arguments>(
      "idto-campaign", kUsage, argc, argv, ParseArguments,
      [&](const Arguments& args) { return Run(args, argc > 0 ? argv[0] : nullptr); });
}
