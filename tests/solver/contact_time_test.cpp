// IterationSummary::time_contact: the share of the derivative and cost phases spent in contact
// evaluation. Finite and non-negative, zero without contact pairs, positive with them, bounded by
// the phases it belongs to (times the number of threads: it is summed over threads), and in the
// summary's report and CSV.

#include <cmath>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using ::testing::HasSubstr;

SolverSummary SolveFew(const Model& model, const ProblemDefinition& p, int threads) {
  SolverOptions o;
  o.max_iterations = 4;
  o.fixed_iterations = true;
  o.num_threads = threads;
  TrajectoryOptimizer opt(model, p, o);
  Trajectory sol;
  return opt.Solve(std::vector<Eigen::VectorXd>(p.num_steps + 1, p.q_init), &sol);
}

void ExpectWithinPhases(const IterationSummary& it, int threads) {
  EXPECT_TRUE(std::isfinite(it.time_contact));
  EXPECT_GE(it.time_contact, 0.0);
  // Contact runs inside the derivative and cost phases, on at most `threads` threads at once
  // (slack for the conversion of the tick counter).
  EXPECT_LE(it.time_contact, threads * (it.time_derivatives + it.time_cost) * 1.01 + 1e-6);
}

TEST(SolverContactTime, ZeroWithoutContactGeometry) {
  const Model model = test::Pendulum();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 10);
  p.Qfq.setConstant(10.0);
  p.SetConstantNominal(Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Zero(1));
  const SolverSummary s = SolveFew(model, p, 1);
  ASSERT_EQ(s.log.size(), 4u);
  for (const IterationSummary& it : s.log) EXPECT_EQ(it.time_contact, 0.0);
}

TEST(SolverContactTime, ZeroWhenContactIsDisabled) {
  const Model model = test::BallAndFinger();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 8);
  p.q_init << 1, 0, 0, 0, 0.0, 0.0, 0.049, 0.5, -1.2;
  p.R.setConstant(0.1);
  p.SetConstantNominal(p.q_init, Eigen::VectorXd::Zero(model.nv()));
  p.enable_contact = false;
  const SolverSummary s = SolveFew(model, p, 1);
  ASSERT_FALSE(s.log.empty());
  for (const IterationSummary& it : s.log) EXPECT_EQ(it.time_contact, 0.0);
}

TEST(SolverContactTime, PositiveWithContactOnOneAndTwoThreads) {
  const Model model = test::BallAndFinger();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 8);
  p.q_init << 1, 0, 0, 0, 0.0, 0.0, 0.049, 0.5, -1.2;  // ball slightly in the ground
  p.Qq.setConstant(1.0);
  p.R.setConstant(0.1);
  p.R.head<6>().setConstant(100.0);
  Eigen::VectorXd target = p.q_init;
  target(4) = 0.2;
  p.SetConstantNominal(target, Eigen::VectorXd::Zero(model.nv()));
  p.contact.parameters.stiffness = 500.0;
  for (int threads : {1, 2}) {
    const SolverSummary s = SolveFew(model, p, threads);
    ASSERT_EQ(s.log.size(), 4u) << s.message;
    double total = 0.0;
    for (const IterationSummary& it : s.log) {
      ExpectWithinPhases(it, threads);
      // Every iteration evaluates a trial point with contact.
      EXPECT_GT(it.time_contact, 0.0);
      total += it.time_contact;
    }
    EXPECT_GT(total, 0.0);
    EXPECT_THAT(s.FullReport(), HasSubstr("contact evaluation"));
    EXPECT_THAT(s.ToCsv(), HasSubstr(",time_contact,correction_norm,growth_guard\n"));
  }
}

}  // namespace
}  // namespace idto
