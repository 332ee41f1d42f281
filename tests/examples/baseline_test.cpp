// Every example, both constraint methods, 15 iterations on 1 thread: the final cost and q_N equal
// the recorded results to 1e-9 relative, on each path of the block kernels
// (src/math/block_kernels.hpp) against its own file: solver_baseline.txt for the portable path,
// solver_baseline_avx2.txt for the AVX2/FMA kernels (their fused multiply-adds round differently,
// and a 15-iteration solve carries that up to 2e-5 relative in the cost). History (the data files'
// headers have the numbers): the split into a transcription and a minimizer reproduced the
// pre-redesign rows bit for bit; the Lagrange rows were re-recorded when the banded KKT solve
// replaced the dense multipliers; all rows were re-recorded when the analytic derivatives became
// the default; the AVX2 file was added with the AVX2/FMA kernels; the "_trial_derivatives" files
// were added with SolverOptions::trial_derivatives (the default), the files without it are now
// solved with that option off (separate passes, unchanged bit for bit); with
// SolverOptions::constraint_correction (the default since 2026-11-30) the "_trial_derivatives"
// files' Lagrange rows were re-recorded, and the files without it are solved with the correction
// off too (the earlier solver, unchanged bit for bit). A change of these numbers
// is a change of the method, not a refactoring: record new values only on purpose, with
//   IDTO_RECORD_BASELINE=tests/data/baseline ./build/tests/idto_examples_test
//     --gtest_filter=*Baseline*EveryExample*
// (writes all four files; keep their header comments).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "examples/example_test_support.hpp"
#include "idto/idto.hpp"
#include "support/kernel_paths.hpp"

namespace idto {
namespace {

using test::kShareDirs;

const char* kBaselineDir = IDTO_TEST_DATA_DIR "/baseline";

// defaults: the default options (the files with "_trial_derivatives": each trial point evaluated
// with its derivatives, dogleg steps corrected onto the linearized constraints); without them the
// solver evaluates and differentiates in separate passes and takes the dogleg step as it is, bit
// for bit the solver before either option existed (the files without "_trial_derivatives").
std::string BaselineFileName(test::KernelPath path, bool defaults) {
  return std::string("solver_baseline") + (defaults ? "_trial_derivatives" : "") +
         (path == test::KernelPath::kAvx2 ? "_avx2" : "") + ".txt";
}

const std::vector<std::string> kExamples = {
    "pendulum",        "acrobot", "spinner",  "hopper",        "quadruped",
    "quadruped_hills", "allegro", "bimanual", "bimanual_lift", "bimanual_balance"};

struct Result {
  double final_cost{0.0};
  Eigen::VectorXd q_final;
};

Result SolveExample(const std::string& name, ConstraintMethod method, int threads = 1,
                    int iterations = 15, bool defaults = true) {
  ExampleConfig config = LoadExampleConfig(FindExampleConfig(name, kShareDirs), kShareDirs);
  config.solver.max_iterations = iterations;
  if (!defaults) {
    config.solver.trial_derivatives = false;
    config.solver.constraint_correction = 0.0;
  }
  config.solver.num_threads = threads;
  config.solver.constraint_method = method;
  TrajectoryOptimizer optimizer(config.model, config.problem, config.solver);
  Trajectory solution;
  const SolverSummary summary = optimizer.Solve(MakeInitialGuess(config), &solution);
  return {summary.final_cost, solution.q.back()};
}

std::string Key(const std::string& name, ConstraintMethod method) {
  return name + " " + ConstraintMethodName(method);
}

// Lines "name method final_cost nq q_N...".
std::map<std::string, Result> ReadBaseline(const std::string& file) {
  std::map<std::string, Result> out;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string name, method;
    Result r;
    int nq = 0;
    s >> name >> method >> r.final_cost >> nq;
    r.q_final.resize(nq);
    for (int i = 0; i < nq; ++i) s >> r.q_final(i);
    out[name + " " + method] = r;
  }
  return out;
}

void CompareWithBaseline(const std::string& file, const std::vector<ConstraintMethod>& methods,
                         bool defaults);

class BaselineKernels : public test::KernelPathTest {};
IDTO_INSTANTIATE_KERNEL_PATHS(BaselineKernels);

TEST_P(BaselineKernels, EveryExampleMatchesThePreRedesignSolver) {
  const std::vector<ConstraintMethod> methods = {ConstraintMethod::kPenalty,
                                                 ConstraintMethod::kLagrangeMultipliers};
  if (const char* record = std::getenv("IDTO_RECORD_BASELINE")) {
    for (const bool defaults : {false, true}) {
      const std::string path = std::string(record) + "/" + BaselineFileName(GetParam(), defaults);
      std::FILE* f = std::fopen(path.c_str(), "w");
      ASSERT_NE(f, nullptr) << path;
      std::fprintf(f, "# name method final_cost nq q_N (15 iterations, 1 thread)\n");
      for (const std::string& name : kExamples) {
        for (ConstraintMethod m : methods) {
          const Result r = SolveExample(name, m, 1, 15, defaults);
          std::fprintf(f, "%s %.17g %d", Key(name, m).c_str(), r.final_cost,
                       static_cast<int>(r.q_final.size()));
          for (int i = 0; i < r.q_final.size(); ++i) std::fprintf(f, " %.17g", r.q_final(i));
          std::fprintf(f, "\n");
        }
      }
      std::fclose(f);
    }
    GTEST_SKIP() << "recorded in " << record;
  }
  for (const bool defaults : {false, true}) {
    const std::string file =
        std::string(kBaselineDir) + "/" + BaselineFileName(GetParam(), defaults);
    CompareWithBaseline(file, methods, defaults);
  }
}

void CompareWithBaseline(const std::string& file, const std::vector<ConstraintMethod>& methods,
                         bool defaults) {
  SCOPED_TRACE(file);
  const std::map<std::string, Result> baseline = ReadBaseline(file);
  ASSERT_EQ(baseline.size(), kExamples.size() * methods.size()) << file;
  for (const std::string& name : kExamples) {
    for (ConstraintMethod m : methods) {
      SCOPED_TRACE(Key(name, m));
      const Result& expected = baseline.at(Key(name, m));
      const Result r = SolveExample(name, m, 1, 15, defaults);
      EXPECT_LE(std::abs(r.final_cost - expected.final_cost),
                1e-9 * std::max(1.0, std::abs(expected.final_cost)))
          << r.final_cost << " vs " << expected.final_cost;
      ASSERT_EQ(r.q_final.size(), expected.q_final.size());
      EXPECT_LE((r.q_final - expected.q_final).norm(),
                1e-9 * std::max(1.0, expected.q_final.norm()));
    }
  }
}

// The examples whose KKT system is factored in two halves (block size n + nu >= 8): the two
// halves on two threads (factorization, solve sweeps, the double-double residual of the adaptive
// refinement step, which the hopper, quadruped and bi-manual lift take) give bitwise the results
// of one thread.
TEST(Baseline, TwoHalfKktIsBitwiseEqualOnOneAndTwoThreads) {
  for (const std::string name : {"hopper", "quadruped", "allegro", "bimanual_lift"}) {
    SCOPED_TRACE(name);
    const Result one = SolveExample(name, ConstraintMethod::kLagrangeMultipliers, 1, 6);
    const Result two = SolveExample(name, ConstraintMethod::kLagrangeMultipliers, 2, 6);
    EXPECT_EQ(one.final_cost, two.final_cost);
    ASSERT_EQ(one.q_final.size(), two.q_final.size());
    EXPECT_TRUE(one.q_final == two.q_final) << (one.q_final - two.q_final).norm();
  }
}

}  // namespace
}  // namespace idto
