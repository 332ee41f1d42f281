// Exact derivatives against forward differences at the stiff corners, as a paired statistic
// (label "heavy"; docs/solver.md, "Stability at the extremes"). The extremes suite solves each
// corner once per derivative method; from a 1e11-1e15 cost both runs are far from converged at
// the iteration limit, and which ends lower is decided by which trust-region steps happen to be
// accepted. Here each corner is solved from the suite's guess and from kPerturbed copies of it
// (every coordinate of q_1..q_N moved by a uniform draw in [-1e-3, 1e-3]), with both derivative
// methods from the same guess, at the suite's iteration limit and at ten times it. A pair counts
// for analytic when its final cost is lower; the counts are printed with the two-sided 95 % band
// of a sign test ("no difference": Binomial(pairs, 1/2)). Asserted: every solve ends with a valid
// status, a finite trajectory and a cost no worse than its guess's. The guess of seed 0 is the
// suite's own, so its pair reproduces the suite's printed costs.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "solver/stiff_corners.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

constexpr int kPerturbed = 39;  // guesses per corner besides the suite's own

struct Outcome {
  double cost{0.0};
  double violation{0.0};
};

// The guess moved by uniform draws in [-1e-3, 1e-3] on every coordinate of q_1..q_N (q_0 is
// the initial state; quaternions are normalized by the solver). seed 0: the guess itself.
std::vector<Eigen::VectorXd> Perturbed(std::vector<Eigen::VectorXd> q, int seed) {
  if (seed == 0) return q;
  test::Random random(static_cast<std::uint32_t>(seed));
  for (size_t k = 1; k < q.size(); ++k) q[k] += random.Vector(q[k].size(), -1e-3, 1e-3);
  return q;
}

Outcome Solve(const Model& model, const ProblemDefinition& p, const SolverOptions& o,
              const std::vector<Eigen::VectorXd>& guess) {
  TrajectoryOptimizer optimizer(model, p, o);
  Trajectory solution;
  const SolverSummary s = optimizer.Solve(guess, &solution);
  EXPECT_TRUE(s.termination == TerminationType::kConverged ||
              s.termination == TerminationType::kMaxIterations ||
              (s.termination == TerminationType::kFailure && !s.message.empty()));
  EXPECT_TRUE(std::isfinite(s.final_cost) && std::isfinite(s.constraint_violation));
  EXPECT_LE(s.final_cost, s.initial_cost * (1 + 1e-12) + 1e-12);
  for (const Eigen::VectorXd& q : solution.q) EXPECT_TRUE(q.allFinite());
  return {s.final_cost, s.constraint_violation};
}

// One corner: a model, its problem and options, and the guess to perturb.
struct StiffCorner {
  std::string name;
  Model model;
  ProblemDefinition problem;
  SolverOptions options;
  std::vector<Eigen::VectorXd> guess;
};

std::vector<StiffCorner> MakeCorners() {
  std::vector<StiffCorner> corners;
  const Model ball = test::BallAndFinger();
  const auto add_ball = [&](const std::string& name, double stiffness, double height,
                            ConstraintMethod method) {
    test::Corner c;
    c.stiffness = stiffness;
    c.ball_height = height;
    c.method = method;
    const ProblemDefinition p = test::CornerProblem(ball, c);
    corners.push_back({name, ball, p, test::CornerOptions(c, c.iterations, true),
                       std::vector<Eigen::VectorXd>(c.N + 1, p.q_init)});
  };
  add_ball("ball + finger, k = 2e8 (penalty)", 2e8, 0.049, ConstraintMethod::kPenalty);
  add_ball("ball + finger, k = 2e8, Lagrange", 2e8, 0.049, ConstraintMethod::kLagrangeMultipliers);
  add_ball("ball 4 cm deep, k = 2e6", 2e6, 0.01, ConstraintMethod::kPenalty);
  const auto add_example = [&](const std::string& name, double smoothing) {
    const ExampleConfig config = test::ExampleAtCorner(name, 2e8, 1e-3, smoothing, 0.05);
    SolverOptions o = config.solver;
    o.max_iterations = 20;  // the suite's limit for the examples
    corners.push_back(
        {name + ", k = 2e8", config.model, config.problem, o, MakeInitialGuess(config)});
  };
  add_example("spinner", 1e-2);
  add_example("hopper", 1e-5);
  add_example("quadruped", 1e-5);
  return corners;
}

TEST(StiffCornerStatistics, PairedComparisonOfDerivativeMethods) {
  const std::vector<StiffCorner> corners = MakeCorners();
  for (int scale : {1, 10}) {
    int pairs = 0, lower_cost = 0, lower_both = 0;
    for (const StiffCorner& c : corners) {
      SCOPED_TRACE(c.name + ", iterations x" + std::to_string(scale));
      int corner_cost = 0, corner_both = 0;
      std::vector<double> log_ratio;
      for (int seed = 0; seed <= kPerturbed; ++seed) {
        const std::vector<Eigen::VectorXd> guess = Perturbed(c.guess, seed);
        SolverOptions o = c.options;
        o.max_iterations *= scale;
        o.derivative_method = DerivativeMethod::kAnalytic;
        const Outcome analytic = Solve(c.model, c.problem, o, guess);
        o.derivative_method = DerivativeMethod::kForwardDifferences;
        const Outcome forward = Solve(c.model, c.problem, o, guess);
        corner_cost += analytic.cost < forward.cost ? 1 : 0;
        corner_both +=
            analytic.cost < forward.cost && analytic.violation < forward.violation ? 1 : 0;
        log_ratio.push_back(std::log10(analytic.cost / forward.cost));
      }
      std::sort(log_ratio.begin(), log_ratio.end());
      std::printf(
          "[stiff-stat] x%-2d %-34s analytic lower: cost %2d/%d, cost and violation %2d/%d, "
          "median log10(analytic/forward cost) %+.3f\n",
          scale, c.name.c_str(), corner_cost, kPerturbed + 1, corner_both, kPerturbed + 1,
          log_ratio[log_ratio.size() / 2]);
      pairs += kPerturbed + 1;
      lower_cost += corner_cost;
      lower_both += corner_both;
    }
    // Sign test: under "no difference" the count is Binomial(pairs, 1/2), whose two-sided 95 %
    // band is pairs / 2 -+ 1.96 sqrt(pairs) / 2 by the normal approximation.
    const double half_width = 1.96 * 0.5 * std::sqrt(static_cast<double>(pairs));
    std::printf(
        "[stiff-stat] x%-2d all corners: analytic lower cost in %d of %d pairs, cost and "
        "violation in %d (no difference: %.1f to %.1f)\n",
        scale, lower_cost, pairs, lower_both, 0.5 * pairs - half_width, 0.5 * pairs + half_width);
  }
}

}  // namespace
}  // namespace idto
