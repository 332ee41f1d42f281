// SolverOptions::constraint_correction (Lagrange method): a dogleg step short of the Newton step is
// moved onto the linearized constraints h + A p = 0. Checked here: the accepted step satisfies
// them (against the dense Jacobian of the transcription) when the correction is within its bound,
// and does not without the correction; the log's correction_norm keeps the bound and is zero where
// no correction applies; and on the paper's Table 4 problem (the reference's spinner, the paper's
// solver settings) the corrected solver ends at or below the paper's violation where the
// uncorrected one stays above it.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "examples/example_test_support.hpp"
#include "idto/config/config.hpp"
#include "idto/problem/transcription.hpp"
#include "idto/solver/trajectory_optimizer.hpp"

namespace idto {
namespace {

using test::LoadExample;

// |h + A p| / |h| for one iteration of the solver from q with trust radius `radius`: h and A at q
// (the transcription's own constraints and dense Jacobian), p the accepted step. Sets *accepted
// and *correction (the log's correction_norm and trust radius) for the caller's checks.
double LinearizedResidualOfOneStep(const ExampleConfig& config,
                                   const std::vector<Eigen::VectorXd>& q, double radius,
                                   double correction, bool* accepted, IterationSummary* log) {
  SolverOptions options = config.solver;
  options.constraint_method = ConstraintMethod::kLagrangeMultipliers;
  options.max_iterations = 1;
  options.initial_trust_radius = radius;
  options.constraint_correction = correction;
  TrajectoryOptimizer optimizer(config.model, config.problem, options);
  Trajectory solution;
  const SolverSummary summary = optimizer.Solve(q, &solution);
  *log = summary.log.at(0);
  *accepted = log->accepted;

  Transcription transcription(config.model, config.problem);
  TrajectoryState state = transcription.MakeState();
  state.q = q;
  state.q[0] = config.problem.q_init;
  transcription.Evaluate(&state);
  TrajectoryDerivatives derivatives = transcription.MakeDerivatives();
  transcription.CalcDerivatives(state, &derivatives);
  Eigen::VectorXd h;
  transcription.CalcConstraints(state, &h);
  Eigen::MatrixXd At;
  transcription.CalcDenseConstraintJacobianTranspose(derivatives, &At);
  const int N = transcription.num_steps(), nq = transcription.nq();
  Eigen::VectorXd p(N * nq);
  for (int k = 1; k <= N; ++k) p.segment((k - 1) * nq, nq) = solution.q[k] - state.q[k];
  return (h + At.transpose() * p).norm() / h.norm();
}

// The spinner a few iterations into its solve (in contact, h != 0), then one step with a radius
// inside the Newton step (a dogleg step) and a bound (10 Δ) that leaves the correction whole.
TEST(ConstraintCorrection, CorrectedStepMeetsTheLinearizedConstraints) {
  ExampleConfig config = LoadExample("spinner");
  config.solver.max_iterations = 8;
  TrajectoryOptimizer warm(config.model, config.problem, config.solver);
  Trajectory start;
  warm.Solve(MakeInitialGuess(config), &start);

  bool accepted = false;
  IterationSummary corrected, plain;
  const double with =
      LinearizedResidualOfOneStep(config, start.q, 0.3, 10.0, &accepted, &corrected);
  ASSERT_TRUE(accepted);
  ASSERT_NE(corrected.step_type, DoglegStep::kNewton);
  ASSERT_GT(corrected.correction_norm, 0.0);
  ASSERT_LT(corrected.correction_norm, 10.0 * corrected.trust_radius);  // within the bound
  EXPECT_LT(with, 1e-9);  // the linearized constraints hold (to the unrefined solve's accuracy)

  const double without = LinearizedResidualOfOneStep(config, start.q, 0.3, 0.0, &accepted, &plain);
  ASSERT_TRUE(accepted);
  EXPECT_EQ(plain.correction_norm, 0.0);
  EXPECT_GT(without, 1e-2);  // the dogleg step alone leaves part of h
}

// The bound |D⁻¹c| <= constraint_correction × Δ, and no correction where none applies.
TEST(ConstraintCorrection, LogKeepsTheBoundAndZeroWhereNoneApplies) {
  for (const std::string name : {"spinner", "hopper", "acrobot"}) {
    SCOPED_TRACE(name);
    ExampleConfig config = LoadExample(name);
    config.solver.max_iterations = 40;
    for (const ConstraintMethod method :
         {ConstraintMethod::kLagrangeMultipliers, ConstraintMethod::kPenalty}) {
      config.solver.constraint_method = method;
      TrajectoryOptimizer optimizer(config.model, config.problem, config.solver);
      const SolverSummary s = optimizer.Solve(MakeInitialGuess(config), nullptr);
      int corrected = 0;
      for (const IterationSummary& it : s.log) {
        EXPECT_LE(it.correction_norm,
                  config.solver.constraint_correction * it.trust_radius * (1.0 + 1e-12));
        if (method == ConstraintMethod::kPenalty || it.step_type == DoglegStep::kNewton) {
          EXPECT_EQ(it.correction_norm, 0.0) << "iteration " << it.iteration;
        }
        corrected += it.correction_norm > 0.0;
      }
      if (method == ConstraintMethod::kLagrangeMultipliers) {
        EXPECT_GT(corrected, 0);
      }
    }
  }
}

// The paper's Table 4 settings (docs/tradeoffs.md §1: the reference's spinner model, Lagrange
// multipliers, Δ₀ = 10, Δ_max = 1e5, η = 0, 500 iterations, weights doubled) in three cells.
double Table4Violation(double k, double vs, double correction) {
  const ExampleConfig config = test::LoadReferenceSpinner();
  ProblemDefinition problem = config.problem;
  problem.contact.parameters.stiffness = k;
  problem.contact.parameters.stiction_velocity = vs;
  problem.Qq *= 2.0;
  problem.Qv *= 2.0;
  problem.R *= 2.0;
  problem.Qfq *= 2.0;
  problem.Qfv *= 2.0;
  SolverOptions o = config.solver;
  o.constraint_method = ConstraintMethod::kLagrangeMultipliers;
  o.max_iterations = 500;
  o.fixed_iterations = true;
  o.initial_trust_radius = 10.0;
  o.max_trust_radius = 1e5;
  o.acceptance_ratio = 0.0;
  o.constraint_correction = correction;
  ExampleConfig for_guess = config;
  for_guess.problem = problem;
  TrajectoryOptimizer optimizer(config.model, problem, o);
  const SolverSummary s = optimizer.Solve(MakeInitialGuess(for_guess), nullptr);
  return std::sqrt(s.constraint_violation);
}

TEST(ConstraintCorrection, Table4CellsReachThePaper) {
  struct Cell {
    double k, vs, paper;
  };
  for (const Cell& c :
       {Cell{2e2, 0.05, 6.1e-8}, Cell{2e6, 0.005, 1.0e-3}, Cell{2e8, 0.05, 2.8e-7}}) {
    SCOPED_TRACE("k " + std::to_string(c.k) + ", v_s " + std::to_string(c.vs));
    const double corrected = Table4Violation(c.k, c.vs, 0.5);
    const double plain = Table4Violation(c.k, c.vs, 0.0);
    EXPECT_LE(corrected, c.paper);
    EXPECT_GT(plain, c.paper);  // what the correction changes: without it, above the paper
  }
}

}  // namespace
}  // namespace idto
