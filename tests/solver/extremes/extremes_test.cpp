// Stability at the extremes (label "extremes"): solves at the corners of the parameter space end
// with a valid status (converged, max iterations, or a reported failure), never return NaN, and
// never crash. Which corners converge is printed (RecordProperty) for docs/tradeoffs.md.

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

// The iteration limit of a corner: `fallback`, or IDTO_EXTREMES_ITERATIONS when set (to rerun
// the corners longer, as docs/solver.md's 300-iteration comparison does).
int CornerIterations(int fallback) {
  const char* env = std::getenv("IDTO_EXTREMES_ITERATIONS");
  return env != nullptr && std::atoi(env) > 0 ? std::atoi(env) : fallback;
}

// SolverOptions::trial_derivatives for the corners: the default, or off when
// IDTO_EXTREMES_TRIAL_DERIVATIVES=0 (to compare the two at the corners).
bool CornerTrialDerivatives() {
  const char* env = std::getenv("IDTO_EXTREMES_TRIAL_DERIVATIVES");
  return env == nullptr || std::string(env) != "0";
}

using test::BallAndFinger;

struct Corner {
  std::string name;
  double stiffness{500}, smoothing{0.01}, stiction{0.1};
  double dt{0.05};
  int N{20};
  double weight_scale{1.0};
  double ball_height{0.049};  // deep penetration when well below 0.05
  double ball_speed{0.0};
  double quaternion_w{1.0};  // near -1 / 0 for sign-flip corners
  ConstraintMethod method{ConstraintMethod::kPenalty};
  DerivativeMethod derivatives{DerivativeMethod::kAnalytic};
  int iterations{30};
};

SolverSummary RunCorner(const Corner& c) {
  SCOPED_TRACE(c.name);
  const Model model = BallAndFinger();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, c.dt, c.N);
  const double qw = c.quaternion_w, qx = std::sqrt(std::max(0.0, 1.0 - qw * qw));
  p.q_init << qw, qx, 0, 0, 0.0, 0.0, c.ball_height, 0.5, -1.2;
  p.v_init.setZero();
  p.v_init(3) = c.ball_speed;
  p.Qq.setConstant(1.0 * c.weight_scale);
  p.Qv.setConstant(0.1 * c.weight_scale);
  p.R.setConstant(0.1 * c.weight_scale);
  p.R.head<6>().setConstant(100.0 * c.weight_scale);
  p.Qfq.setConstant(10.0 * c.weight_scale);
  p.Qfv.setConstant(1.0 * c.weight_scale);
  Eigen::VectorXd target = p.q_init;
  target(4) = 0.2;
  target(6) = 0.05;
  p.SetConstantNominal(target, Eigen::VectorXd::Zero(model.nv()));
  p.contact.parameters.stiffness = c.stiffness;
  p.contact.parameters.smoothing = c.smoothing;
  p.contact.parameters.stiction_velocity = c.stiction;
  SolverOptions o;
  o.max_iterations = CornerIterations(c.iterations);
  o.trial_derivatives = CornerTrialDerivatives();
  o.constraint_method = c.method;
  o.derivative_method = c.derivatives;
  TrajectoryOptimizer opt(model, p, o);
  Trajectory sol;
  const SolverSummary s = opt.Solve(std::vector<Eigen::VectorXd>(c.N + 1, p.q_init), &sol);
  EXPECT_EQ(sol.q.size(), static_cast<size_t>(c.N + 1));
  for (size_t k = 0; k < sol.q.size(); ++k) {
    EXPECT_TRUE(sol.q[k].allFinite()) << "q[" << k << "]";
    EXPECT_TRUE(sol.v[k].allFinite()) << "v[" << k << "]";
    EXPECT_TRUE(sol.tau[k].allFinite()) << "tau[" << k << "]";
  }
  EXPECT_TRUE(s.termination == TerminationType::kConverged ||
              s.termination == TerminationType::kMaxIterations ||
              s.termination == TerminationType::kFailure);
  if (s.termination == TerminationType::kFailure) {
    EXPECT_FALSE(s.message.empty());
  }
  EXPECT_TRUE(std::isfinite(s.final_cost));
  EXPECT_LE(s.final_cost, s.initial_cost * (1 + 1e-12) + 1e-12);  // never worse than the guess
  ::testing::Test::RecordProperty(c.name, TerminationTypeName(s.termination) + " after " +
                                              std::to_string(s.iterations) + " iterations");
  std::printf("[corner] %-34s %-8s %-15s it=%3d cost %.3e -> %.3e viol %.2e\n", c.name.c_str(),
              c.derivatives == DerivativeMethod::kAnalytic ? "analytic" : "forward",
              TerminationTypeName(s.termination).c_str(), s.iterations, s.initial_cost,
              s.final_cost, s.constraint_violation);
  if (!s.message.empty()) std::printf("[corner]   message: %s\n", s.message.c_str());
  return s;
}

// A stiff corner with both derivative methods: analytic (the default) and forward differences.
void RunCornerBothMethods(Corner c) {
  c.derivatives = DerivativeMethod::kAnalytic;
  RunCorner(c);
  c.derivatives = DerivativeMethod::kForwardDifferences;
  RunCorner(c);
}

TEST(Extremes, Stiffness) {
  for (double k : {2e2, 2e4, 2e6, 2e8}) {
    Corner c;
    c.name = "stiffness " + std::to_string(k);
    c.stiffness = k;
    RunCornerBothMethods(c);
  }
}

TEST(Extremes, StictionAndSmoothing) {
  for (double vs : {1e-3, 1e-2}) {
    for (double sigma : {1e-5, 1e-3}) {
      Corner c;
      c.name = "stiction " + std::to_string(vs) + " smoothing " + std::to_string(sigma);
      c.stiction = vs;
      c.smoothing = sigma;
      RunCorner(c);
    }
  }
}

TEST(Extremes, TimeStepsAndHorizons) {
  for (auto [dt, N] : {std::pair{1e-3, 20}, std::pair{0.2, 10}, std::pair{0.05, 320}}) {
    Corner c;
    c.name = "dt " + std::to_string(dt) + " N " + std::to_string(N);
    c.dt = dt;
    c.N = N;
    c.iterations = N > 100 ? 5 : 30;
    RunCorner(c);
  }
}

TEST(Extremes, LargeWeights) {
  for (double w : {1e4, 1e8}) {
    Corner c;
    c.name = "weights x" + std::to_string(w);
    c.weight_scale = w;
    RunCorner(c);
  }
}

TEST(Extremes, DeepPenetrationAndZeroVelocityContacts) {
  Corner deep;
  deep.name = "ball 4 cm into the ground";
  deep.ball_height = 0.01;
  deep.stiffness = 2e6;
  RunCornerBothMethods(deep);
  Corner touching;
  touching.name = "touching exactly, at rest";
  touching.ball_height = 0.05;
  touching.smoothing = 1e-5;
  RunCorner(touching);
  Corner sliding;
  sliding.name = "sliding at 1 m/s";
  sliding.ball_speed = 1.0;
  sliding.stiction = 1e-3;
  RunCorner(sliding);
}

TEST(Extremes, QuaternionsNearTheSignFlip) {
  for (double w : {-1.0, -0.999999, 1e-9, -1e-9}) {
    Corner c;
    c.name = "quaternion w " + std::to_string(w);
    c.quaternion_w = w;
    RunCorner(c);
  }
}

TEST(Extremes, LagrangeMultipliersAtStiffCorners) {
  for (double k : {2e4, 2e8}) {
    Corner c;
    c.name = "lagrange stiffness " + std::to_string(k);
    c.stiffness = k;
    c.method = ConstraintMethod::kLagrangeMultipliers;
    RunCornerBothMethods(c);
  }
}

// The examples themselves at the stiff, sharp corners (their models, weights and horizons):
// valid status, finite trajectory, and the same answer bit for bit on 1 and 2 threads.
void RunExampleCorner(const std::string& name, double stiffness, double stiction, double smoothing,
                      double dt, DerivativeMethod derivatives = DerivativeMethod::kAnalytic) {
  SCOPED_TRACE(name + " k " + std::to_string(stiffness) + " v_s " + std::to_string(stiction) +
               " sigma " + std::to_string(smoothing) + " dt " + std::to_string(dt));
  const std::vector<std::string> dirs{IDTO_SOURCE_DIR};
  ExampleConfig config = LoadExampleConfig(FindExampleConfig(name, dirs), dirs);
  ProblemDefinition& p = config.problem;
  p.contact.parameters.stiffness = stiffness;
  p.contact.parameters.stiction_velocity = stiction;
  p.contact.parameters.smoothing = smoothing;
  p.time_step = dt;
  std::vector<Trajectory> solutions(2);
  std::vector<SolverSummary> summaries;
  for (int threads : {1, 2}) {
    SolverOptions o = config.solver;
    o.max_iterations = CornerIterations(20);
    o.trial_derivatives = CornerTrialDerivatives();
    o.num_threads = threads;
    o.derivative_method = derivatives;
    TrajectoryOptimizer opt(config.model, p, o);
    summaries.push_back(opt.Solve(MakeInitialGuess(config), &solutions[threads - 1]));
  }
  const SolverSummary& s = summaries[0];
  EXPECT_TRUE(s.termination == TerminationType::kConverged ||
              s.termination == TerminationType::kMaxIterations ||
              (s.termination == TerminationType::kFailure && !s.message.empty()));
  EXPECT_TRUE(std::isfinite(s.final_cost));
  EXPECT_LE(s.final_cost, s.initial_cost * (1 + 1e-12) + 1e-12);
  for (size_t k = 0; k < solutions[0].q.size(); ++k) {
    ASSERT_TRUE(solutions[0].q[k].allFinite()) << "q[" << k << "]";
    ASSERT_TRUE(solutions[0].tau[k].allFinite()) << "tau[" << k << "]";
    EXPECT_TRUE(solutions[0].q[k] == solutions[1].q[k]) << "q[" << k << "] depends on threads";
  }
  EXPECT_EQ(summaries[0].final_cost, summaries[1].final_cost);
  std::printf(
      "[corner] %-12s k %.0e v_s %.0e sigma %.0e dt %.3f %-8s: %-15s it=%3d cost %.3e -> %.3e "
      "viol %.2e\n",
      name.c_str(), stiffness, stiction, smoothing, dt,
      derivatives == DerivativeMethod::kAnalytic ? "analytic" : "forward",
      TerminationTypeName(s.termination).c_str(), s.iterations, s.initial_cost, s.final_cost,
      s.constraint_violation);
  if (!s.message.empty()) std::printf("[corner]   message: %s\n", s.message.c_str());
}

TEST(Extremes, ExamplesAtTheStiffSharpCorners) {
  // The k = 2e8 corners with both derivative methods (docs/solver.md compares them).
  for (DerivativeMethod m : {DerivativeMethod::kAnalytic, DerivativeMethod::kForwardDifferences}) {
    RunExampleCorner("spinner", 2e8, 1e-3, 1e-2, 0.05, m);  // Table 4's hardest cell
    RunExampleCorner("hopper", 2e8, 1e-3, 1e-5, 0.05, m);
    RunExampleCorner("quadruped", 2e8, 1e-3, 1e-5, 0.05, m);
  }
  RunExampleCorner("spinner", 2e8, 1e-3, 1e-5, 0.05);  // no force at a distance: no contact
  RunExampleCorner("spinner", 2e2, 1e-3, 1e-5, 0.2);
  RunExampleCorner("quadruped", 2e3, 5e-2, 1e-2, 1e-3);
}

}  // namespace
}  // namespace idto
