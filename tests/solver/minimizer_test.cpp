// The transcription on its own (its derivative seam), the trust-region strategy's named pieces,
// and the callbacks' two ways to stop.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "idto/idto.hpp"
#include "solver/trust_region.hpp"
#include "support/kernel_paths.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

ProblemDefinition BallAndFingerProblem(const Model& model, int N) {
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, N);
  p.q_init << 1, 0, 0, 0, 0.0, 0.0, 0.049, 0.5, -1.2;
  p.Qq.setConstant(1.0);
  p.Qv.setConstant(0.1);
  p.R.setConstant(0.1);
  p.Qfq.setConstant(10.0);
  Eigen::VectorXd q_target = p.q_init;
  q_target(4) = 0.2;
  p.SetConstantNominal(q_target, Eigen::VectorXd::Zero(model.nv()));
  p.contact.parameters.stiffness = 500.0;
  p.contact.parameters.smoothing = 0.01;
  return p;
}

std::vector<Eigen::VectorXd> Guess(const Model& model, const ProblemDefinition& p) {
  test::Random rng(7);
  std::vector<Eigen::VectorXd> q(p.num_steps + 1, p.q_init);
  for (int k = 1; k <= p.num_steps; ++k) {
    q[k] += 0.01 * rng.Vector(model.nq());
    NormalizeQuaternions(model, &q[k]);
  }
  return q;
}

// Delegates to central differences and counts its calls: another method plugged into the seam.
class CountingEvaluator final : public TauDerivativeEvaluator {
 public:
  explicit CountingEvaluator(int* calls)
      : inner_(MakeTauDerivativeEvaluator(DerivativeMethod::kCentralDifferences, 0.0)),
        calls_(calls) {}
  void Calc(const TrajectoryState& state, Transcription* transcription,
            TrajectoryDerivatives* derivatives) const override {
    ++*calls_;
    inner_->Calc(state, transcription, derivatives);
  }

 private:
  std::unique_ptr<TauDerivativeEvaluator> inner_;
  int* calls_;
};

TEST(Transcription, AgreesWithTheOptimizerAndTakesAnotherDerivativeMethod) {
  const Model model = test::BallAndFinger();
  const ProblemDefinition p = BallAndFingerProblem(model, 8);
  const std::vector<Eigen::VectorXd> q = Guess(model, p);
  SolverOptions o;
  o.derivative_method = DerivativeMethod::kCentralDifferences;
  o.constraint_method = ConstraintMethod::kNone;
  TrajectoryOptimizer optimizer(model, p, o);
  Eigen::VectorXd g_optimizer;
  optimizer.EvalGradient(q, &g_optimizer);

  Transcription transcription(model, p);
  int calls = 0;
  transcription.SetDerivativeEvaluator(std::make_unique<CountingEvaluator>(&calls));
  TrajectoryState state = transcription.MakeState();
  state.q = q;
  const double cost = transcription.Evaluate(&state);
  EXPECT_EQ(cost, optimizer.EvalCost(q));
  TrajectoryDerivatives d = transcription.MakeDerivatives();
  transcription.CalcDerivatives(state, &d);
  EXPECT_EQ(calls, 1);
  Eigen::VectorXd g(p.num_steps * model.nq());
  transcription.CalcGradient(state, d, &g);
  EXPECT_EQ((g - g_optimizer).norm(), 0.0);  // the same computation, bit for bit
  PentaDiagonalMatrix H(p.num_steps, model.nq());
  transcription.CalcHessian(state, d, &H);
  EXPECT_EQ((H.MakeDense() - optimizer.EvalDenseHessian(q)).norm(), 0.0);
  // Both in one parallel phase (the solver's route), on 1 and 2 threads: the same bits.
  for (int threads : {1, 2}) {
    transcription.SetNumThreads(threads);
    Eigen::VectorXd g_both = Eigen::VectorXd::Constant(g.size(), 7.0);
    PentaDiagonalMatrix H_both(p.num_steps, model.nq());
    transcription.CalcGradientAndHessian(state, d, &g_both, &H_both);
    EXPECT_EQ(g_both, g);
    EXPECT_EQ(H_both.MakeDense(), H.MakeDense());
  }
  transcription.SetNumThreads(1);
  // The constraint blocks agree with the dense Jacobian.
  Eigen::MatrixXd At(p.num_steps * model.nq(), p.num_steps * transcription.num_unactuated());
  transcription.CalcDenseConstraintJacobianTranspose(d, &At);
  Eigen::MatrixXd block(transcription.num_unactuated(), model.nq());
  transcription.ConstraintBlock(d, 2, 3, block);
  const int nu = transcription.num_unactuated();
  EXPECT_EQ((block - At.block(2 * model.nq(), 2 * nu, model.nq(), nu).transpose()).norm(), 0.0);
  EXPECT_THAT([&] { transcription.SetDerivativeEvaluator(nullptr); },
              ::testing::ThrowsMessage<InvalidArgument>(::testing::HasSubstr("evaluator")));
}

// The Gauss-Newton Hessian against its definition, formed densely: J^T W J with J the Jacobian
// of the residuals (q_k, v_k and tau_j, stacked) from the derivative blocks, W their weights.
// CalcHessianRow exploits the structure (block-diagonal velocity partials, stacked symmetric
// rank updates); this oracle does not. On both paths of the block kernels.
class TranscriptionKernels : public test::KernelPathTest {};
IDTO_INSTANTIATE_KERNEL_PATHS(TranscriptionKernels);

TEST_P(TranscriptionKernels, HessianIsTheDenseGaussNewtonProduct) {
  const Model model = test::BallAndFinger();
  const int N = 7, nq = model.nq(), nv = model.nv();
  ProblemDefinition p = BallAndFingerProblem(model, N);
  p.Qv.setLinSpaced(0.05, 0.3);
  p.R.setLinSpaced(0.02, 0.4);
  Transcription t(model, p);
  const double penalty = 3e3;
  t.SetPenaltyWeight(penalty);
  TrajectoryState state = t.MakeState();
  state.q = Guess(model, p);
  t.Evaluate(&state);
  TrajectoryDerivatives d = t.MakeDerivatives();
  t.CalcDerivatives(state, &d);
  PentaDiagonalMatrix H(N, nq);
  t.CalcHessian(state, d, &H);

  const double dt = p.time_step;
  Eigen::VectorXd R = p.R;
  for (int u : t.unactuated_dofs()) R(u) = penalty;
  // Residual rows: q_1..q_N (nq each), v_1..v_N (nv each), tau_0..tau_{N-1} (nv each).
  const int rows = N * nq + 2 * N * nv;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(rows, N * nq);
  Eigen::VectorXd w(rows);
  const auto col = [&](int s) { return (s - 1) * nq; };
  for (int k = 1; k <= N; ++k) {
    const int rq = (k - 1) * nq, rv = N * nq + (k - 1) * nv;
    J.block(rq, col(k), nq, nq).setIdentity();
    w.segment(rq, nq) = k < N ? Eigen::VectorXd(dt * p.Qq) : p.Qfq;
    J.block(rv, col(k), nv, nq) = d.dv_dq[k];
    if (k >= 2) J.block(rv, col(k - 1), nv, nq) = d.dv_dqm[k];
    w.segment(rv, nv) = k < N ? Eigen::VectorXd(dt * p.Qv) : p.Qfv;
  }
  for (int j = 0; j < N; ++j) {
    const int rt = N * (nq + nv) + j * nv;
    for (int s = std::max(j - 1, 1); s <= std::min(j + 1, N); ++s) {
      J.block(rt, col(s), nv, nq) = d.DtauDq(j, s);
    }
    w.segment(rt, nv) = dt * R;
  }
  const Eigen::MatrixXd expected = J.transpose() * w.asDiagonal() * J;
  const Eigen::MatrixXd dense = H.MakeDense();
  EXPECT_LE((dense - expected).norm(), 1e-14 * expected.norm());
  EXPECT_EQ((dense - dense.transpose()).norm(), 0.0);  // exactly symmetric
  EXPECT_GT(expected.norm(), 1.0);
}

TEST(TrustRegion, DoglegStepKinds) {
  const Eigen::VectorXd D = Eigen::Vector2d(1.0, 2.0);
  const Eigen::VectorXd p_newton = Eigen::Vector2d(2.0, 0.0);
  const Eigen::VectorXd p_cauchy = Eigen::Vector2d(0.5, 0.5);
  Eigen::VectorXd w, u, p;
  double norm = 0.0;
  EXPECT_EQ(internal::CalcDoglegStep(p_newton, p_cauchy, D, 3.0, &w, &u, &p, &norm),
            DoglegStep::kNewton);
  EXPECT_EQ(p, p_newton);
  EXPECT_DOUBLE_EQ(norm, 2.0);
  EXPECT_EQ(internal::CalcDoglegStep(p_newton, p_cauchy, D, 0.1, &w, &u, &p, &norm),
            DoglegStep::kCauchy);
  EXPECT_NEAR(p.cwiseQuotient(D).norm(), 0.1, 1e-15);
  EXPECT_EQ(internal::CalcDoglegStep(p_newton, p_cauchy, D, 1.0, &w, &u, &p, &norm),
            DoglegStep::kDogleg);
  EXPECT_NEAR(p.cwiseQuotient(D).norm(), 1.0, 1e-14);  // on the boundary
  // On the segment from the Cauchy to the Newton point.
  const Eigen::VectorXd t = (p - p_cauchy).cwiseQuotient(p_newton - p_cauchy);
  EXPECT_NEAR(t(0), t(1), 1e-14);
}

TEST(TrustRegion, RatioRadiusAndConvergencePredicates) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(internal::ReductionRatio(1.0, std::nan(""), 0.1), -inf);
  EXPECT_EQ(internal::ReductionRatio(1.0, 0.5, 0.0), -inf);
  EXPECT_DOUBLE_EQ(internal::ReductionRatio(1.0, 0.5, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(internal::UpdateTrustRadius(0.1, 0.4, 1.0, 10.0), 0.1);
  EXPECT_DOUBLE_EQ(internal::UpdateTrustRadius(0.9, 1.0, 1.0, 10.0), 2.0);
  EXPECT_DOUBLE_EQ(internal::UpdateTrustRadius(0.9, 0.5, 1.0, 10.0), 1.0);  // inside
  EXPECT_DOUBLE_EQ(internal::UpdateTrustRadius(0.9, 8.0, 8.0, 10.0), 10.0);
  SolverOptions o;
  std::string message;
  EXPECT_TRUE(internal::CostChangeConverged(1.0, 1.0 + 1e-12, o, &message));
  EXPECT_THAT(message, ::testing::HasSubstr("cost_tolerance"));
  EXPECT_FALSE(internal::CostChangeConverged(1.0, std::nan(""), o, &message));
  EXPECT_FALSE(internal::StepConverged(std::nan(""), 1.0, o, &message));
  EXPECT_FALSE(internal::GradientConverged(std::nan(""), 1.0, o, &message));
  EXPECT_TRUE(internal::PredictedReductionNegligible(1e-20, 1.0));
  EXPECT_FALSE(internal::PredictedReductionNegligible(1e-3, 1.0));
}

TEST(TrustRegion, GrowthGuardTripsOnlyWhenBothGrowTenfold) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(internal::GrowthGuardTrips(1.0, 2.0, 10.5, 21.0));
  EXPECT_FALSE(internal::GrowthGuardTrips(1.0, 2.0, 10.5, 19.0));  // violation only 9.5x
  EXPECT_FALSE(internal::GrowthGuardTrips(1.0, 2.0, 9.5, 1e9));    // cost only 9.5x
  EXPECT_FALSE(internal::GrowthGuardTrips(1.0, 2.0, 10.0, 20.0));  // exactly 10x: kept
  // A feasible iterate (violation 0): any violation counts as growth, a cost of 10x too.
  EXPECT_TRUE(internal::GrowthGuardTrips(1.0, 0.0, 11.0, 1e-30));
  EXPECT_FALSE(internal::GrowthGuardTrips(1.0, 0.0, 11.0, 0.0));
  // Non-finite trial values are left to the ratio test.
  EXPECT_FALSE(internal::GrowthGuardTrips(1.0, 1.0, inf, inf));
  EXPECT_FALSE(internal::GrowthGuardTrips(1.0, 1.0, std::nan(""), 100.0));
}

TEST(Callbacks, TerminateSuccessfullyAndAbortAreDistinct) {
  const Model model = test::BallAndFinger();
  const ProblemDefinition p = BallAndFingerProblem(model, 8);
  for (CallbackReturn r : {CallbackReturn::kTerminateSuccessfully, CallbackReturn::kAbort}) {
    TrajectoryOptimizer optimizer(model, p, SolverOptions{});
    optimizer.AddCallback([r](const IterationSummary& s) {
      return s.iteration == 2 ? r : CallbackReturn::kContinue;
    });
    Trajectory solution;
    const SolverSummary summary = optimizer.Solve(Guess(model, p), &solution);
    EXPECT_EQ(summary.iterations, 3);
    if (r == CallbackReturn::kAbort) {
      EXPECT_EQ(summary.termination, TerminationType::kUserAbort);
      EXPECT_EQ(TerminationTypeName(summary.termination), "user_abort");
    } else {
      EXPECT_EQ(summary.termination, TerminationType::kUserTermination);
      EXPECT_EQ(TerminationTypeName(summary.termination), "user");
    }
    EXPECT_EQ(static_cast<int>(solution.q.size()), p.num_steps + 1);
  }
}

}  // namespace
}  // namespace idto
