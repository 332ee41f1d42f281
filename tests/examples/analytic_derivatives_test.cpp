// The analytic derivatives on every example:
//  - d tau / d q and d tau / d v of inverse dynamics with the example's contact (its engine,
//    parameters and pruning) against forward-mode AD (tests/support/contact_oracle.hpp) at
//    random states around the initial guess, in and out of contact, sliding and sticking;
//  - the transcription's blocks d tau_j / d q_s (the chain rule through v and a, N+ of the
//    quaternions) against central differences, and the gradient against a central difference of
//    the cost along random directions.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "examples/example_test_support.hpp"
#include "idto/idto.hpp"
#include "support/contact_oracle.hpp"
#include "support/random.hpp"

namespace idto {
namespace {

using test::LoadExample;

const std::vector<std::string> kExamples = {
    "pendulum",        "acrobot", "spinner",  "hopper",        "quadruped",
    "quadruped_hills", "allegro", "bimanual", "bimanual_lift", "bimanual_balance"};

double RelativeError(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double floor) {
  return (A - B).norm() / std::max(B.norm(), floor);
}

TEST(AnalyticDerivatives, EveryExampleMatchesAutoDiff) {
  test::Random rng(3);
  for (const std::string& name : kExamples) {
    SCOPED_TRACE(name);
    const ExampleConfig config = LoadExample(name);
    const Model& model = config.model;
    const Transcription t(model, config.problem);
    const std::vector<Eigen::VectorXd> guess = MakeInitialGuess(config);
    const int N = static_cast<int>(guess.size()) - 1;
    int with_contact = 0;
    for (int trial = 0; trial < 6; ++trial) {
      const int k = 1 + trial * (N - 1) / 5;
      Eigen::VectorXd q = guess[k] + rng.Vector(model.nq(), -0.02, 0.02);
      NormalizeQuaternions(model, &q);
      // Sticking (slow) and sliding (fast) velocities.
      const double speed = trial % 2 == 0 ? 1e-3 : 0.5;
      const Eigen::VectorXd v = rng.Vector(model.nv(), -speed, speed);
      const Eigen::VectorXd a = rng.Vector(model.nv(), -1.0, 1.0);
      SCOPED_TRACE("step " + std::to_string(k) + " speed " + std::to_string(speed));
      Data data(model);
      const double floor = MassMatrix(model, q, &data).norm();
      if (t.engine() == nullptr) {
        ComputeRneaDerivatives(model, q, v, a, &data);
        continue;  // no contact: covered by the RNEA derivative tests
      }
      std::vector<int> pairs;
      const test::TauDerivatives an =
          test::AnalyticTauWithContact(model, *t.engine(), q, v, a, &pairs);
      const test::TauDerivatives ad =
          test::AutoDiffTauWithContact(model, *t.engine(), pairs, q, v, a);
      with_contact += an.num_pairs > 0 ? 1 : 0;
      EXPECT_LE(RelativeError(an.tau, ad.tau, floor), 1e-12);
      EXPECT_LE(RelativeError(an.dtau_dq, ad.dtau_dq, floor), 1e-12);
      EXPECT_LE(RelativeError(an.dtau_dv, ad.dtau_dv, floor), 1e-12);
    }
    if (t.engine() != nullptr) {
      EXPECT_GT(with_contact, 0);
    }
  }
}

// Blocks of the transcription: analytic against central differences.
TEST(AnalyticDerivatives, TranscriptionBlocksMatchCentralDifferences) {
  for (const std::string& name : kExamples) {
    SCOPED_TRACE(name);
    const ExampleConfig config = LoadExample(name);
    Transcription t(config.model, config.problem);
    TrajectoryState s = t.MakeState();
    // The initial guess moved off the branch points of the contact law: interpolated guesses
    // slide the feet with v_n = 0 exactly, where d(v_n) is C1 but its second derivative jumps,
    // and a central difference there has an O(h) error (measured: 1.5e-6 at h = 1e-7, 1.5e-5
    // at 1e-6 on the quadruped, while the analytic block is the exact derivative).
    s.q = MakeInitialGuess(config);
    test::Random noise(11);
    for (int k = 1; k <= t.num_steps(); ++k) {
      s.q[k] += noise.Vector(t.nq(), -2e-3, 2e-3);
      NormalizeQuaternions(config.model, &s.q[k]);
    }
    t.Evaluate(&s);
    TrajectoryDerivatives analytic = t.MakeDerivatives(), central = t.MakeDerivatives();
    t.SetDerivativeMethod(DerivativeMethod::kAnalytic, 0.0);
    t.CalcDerivatives(s, &analytic);
    // A relative step of 1e-7, not the default cbrt(eps) ~ 6e-6: at the examples' initial
    // guesses (feet sliding at 0.5 m/s against v_s = 0.05 m/s) the default step's truncation
    // error reaches 1e-4 relative on the hopper, while 1e-7 agrees with the analytic blocks to
    // about 1e-8 (measured).
    t.SetDerivativeMethod(DerivativeMethod::kCentralDifferences, 1e-7);
    t.CalcDerivatives(s, &central);
    const int N = t.num_steps();
    double scale = 0.0;
    for (int k = 0; k < N; ++k) scale = std::max(scale, central.dtau_dqp[k].norm());
    for (int k = 0; k < N; ++k) {
      SCOPED_TRACE("step " + std::to_string(k));
      EXPECT_LE(RelativeError(analytic.dtau_dqp[k], central.dtau_dqp[k], 1e-3 * scale), 1e-6);
      if (k >= 1) {
        EXPECT_LE(RelativeError(analytic.dtau_dq[k], central.dtau_dq[k], 1e-3 * scale), 1e-6);
      }
      if (k >= 2) {
        EXPECT_LE(RelativeError(analytic.dtau_dqm[k], central.dtau_dqm[k], 1e-3 * scale), 1e-6);
      }
    }
    // The gradient along random directions against a central difference of the cost.
    Eigen::VectorXd g(N * t.nq());
    t.CalcGradient(s, analytic, &g);
    test::Random rng(7);
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd dir = rng.Vector(N * t.nq());
      const double h = 1e-6;
      TrajectoryState sp = s, sm = s;
      for (int k = 1; k <= N; ++k) {
        sp.q[k] += h * dir.segment((k - 1) * t.nq(), t.nq());
        sm.q[k] -= h * dir.segment((k - 1) * t.nq(), t.nq());
      }
      const double fd = (t.Evaluate(&sp) - t.Evaluate(&sm)) / (2.0 * h);
      EXPECT_NEAR(g.dot(dir), fd, 1e-5 * (std::abs(fd) + g.norm() * dir.norm() * 1e-3));
    }
  }
}

// Transcription::EvaluateWithDerivatives (tau from the RNEA derivatives' pass, the contact on
// its kinematics) against Evaluate followed by CalcDerivatives: the same v and a bit for bit,
// tau, contact forces, cost and every derivative block equal to round-off, on every example at
// a perturbed initial guess (in and out of contact) and at one moved further (other contacts);
// and bitwise the same on 1 and 2 threads.
TEST(AnalyticDerivatives, EvaluationWithDerivativesMatchesSeparatePasses) {
  double worst_tau = 0.0, worst_block = 0.0;
  int steps_in_contact = 0;
  for (const std::string& name : kExamples) {
    SCOPED_TRACE(name);
    const ExampleConfig config = LoadExample(name);
    Transcription t(config.model, config.problem);
    ASSERT_TRUE(t.CanEvaluateWithDerivatives());
    test::Random noise(5);
    for (const double amplitude : {2e-3, 3e-2}) {
      SCOPED_TRACE("noise " + std::to_string(amplitude));
      TrajectoryState separate = t.MakeState();
      separate.q = MakeInitialGuess(config);
      for (int k = 1; k <= t.num_steps(); ++k) {
        separate.q[k] += noise.Vector(t.nq(), -amplitude, amplitude);
        NormalizeQuaternions(config.model, &separate.q[k]);
      }
      TrajectoryState fused = separate, fused2 = separate;
      TrajectoryDerivatives d_separate = t.MakeDerivatives(), d_fused = t.MakeDerivatives();
      TrajectoryDerivatives d_fused2 = t.MakeDerivatives();
      t.SetNumThreads(1);
      const double cost = t.Evaluate(&separate);
      t.CalcDerivatives(separate, &d_separate);
      const double cost_fused = t.EvaluateWithDerivatives(&fused, &d_fused);
      t.SetNumThreads(2);
      const double cost_fused2 = t.EvaluateWithDerivatives(&fused2, &d_fused2);
      EXPECT_EQ(cost_fused, cost_fused2);
      EXPECT_NEAR(cost_fused, cost, 1e-12 * std::max(1.0, std::abs(cost)));
      const int N = t.num_steps();
      // tau's scale: the largest generalized force of the trajectory (contact and gravity
      // terms cancel in tau, so its round-off is relative to the terms, not to tau itself).
      double scale = 1.0;
      for (int k = 0; k < N; ++k) scale = std::max(scale, separate.tau[k].norm());
      for (int k = 0; k < N; ++k) {
        SCOPED_TRACE("step " + std::to_string(k));
        EXPECT_TRUE(fused.v[k + 1] == separate.v[k + 1] && fused.a[k] == separate.a[k]);
        EXPECT_TRUE(fused.tau[k] == fused2.tau[k]);
        const double e_tau = (fused.tau[k] - separate.tau[k]).norm() / scale;
        worst_tau = std::max(worst_tau, e_tau);
        EXPECT_LE(e_tau, 1e-13);
        if (t.engine() != nullptr) {
          EXPECT_EQ(fused.contact[k].num_active, separate.contact[k].num_active);
          steps_in_contact += separate.contact[k].num_active > 0;
          EXPECT_LE((fused.contact[k].F_ext - separate.contact[k].F_ext).norm(),
                    1e-10 * std::max(1.0, separate.contact[k].F_ext.norm()));
        }
        using Blocks = std::vector<Eigen::MatrixXd> TrajectoryDerivatives::*;
        for (const Blocks blocks :
             {&TrajectoryDerivatives::dtau_dqm, &TrajectoryDerivatives::dtau_dq,
              &TrajectoryDerivatives::dtau_dqp}) {
          const Eigen::MatrixXd& a = (d_fused.*blocks)[k];
          const Eigen::MatrixXd& b = (d_separate.*blocks)[k];
          EXPECT_TRUE(a == (d_fused2.*blocks)[k]);
          const double e = RelativeError(a, b, 1.0);
          worst_block = std::max(worst_block, e);
          EXPECT_LE(e, 1e-12);
        }
      }
    }
  }
  EXPECT_GT(steps_in_contact, 100);
  std::printf(
      "worst tau difference %.1e (of the largest |tau|), worst block %.1e, %d steps in "
      "contact\n",
      worst_tau, worst_block, steps_in_contact);
}

// Finite differences have no evaluation with derivatives: the transcription says so and the
// call throws instead of computing something else.
TEST(AnalyticDerivatives, FiniteDifferencesDoNotEvaluateWithDerivatives) {
  const ExampleConfig config = LoadExample("spinner");
  Transcription t(config.model, config.problem);
  t.SetDerivativeMethod(DerivativeMethod::kForwardDifferences, 0.0);
  EXPECT_FALSE(t.CanEvaluateWithDerivatives());
  TrajectoryState s = t.MakeState();
  s.q = MakeInitialGuess(config);
  TrajectoryDerivatives d = t.MakeDerivatives();
  EXPECT_THROW(t.EvaluateWithDerivatives(&s, &d), std::logic_error);
}

// The solver with trial derivatives (the default) against separate passes: the same accepted
// and rejected steps and the same iterates to round-off (a rejected trial point's derivatives
// must never reach the next iteration, which works at the unchanged iterate), and trial points
// evaluated with derivatives exactly as the policy says: not on the last iteration, not after a
// rejected step or one that grew the trust radius, not for a full Newton step.
TEST(AnalyticDerivatives, TrialDerivativesGiveTheSolverOfSeparatePasses) {
  int rejected = 0, with_derivatives = 0;
  for (const std::string name : {"acrobot", "hopper", "quadruped", "bimanual", "allegro"}) {
    SCOPED_TRACE(name);
    ExampleConfig config = LoadExample(name);
    config.solver.max_iterations = 12;
    config.solver.constraint_method = ConstraintMethod::kPenalty;
    SolverSummary summary[2];
    Trajectory solution[2];
    for (const bool fused : {false, true}) {
      config.solver.trial_derivatives = fused;
      TrajectoryOptimizer optimizer(config.model, config.problem, config.solver);
      summary[fused] = optimizer.Solve(MakeInitialGuess(config), &solution[fused]);
    }
    ASSERT_EQ(summary[0].log.size(), summary[1].log.size());
    const int n = static_cast<int>(summary[1].log.size());
    for (int i = 0; i < n; ++i) {
      SCOPED_TRACE("iteration " + std::to_string(i));
      const IterationSummary& it = summary[1].log[i];
      EXPECT_EQ(it.accepted, summary[0].log[i].accepted);
      EXPECT_FALSE(summary[0].log[i].trial_with_derivatives);
      const IterationSummary* previous = i > 0 ? &summary[1].log[i - 1] : nullptr;
      const bool expected = i + 1 < config.solver.max_iterations &&
                            it.step_type != DoglegStep::kNewton &&
                            (previous == nullptr ||
                             (previous->accepted && !(it.trust_radius > previous->trust_radius)));
      EXPECT_EQ(it.trial_with_derivatives, expected);
      EXPECT_NEAR(it.cost, summary[0].log[i].cost, 1e-6 * std::max(1.0, std::abs(it.cost)));
      rejected += !it.accepted;
      with_derivatives += it.trial_with_derivatives;
    }
    // Round-off in tau (1e-15 relative) grows through the iterations: up to 6e-8 after 12
    // (bi-manual, measured), as between the two block-kernel paths.
    EXPECT_NEAR(summary[1].final_cost, summary[0].final_cost,
                1e-6 * std::max(1.0, summary[0].final_cost));
  }
  // Both branches were taken.
  EXPECT_GT(rejected, 0);
  EXPECT_GT(with_derivatives, 0);
  std::printf("%d rejected steps, %d trial points with derivatives\n", rejected, with_derivatives);
}

// Finite differences ignore the option: the same solve bit for bit.
TEST(AnalyticDerivatives, TrialDerivativesDoNotChangeFiniteDifferenceSolves) {
  ExampleConfig config = LoadExample("hopper");
  config.solver.max_iterations = 6;
  config.solver.derivative_method = DerivativeMethod::kForwardDifferences;
  Trajectory solution[2];
  double cost[2];
  for (const bool fused : {false, true}) {
    config.solver.trial_derivatives = fused;
    TrajectoryOptimizer optimizer(config.model, config.problem, config.solver);
    const SolverSummary s = optimizer.Solve(MakeInitialGuess(config), &solution[fused]);
    cost[fused] = s.final_cost;
    for (const IterationSummary& it : s.log) EXPECT_FALSE(it.trial_with_derivatives);
  }
  EXPECT_EQ(cost[0], cost[1]);
  EXPECT_TRUE(solution[0].q == solution[1].q);
}

}  // namespace
}  // namespace idto
