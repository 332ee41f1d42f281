// Iteration time with and without a busy competitor process (issue 19: contention-proof
// parallelism), for the quadruped, Allegro and bi-manual examples as configured in their YAML
// files.
//
// Four optimizers of the same example (1 thread quiet, 2 threads quiet, 1 thread with the
// competitor, 2 threads with it) are timed in alternating blocks within each benchmark
// iteration (a "round"), so the machine's drift affects all four alike. The competitor is a
// child process spinning on a core (competitor.hpp), resumed for the contended blocks and
// stopped for the quiet ones; it is killed at the end. Every block restarts its optimizer from
// the same iterate and every optimizer sees the same sequence of calls, so the four do bitwise
// the same arithmetic: only the scheduling differs.
//
// Counters (ms per solver iteration, mean over the run): t1_quiet, t2_quiet, t1_busy, t2_busy;
// ratios: busy2_over_quiet1 = t2_busy / t1_quiet (the acceptance ratio, target <= 1.2),
// quiet2_over_quiet1 and busy1_over_quiet1. The benchmark's own time is one round.
// Name: "contention/<example>".

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "competitor.hpp"
#include "idto/idto.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Setting {
  int threads;
  bool competitor;
  const char* counter;
};
constexpr std::array<Setting, 4> kSettings{{{1, false, "t1_quiet_ms"},
                                            {2, false, "t2_quiet_ms"},
                                            {1, true, "t1_busy_ms"},
                                            {2, true, "t2_busy_ms"}}};
// Target duration of one timed block.
constexpr double kBlockSeconds = 0.03;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Runs `count` single-iteration warm starts of `opt` from `q_start`; false on a failure.
bool RunBlock(const std::vector<Eigen::VectorXd>& q_start, int count,
              idto::TrajectoryOptimizer* opt, idto::Trajectory* solution) {
  opt->SetIterate(q_start);
  for (int i = 0; i < count; ++i) {
    const idto::SolverSummary s = opt->SolveWarmStart(solution);
    if (s.termination == idto::TerminationType::kFailure || s.log.empty()) return false;
  }
  return true;
}

void BM_Contention(benchmark::State& state, const std::string& name) {
  idto::ExampleConfig config;
  try {
    const std::string dir = std::string(IDTO_SOURCE_DIR);
    config = idto::LoadExampleConfig(dir + "/examples/" + name + "/" + name + ".yaml", {dir});
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  // Four optimizers, warmed up by 5 iterations from the example's initial guess.
  std::vector<std::unique_ptr<idto::TrajectoryOptimizer>> opts;
  std::vector<idto::Trajectory> solutions(kSettings.size());
  double warmup_seconds = 0.0;
  for (size_t c = 0; c < kSettings.size(); ++c) {
    idto::SolverOptions o = config.solver;
    o.num_threads = kSettings[c].threads;
    o.max_iterations = 5;
    o.fixed_iterations = true;
    opts.push_back(std::make_unique<idto::TrajectoryOptimizer>(config.model, config.problem, o));
    const auto start = Clock::now();
    opts.back()->Solve(idto::MakeInitialGuess(config), &solutions[c]);
    if (c == 0) warmup_seconds = SecondsSince(start);
    opts.back()->mutable_options().max_iterations = 1;
  }
  const std::vector<Eigen::VectorXd> q_start = solutions[0].q;
  const int block =
      std::clamp(static_cast<int>(std::lround(kBlockSeconds * 5 / warmup_seconds)), 2, 50);
  idto::bench::BusyCompetitor competitor(false);
  std::array<double, kSettings.size()> seconds{};
  std::int64_t iterations = 0;
  std::int64_t round = 0;
  for (auto _ : state) {
    for (size_t j = 0; j < kSettings.size(); ++j) {
      // Alternate the order of the settings from one round to the next.
      const size_t c = round % 2 == 0 ? j : kSettings.size() - 1 - j;
      if (kSettings[c].competitor) {
        competitor.Resume();
      } else {
        competitor.Pause();
      }
      const auto start = Clock::now();
      if (!RunBlock(q_start, block, opts[c].get(), &solutions[c])) {
        state.SkipWithError("an iteration failed");
        return;
      }
      seconds[c] += SecondsSince(start);
    }
    iterations += block;
    ++round;
  }
  competitor.Pause();
  if (iterations == 0) return;
  for (size_t c = 0; c < kSettings.size(); ++c) {
    state.counters[kSettings[c].counter] = 1e3 * seconds[c] / static_cast<double>(iterations);
  }
  state.counters["busy2_over_quiet1"] = seconds[3] / seconds[0];
  state.counters["quiet2_over_quiet1"] = seconds[1] / seconds[0];
  state.counters["busy1_over_quiet1"] = seconds[2] / seconds[0];
  state.counters["block"] = block;
}

void Register() {
  for (const std::string name : {"quadruped", "allegro", "bimanual"}) {
    benchmark::RegisterBenchmark(("contention/" + name).c_str(),
                                 [name](benchmark::State& s) { BM_Contention(s, name); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
}

const bool kRegistered = (Register(), true);

}  // namespace
