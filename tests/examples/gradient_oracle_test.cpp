// The solver's whole gradient (TrajectoryOptimizer::EvalGradient) against forward-mode AD of the
// cost written out independently (tests/support/cost_gradient_oracle.hpp), on the five examples
// of the accuracy criterion, at the initial guess and after 10 iterations: the analytic
// derivatives agree with AD to round-off, and forward differences are at least 100 times less
// accurate (docs/tradeoffs.md §3 uses a difference-based reference, whose own error hides the
// ratio at some of its points).

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "examples/example_test_support.hpp"
#include "idto/idto.hpp"
#include "support/cost_gradient_oracle.hpp"

namespace idto {
namespace {

using test::kShareDirs;

struct Errors {
  double analytic{0.0}, forward{0.0};
};

// Relative errors of the analytic and forward-difference gradients at q against AD.
Errors GradientErrors(TrajectoryOptimizer* opt, const Model& model,
                      const ProblemDefinition& problem, double penalty,
                      const std::vector<Eigen::VectorXd>& q) {
  const Eigen::VectorXd g_ad = test::AutoDiffCostGradient(model, problem, penalty, q);
  Eigen::VectorXd g;
  opt->mutable_options().derivative_method = DerivativeMethod::kAnalytic;
  opt->EvalGradient(q, &g);
  Errors e;
  e.analytic = (g - g_ad).norm() / g_ad.norm();
  opt->mutable_options().derivative_method = DerivativeMethod::kForwardDifferences;
  opt->EvalGradient(q, &g);
  e.forward = (g - g_ad).norm() / g_ad.norm();
  opt->mutable_options().derivative_method = DerivativeMethod::kAnalytic;
  return e;
}

class GradientOracle : public ::testing::TestWithParam<std::string> {};

TEST_P(GradientOracle, AnalyticMatchesAutoDiffAndBeatsForwardDifferencesHundredfold) {
  const ExampleConfig config =
      LoadExampleConfig(FindExampleConfig(GetParam(), kShareDirs), kShareDirs);
  ProblemDefinition problem = config.problem;
  problem.contact.force_tolerance = 0.0;  // every pair, as the oracle evaluates them
  SolverOptions options = config.solver;
  options.num_threads = 1;
  options.derivative_method = DerivativeMethod::kAnalytic;
  options.max_iterations = 10;
  options.fixed_iterations = true;
  const double penalty =
      options.constraint_method == ConstraintMethod::kPenalty ? options.penalty_weight : 0.0;
  TrajectoryOptimizer opt(config.model, problem, options);
  const std::vector<Eigen::VectorXd> guess = MakeInitialGuess(config);
  Trajectory solution;
  opt.Solve(guess, &solution);
  const std::vector<std::pair<std::string, std::vector<Eigen::VectorXd>>> points = {
      {"initial guess", guess}, {"after 10 iterations", solution.q}};
  for (const auto& [label, q] : points) {
    SCOPED_TRACE(label);
    const Errors e = GradientErrors(&opt, config.model, problem, penalty, q);
    std::printf("%s, %s: relative gradient error analytic %.2e, forward %.2e (ratio %.1e)\n",
                GetParam().c_str(), label.c_str(), e.analytic, e.forward, e.forward / e.analytic);
    EXPECT_LT(e.analytic, 1e-10);
    EXPECT_GE(e.forward, 100.0 * e.analytic);
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, GradientOracle,
                         ::testing::Values("spinner", "hopper", "quadruped", "allegro",
                                           "bimanual"));

}  // namespace
}  // namespace idto
