// idto-bench: the benchmark suite. Benchmarks register themselves in the other files of this
// folder; names start with their module ("core/", "dynamics/", "contact/", "solver/", ...).
//
// Benchmarks that come in pairs ".../idto" and ".../mujoco" (same kernel, same model, same run)
// are summarized at the end of the run by a table of the ratio idto / MuJoCo of their real time
// per call (the mean over repetitions when --benchmark_repetitions is used). The table goes to
// stdout after the console output, or to stderr when another --benchmark_format is selected, so
// that JSON/CSV output stays parseable. Likewise, benchmarks whose name contains "/clutter100"
// are compared with the same name with "/plain" (scene_bench.cpp).
#include <cstdio>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "idto/version.hpp"

namespace {

// Forwards everything to the reporter the command line asks for, and remembers the real time
// per call of every benchmark for the ratio table.
class RatioReporter : public benchmark::BenchmarkReporter {
 public:
  explicit RatioReporter(benchmark::BenchmarkReporter* inner) : inner_(inner) {}

  bool ReportContext(const Context& context) override { return inner_->ReportContext(context); }

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.error_occurred) continue;
      const bool is_mean = run.run_type == Run::RT_Aggregate && run.aggregate_name == "mean";
      if (run.run_type != Run::RT_Iteration && !is_mean) continue;
      const std::string name = run.run_name.str();
      if (seconds_.count(name) == 0) order_.push_back(name);
      Entry& entry = seconds_[name];
      if (entry.from_mean && !is_mean) continue;
      entry.seconds = run.GetAdjustedRealTime() / benchmark::GetTimeUnitMultiplier(run.time_unit);
      entry.from_mean = is_mean;
    }
    inner_->ReportRuns(runs);
  }

  void Finalize() override {
    inner_->Finalize();
    const bool console = dynamic_cast<benchmark::ConsoleReporter*>(inner_.get()) != nullptr;
    std::ostream& out = console ? inner_->GetOutputStream() : inner_->GetErrorStream();
    char line[160];
    bool header = false;
    const std::string kIdto = "/idto";
    for (const std::string& name : order_) {
      const Entry& entry = seconds_.at(name);
      if (name.size() <= kIdto.size() ||
          name.compare(name.size() - kIdto.size(), kIdto.size(), kIdto) != 0) {
        continue;
      }
      const std::string stem = name.substr(0, name.size() - kIdto.size());
      const auto peer = seconds_.find(stem + "/mujoco");
      if (peer == seconds_.end()) continue;
      if (!header) {
        std::snprintf(line, sizeof(line), "%-44s %12s %12s %8s", "benchmark", "idto [us]",
                      "mujoco [us]", "ratio");
        out << "\nratio idto/mujoco (real time per call, same run)\n" << line << "\n";
        header = true;
      }
      std::snprintf(line, sizeof(line), "%-44s %12.3f %12.3f %8.3f", stem.c_str(),
                    1e6 * entry.seconds, 1e6 * peer->second.seconds,
                    entry.seconds / peer->second.seconds);
      out << line << "\n";
    }
    // Scenes with clutter against the same scene without ("/clutter100" vs "/plain").
    header = false;
    const std::string kClutter = "/clutter100", kPlain = "/plain";
    for (const std::string& name : order_) {
      const size_t at = name.find(kClutter);
      if (at == std::string::npos) continue;
      std::string plain = name;
      plain.replace(at, kClutter.size(), kPlain);
      const auto peer = seconds_.find(plain);
      if (peer == seconds_.end()) continue;
      if (!header) {
        std::snprintf(line, sizeof(line), "%-52s %12s %12s %8s", "benchmark", "clutter [us]",
                      "plain [us]", "ratio");
        out << "\nratio clutter/plain (real time per call, same run)\n" << line << "\n";
        header = true;
      }
      const double seconds = seconds_.at(name).seconds;
      std::snprintf(line, sizeof(line), "%-52s %12.3f %12.3f %8.3f", name.c_str(), 1e6 * seconds,
                    1e6 * peer->second.seconds, seconds / peer->second.seconds);
      out << line << "\n";
    }
    out << std::flush;
  }

 private:
  struct Entry {
    double seconds{0.0};
    bool from_mean{false};
  };
  std::unique_ptr<benchmark::BenchmarkReporter> inner_;
  std::map<std::string, Entry> seconds_;
  std::vector<std::string> order_;  // names in the order run
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::AddCustomContext("idto_version", IDTO_VERSION_STRING);
#if defined(__clang__)
  benchmark::AddCustomContext("compiler", "clang " __clang_version__);
#elif defined(__GNUC__)
  benchmark::AddCustomContext("compiler", "gcc " __VERSION__);
#endif
#ifdef IDTO_HAVE_MUJOCO
  benchmark::AddCustomContext("mujoco", "yes");
#else
  benchmark::AddCustomContext("mujoco", "no");
#endif
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  // The default display reporter honours --benchmark_format and --benchmark_color.
  RatioReporter reporter(benchmark::CreateDefaultDisplayReporter());
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
