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

}  // namespace
}  // namespace idto
