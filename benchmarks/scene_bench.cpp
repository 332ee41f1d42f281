// "Model only what a scene requires" (issue 8): the quadruped example as configured in
// examples/quadruped/quadruped.yaml ("plain"), and the same scene with 100 extra geometries the
// task never touches ("clutter100"):
//  - 50 static spheres in the world, 3-5.5 m around the robot (beyond the contact cut-off, about
//    0.21 m here). They are real contact pairs with every robot geometry (added to the file's
//    included_pairs), so only pruning keeps them out of the evaluation: 400 extra pairs.
//  - 50 small spheres welded to the robot's bodies whose pairs are all filtered out
//    (excluded_pairs): no pair at all.
// The cluttered model is re-created in code with a ModelBuilder from the example's URDF models
// and scene geometry, then the clutter is appended, so every pair of the plain scene keeps its
// geometry indices and relative order and the solver's iterates are bitwise the same (tested in
// tests/solver/clutter_test.cpp).
//
// Method as in examples_bench.cpp: 5 warm-up iterations from the file's initial guess, then each
// benchmark iteration is one solver iteration (SolveWarmStart, max_iterations = 1,
// fixed_iterations), with the file's constraint method (penalty). Counters: per-iteration
// breakdown in µs and the number of contact pairs. main.cpp prints the clutter100 / plain ratio
// of real time per iteration at the end of the run. On a shared machine whose speed drifts, the
// paired benchmark "scene/quadruped/clutter100_vs_plain/threads:<T>" is the better measure: it
// alternates one iteration of each scene and reports both times and their ratio as counters.
// Names: "scene/quadruped/<plain|clutter100|clutter100_vs_plain>/threads:<T>".

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/idto.hpp"
#include "iteration_timing.hpp"

namespace {

constexpr int kNumStaticClutter = 50;
constexpr int kNumBodyClutter = 50;

// The example's scene re-created with a ModelBuilder (its URDF models, then its scene
// geometry), plus the clutter described at the top of this file.
idto::ExampleConfig AddClutter(const idto::ExampleConfig& plain) {
  idto::ModelBuilder builder(plain.model.name());
  for (const idto::SceneModelConfig& m : plain.models) {
    idto::AddUrdfFile(m.urdf_file, m.options, &builder);
  }
  const std::vector<idto::GeometryInstance>& scene = plain.model.geometries();
  const std::vector<idto::GeometryInstance> from_urdf = builder.Build().geometries();
  for (size_t g = 0; g < scene.size(); ++g) {
    if (g < from_urdf.size()) {
      if (from_urdf[g].name != scene[g].name) {
        throw std::runtime_error("AddClutter: geometry " + std::to_string(g) + " is \"" +
                                 from_urdf[g].name + "\", expected \"" + scene[g].name + "\"");
      }
      continue;
    }
    builder.AddGeometry(scene[g].name, scene[g].body, scene[g].X_BG, scene[g].shape);
  }
  builder.SetGravity(plain.model.gravity());

  idto::ExampleConfig cluttered = plain;
  idto::ContactOptions& contact = cluttered.problem.contact;
  for (int i = 0; i < kNumStaticClutter; ++i) {
    const std::string name = "clutter_static" + std::to_string(i);
    const double angle = 2.0 * M_PI * i / kNumStaticClutter;
    const double distance = 3.0 + 0.05 * i;
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() << distance * std::cos(angle), distance * std::sin(angle), 0.2 + 0.02 * i;
    builder.AddGeometry(name, idto::kWorldBody, X, idto::Sphere{0.05 + 0.005 * i});
    // Without included_pairs every pair is admitted already.
    if (!contact.included_pairs.empty()) contact.included_pairs.emplace_back(name, "*");
  }
  const int num_bodies = plain.model.num_bodies();
  for (int i = 0; i < kNumBodyClutter; ++i) {
    const std::string name = "clutter_body" + std::to_string(i);
    const idto::BodyIndex body = 1 + i % (num_bodies - 1);
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() << 0.01 * (i % 5), 0.01 * ((i / 5) % 5), 0.01 * (i / 25);
    builder.AddGeometry(name, body, X, idto::Sphere{0.01});
    contact.excluded_pairs.emplace_back(name, "*");
  }
  cluttered.model = builder.Build();
  return cluttered;
}

idto::ExampleConfig LoadQuadruped() {
  const std::string dir = std::string(IDTO_SOURCE_DIR);
  return idto::LoadExampleConfig(dir + "/examples/quadruped/quadruped.yaml", {dir});
}

// An optimizer for `config` after 5 warm-up iterations from the file's initial guess, set to
// run one iteration per SolveWarmStart.
idto::TrajectoryOptimizer WarmOptimizer(const idto::ExampleConfig& config, int threads) {
  idto::SolverOptions o = config.solver;
  o.num_threads = threads;
  o.max_iterations = 5;
  o.fixed_iterations = true;
  idto::TrajectoryOptimizer opt(config.model, config.problem, o);
  idto::Trajectory sol;
  opt.Solve(idto::MakeInitialGuess(config), &sol);  // warm-up: past the first iterations
  opt.mutable_options().max_iterations = 1;
  return opt;
}

void BM_Scene(benchmark::State& state, bool clutter) {
  const int threads = static_cast<int>(state.range(0));
  idto::ExampleConfig config;
  try {
    config = LoadQuadruped();
    if (clutter) config = AddClutter(config);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  idto::TrajectoryOptimizer opt = WarmOptimizer(config, threads);
  idto::Trajectory sol;
  idto::bench::TimeSolverIterations(state, &opt, &sol);
  state.counters["geometries"] = static_cast<double>(config.model.geometries().size());
  state.counters["pairs"] = idto::ContactEngine(config.model, config.problem.contact).num_pairs();
}

// Both scenes in one benchmark, one solver iteration of each per benchmark iteration (the
// order alternates), so that drifts in the machine's speed (other jobs, a virtual machine's
// neighbours) hit both alike. Counters: ms per iteration of each and their ratio.
void BM_ScenePair(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  idto::ExampleConfig plain, cluttered;
  try {
    plain = LoadQuadruped();
    cluttered = AddClutter(plain);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  idto::TrajectoryOptimizer opt[2] = {WarmOptimizer(plain, threads),
                                      WarmOptimizer(cluttered, threads)};
  idto::Trajectory sol;
  double seconds[2] = {0.0, 0.0};
  int64_t n = 0;
  for (auto _ : state) {
    for (int j = 0; j < 2; ++j) {
      const int c = (n + j) % 2;
      const auto start = std::chrono::steady_clock::now();
      const idto::SolverSummary s = opt[c].SolveWarmStart(&sol);
      seconds[c] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (s.log.empty()) {
        state.SkipWithError(("no iteration: " + s.message).c_str());
        return;
      }
    }
    ++n;
  }
  if (n > 0 && seconds[0] > 0.0) {
    state.counters["plain_ms"] = 1e3 * seconds[0] / static_cast<double>(n);
    state.counters["clutter100_ms"] = 1e3 * seconds[1] / static_cast<double>(n);
    state.counters["ratio"] = seconds[1] / seconds[0];
  }
}

void Register() {
  benchmark::RegisterBenchmark("scene/quadruped/clutter100_vs_plain", BM_ScenePair)
      ->ArgName("threads")
      ->Arg(1)
      ->Arg(2)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  for (bool clutter : {false, true}) {
    const std::string name = std::string("scene/quadruped/") + (clutter ? "clutter100" : "plain");
    benchmark::RegisterBenchmark(name.c_str(),
                                 [clutter](benchmark::State& s) { BM_Scene(s, clutter); })
        ->ArgName("threads")
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
}

const bool kRegistered = (Register(), true);

}  // namespace
