// The IDTO solver: derivatives against finite differences and an independently built residual,
// trust-region mechanics, convergence on small problems, constraints, determinism, errors.

#include <cmath>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#define IDTO_DEFINE_ALLOCATION_COUNTER
#include "idto/idto.hpp"
#include "support/allocation_counter.hpp"
#include "support/eigen_matchers.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using test::BallAndFinger;
using test::Pendulum;
using test::PointLikeMass;
using ::testing::HasSubstr;

// A mass on a horizontal slider: tau = m a exactly, so every residual is linear in q.
Model Slider() {
  ModelBuilder b("slider");
  JointSpec j;
  j.name = "x";
  j.type = JointType::kPrismatic;
  j.axis = Eigen::Vector3d::UnitX();
  b.AddBody("cart", PointLikeMass(2.0, Eigen::Vector3d::Zero()), kWorldBody, j);
  return b.Build();
}

ProblemDefinition BallAndFingerProblem(const Model& model, int N) {
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, N);
  p.q_init << 1, 0, 0, 0, 0.0, 0.0, 0.049, 0.5, -1.2;  // ball slightly in the ground
  p.Qq.setConstant(1.0);
  p.Qv.setConstant(0.1);
  p.R.setConstant(0.1);
  p.R.head<6>().setConstant(100.0);
  p.Qfq.setConstant(10.0);
  p.Qfv.setConstant(1.0);
  Eigen::VectorXd q_target = p.q_init;
  q_target(4) = 0.2;
  p.SetConstantNominal(q_target, Eigen::VectorXd::Zero(model.nv()));
  p.contact.parameters.stiffness = 500.0;
  p.contact.parameters.smoothing = 0.01;
  p.contact.parameters.stiction_velocity = 0.1;
  p.contact.parameters.friction_coefficient = 0.5;
  return p;
}

// A guess with some motion in every coordinate (and non-trivial contact states).
std::vector<Eigen::VectorXd> PerturbedGuess(const Model& model, const ProblemDefinition& p,
                                            double scale, std::uint32_t seed) {
  test::Random rng(seed);
  std::vector<Eigen::VectorXd> q(p.num_steps + 1, p.q_init);
  for (int k = 1; k <= p.num_steps; ++k) {
    q[k] += scale * rng.Vector(model.nq());
    NormalizeQuaternions(model, &q[k]);
  }
  return q;
}

// The residual of the paper's Remark 1, built here from the trajectory alone.
Eigen::VectorXd Residual(TrajectoryOptimizer* opt, const std::vector<Eigen::VectorXd>& q) {
  const ProblemDefinition& p = opt->problem();
  Trajectory t;
  opt->EvalTrajectory(q, &t);
  const int N = p.num_steps, nq = static_cast<int>(q[0].size()),
            nv = static_cast<int>(t.v[0].size());
  Eigen::VectorXd r(N * (nq + 2 * nv) + nq + nv);
  int i = 0;
  const double dt = p.time_step;
  for (int k = 0; k < N; ++k) {
    r.segment(i, nq) = (dt * p.Qq).cwiseSqrt().cwiseProduct(t.q[k] - p.q_nom[k]);
    i += nq;
    r.segment(i, nv) = (dt * p.Qv).cwiseSqrt().cwiseProduct(t.v[k] - p.v_nom[k]);
    i += nv;
    r.segment(i, nv) = (dt * p.R).cwiseSqrt().cwiseProduct(t.tau[k]);
    i += nv;
  }
  r.segment(i, nq) = p.Qfq.cwiseSqrt().cwiseProduct(t.q[N] - p.q_nom[N]);
  i += nq;
  r.segment(i, nv) = p.Qfv.cwiseSqrt().cwiseProduct(t.v[N] - p.v_nom[N]);
  return r;
}

// Stacks q_1..q_N into one vector and back.
Eigen::VectorXd Stack(const std::vector<Eigen::VectorXd>& q) {
  const int nq = static_cast<int>(q[0].size());
  Eigen::VectorXd x((q.size() - 1) * nq);
  for (size_t k = 1; k < q.size(); ++k) x.segment((k - 1) * nq, nq) = q[k];
  return x;
}
std::vector<Eigen::VectorXd> Unstack(const Eigen::VectorXd& x, const Eigen::VectorXd& q0) {
  const int nq = static_cast<int>(q0.size());
  std::vector<Eigen::VectorXd> q{q0};
  for (int k = 0; k < x.size() / nq; ++k) q.push_back(x.segment(k * nq, nq));
  return q;
}

TEST(Solver, GradientMatchesFiniteDifferencesOfTheCostWithContactAndFloatingBase) {
  const Model model = BallAndFinger();
  const ProblemDefinition p = BallAndFingerProblem(model, 5);
  SolverOptions o;
  o.derivative_method = DerivativeMethod::kCentralDifferences;
  TrajectoryOptimizer opt(model, p, o);
  const std::vector<Eigen::VectorXd> q = PerturbedGuess(model, p, 0.02, 1);
  Eigen::VectorXd g;
  opt.EvalGradient(q, &g);
  const Eigen::VectorXd x = Stack(q);
  Eigen::VectorXd g_fd(x.size());
  for (int i = 0; i < x.size(); ++i) {
    const double h = 1e-6;
    Eigen::VectorXd xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    g_fd(i) = (opt.EvalCost(Unstack(xp, q[0])) - opt.EvalCost(Unstack(xm, q[0]))) / (2 * h);
  }
  EXPECT_GT(g.norm(), 1.0);  // a meaningful comparison
  EXPECT_EIGEN_NEAR(g, g_fd, 1e-5 * g.cwiseAbs().maxCoeff());
  // Forward differences (the default) agree to a looser tolerance.
  TrajectoryOptimizer fwd(model, p, SolverOptions{});
  Eigen::VectorXd g_fwd;
  fwd.EvalGradient(q, &g_fwd);
  EXPECT_EIGEN_NEAR(g_fwd, g_fd, 1e-4 * g.cwiseAbs().maxCoeff());
}

TEST(Solver, CostIsHalfTheSquaredResidualAndHessianIsGaussNewton) {
  const Model model = BallAndFinger();
  const ProblemDefinition p = BallAndFingerProblem(model, 4);
  SolverOptions o;
  o.derivative_method = DerivativeMethod::kCentralDifferences;
  TrajectoryOptimizer opt(model, p, o);
  const std::vector<Eigen::VectorXd> q = PerturbedGuess(model, p, 0.02, 2);
  const Eigen::VectorXd r = Residual(&opt, q);
  EXPECT_NEAR(opt.EvalCost(q), 0.5 * r.squaredNorm(), 1e-12 * r.squaredNorm());
  // Dense Jacobian of the residual by central differences.
  const Eigen::VectorXd x = Stack(q);
  Eigen::MatrixXd J(r.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    const double h = 1e-6;
    Eigen::VectorXd xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    J.col(i) = (Residual(&opt, Unstack(xp, q[0])) - Residual(&opt, Unstack(xm, q[0]))) / (2 * h);
  }
  const Eigen::MatrixXd H = opt.EvalDenseHessian(q);
  const Eigen::MatrixXd JtJ = J.transpose() * J;
  EXPECT_EIGEN_NEAR(H, JtJ, 1e-5 * JtJ.cwiseAbs().maxCoeff());
  Eigen::VectorXd g;
  opt.EvalGradient(q, &g);
  EXPECT_EIGEN_NEAR(g, Eigen::VectorXd(J.transpose() * r), 1e-5 * g.cwiseAbs().maxCoeff());
  // Pentadiagonal: blocks farther than two steps apart are exactly zero.
  const int nq = model.nq();
  EXPECT_EQ(H.block(3 * nq, 0, nq, nq).norm(), 0.0);
}

TEST(Solver, RatioIsOneWhenResidualsAreLinear) {
  const Model model = Slider();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.1, 10);
  p.Qq.setConstant(1.0);
  p.Qv.setConstant(0.5);
  p.R.setConstant(0.01);
  p.Qfq.setConstant(10.0);
  p.Qfv.setConstant(1.0);
  p.SetConstantNominal(Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Zero(1));
  SolverOptions o;
  o.max_iterations = 5;
  o.initial_trust_radius = 1e3;  // the Newton step fits: one step solves the problem
  TrajectoryOptimizer opt(model, p, o);
  Trajectory sol;
  const SolverSummary s = opt.Solve(std::vector<Eigen::VectorXd>(11, p.q_init), &sol);
  ASSERT_GE(s.log.size(), 1u);
  EXPECT_NEAR(s.log[0].ratio, 1.0, 1e-6);
  EXPECT_EQ(s.log[0].step_type, DoglegStep::kNewton);
  EXPECT_EQ(s.termination, TerminationType::kConverged);
  // At the minimum of a quadratic the gradient vanishes.
  Eigen::VectorXd g;
  opt.EvalGradient(sol.q, &g);
  EXPECT_LT(g.norm(), 1e-6);
}

TEST(Solver, DoglegStepsLieOnTheScaledTrustRegionBoundary) {
  const Model model = Pendulum();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 20);
  p.Qq.setConstant(0.1);
  p.Qv.setConstant(0.1);
  p.R.setConstant(0.01);
  p.Qfq.setConstant(100.0);
  p.Qfv.setConstant(10.0);
  p.SetConstantNominal(Eigen::VectorXd::Constant(1, M_PI), Eigen::VectorXd::Zero(1));
  SolverOptions o;
  o.max_iterations = 1;
  o.initial_trust_radius = 0.05;
  TrajectoryOptimizer opt(model, p, o);
  Trajectory sol;
  std::vector<Eigen::VectorXd> q(21, p.q_init);
  const Eigen::MatrixXd H = opt.EvalDenseHessian(q);
  const SolverSummary s = opt.Solve(q, &sol);
  ASSERT_EQ(s.log.size(), 1u);
  ASSERT_TRUE(s.log[0].accepted);
  ASSERT_NE(s.log[0].step_type, DoglegStep::kNewton);
  // The step, recovered from the iterates, measured with D = diag(H)^(-1/4).
  const Eigen::VectorXd p_step = Stack(sol.q) - Stack(q);
  const Eigen::VectorXd D = H.diagonal().array().pow(-0.25);
  EXPECT_NEAR(p_step.cwiseQuotient(D).norm(), 0.05, 1e-12);
}

TEST(Solver, PendulumSwingsUp) {
  const Model model = Pendulum();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 40);
  p.Qq.setConstant(0.1);
  p.Qv.setConstant(0.1);
  p.R.setConstant(0.01);
  p.Qfq.setConstant(1000.0);
  p.Qfv.setConstant(100.0);
  p.SetConstantNominal(Eigen::VectorXd::Constant(1, M_PI), Eigen::VectorXd::Zero(1));
  SolverOptions o;
  o.max_iterations = 300;
  TrajectoryOptimizer opt(model, p, o);
  Trajectory sol;
  const SolverSummary s = opt.Solve(std::vector<Eigen::VectorXd>(41, p.q_init), &sol);
  EXPECT_NE(s.termination, TerminationType::kFailure) << s.message;
  EXPECT_LT(std::abs(sol.q.back()(0) - M_PI), 1e-3) << s.BriefReport();
  EXPECT_LT(s.final_cost, s.initial_cost);
}

// Two carts on a rail; the left one (actuated) pushes the right one (unactuated) through
// contact between their spheres.
Model Pusher() {
  ModelBuilder b("pusher");
  for (const char* name : {"pusher", "block"}) {
    JointSpec j;
    j.name = std::string(name) + "_x";
    j.type = JointType::kPrismatic;
    j.axis = Eigen::Vector3d::UnitX();
    const BodyIndex body =
        b.AddBody(name, PointLikeMass(1.0, Eigen::Vector3d::Zero()), kWorldBody, j);
    b.AddGeometry(std::string(name) + "_sphere", body, Eigen::Isometry3d::Identity(), Sphere{0.1});
  }
  b.SetGravity(Eigen::Vector3d::Zero());
  return b.Build();
}

ProblemDefinition PusherProblem(const Model& model) {
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 20);
  p.q_init << 0.0, 0.25;
  p.Qq << 0.0, 1.0;
  p.Qv.setConstant(0.1);
  p.R << 0.01, 1.0;
  p.Qfq << 0.0, 10.0;
  p.Qfv.setConstant(1.0);
  p.SetConstantNominal(Eigen::Vector2d(0.0, 0.6), Eigen::Vector2d::Zero());
  p.unactuated_dofs = std::vector<int>{1};
  p.contact.parameters.stiffness = 200.0;
  p.contact.parameters.smoothing = 0.01;
  p.contact.parameters.friction_coefficient = 0.0;
  return p;
}

TEST(Solver, LagrangeMultipliersDriveUnactuatedTorquesToZeroUnlikeThePenalty) {
  const Model model = Pusher();
  const ProblemDefinition p = PusherProblem(model);
  std::vector<Eigen::VectorXd> guess(21, p.q_init);
  SolverOptions lagrange;
  lagrange.constraint_method = ConstraintMethod::kLagrangeMultipliers;
  lagrange.max_iterations = 200;
  TrajectoryOptimizer lm(model, p, lagrange);
  Trajectory sol_lm;
  const SolverSummary s_lm = lm.Solve(guess, &sol_lm);
  SolverOptions penalty;
  penalty.constraint_method = ConstraintMethod::kPenalty;
  penalty.max_iterations = 200;
  TrajectoryOptimizer pen(model, p, penalty);
  Trajectory sol_pen;
  const SolverSummary s_pen = pen.Solve(guess, &sol_pen);
  EXPECT_NE(s_lm.termination, TerminationType::kFailure) << s_lm.message;
  EXPECT_LT(s_lm.constraint_violation, 1e-8) << s_lm.BriefReport();
  EXPECT_GT(s_pen.constraint_violation, 1e3 * std::max(s_lm.constraint_violation, 1e-12))
      << s_pen.BriefReport();
  // The block moved towards its target.
  EXPECT_GT(sol_lm.q.back()(1), 0.4);
  Eigen::VectorXd h;
  lm.EvalConstraints(sol_lm.q, &h);
  EXPECT_NEAR(h.squaredNorm(), s_lm.constraint_violation, 1e-12);
}

// kkt_extended_residual and kkt_extended_threshold change only the round-off of the Lagrange
// step: the same solve to ~1e-9, but not bit for bit (the options reach the KKT solver). Runs:
// the residual in double only (threshold infinity), always in double-double, and threshold 0
// (one double-double step after the double one).
TEST(Solver, ExtendedKktResidualChangesOnlyRoundOff) {
  const Model model = Pusher();
  const ProblemDefinition p = PusherProblem(model);
  std::vector<Eigen::VectorXd> guess(21, p.q_init);
  std::vector<Trajectory> sols(3);
  for (int run = 0; run < 3; ++run) {
    SolverOptions o;
    o.constraint_method = ConstraintMethod::kLagrangeMultipliers;
    o.max_iterations = 10;
    o.fixed_iterations = true;
    o.kkt_extended_residual = run == 1;
    o.kkt_extended_threshold = run == 0 ? std::numeric_limits<double>::infinity() : 0.0;
    TrajectoryOptimizer opt(model, p, o);
    const SolverSummary s = opt.Solve(guess, &sols[run]);
    EXPECT_NE(s.termination, TerminationType::kFailure) << s.message;
  }
  auto difference = [&](int a, int b) {
    double d = 0.0, scale = 0.0;
    for (size_t k = 0; k < sols[a].q.size(); ++k) {
      d = std::max(d, (sols[a].q[k] - sols[b].q[k]).cwiseAbs().maxCoeff());
      scale = std::max(scale, sols[b].q[k].cwiseAbs().maxCoeff());
    }
    return d / scale;
  };
  EXPECT_LE(difference(0, 1), 1e-9);
  EXPECT_GT(difference(0, 1), 0.0);
  EXPECT_LE(difference(2, 1), 1e-9);
  EXPECT_GT(difference(2, 0), 0.0);
}

TEST(Solver, KktExtendedThresholdIsValidated) {
  SolverOptions o;
  std::string why;
  o.kkt_extended_threshold = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(o.IsValid(&why)) << why;
  for (double bad : {-1e-12, std::numeric_limits<double>::quiet_NaN()}) {
    o.kkt_extended_threshold = bad;
    EXPECT_FALSE(o.IsValid(&why));
    EXPECT_NE(why.find("kkt_extended_threshold"), std::string::npos) << why;
  }
}

TEST(Solver, ConstraintCorrectionIsValidated) {
  SolverOptions o;
  std::string why;
  EXPECT_EQ(o.constraint_correction, 0.5);
  for (double good : {0.0, 1e-3, 10.0}) {
    o.constraint_correction = good;
    EXPECT_TRUE(o.IsValid(&why)) << why;
  }
  for (double bad : {-1e-12, 10.5, std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::quiet_NaN()}) {
    o.constraint_correction = bad;
    EXPECT_FALSE(o.IsValid(&why));
    EXPECT_NE(why.find("constraint_correction"), std::string::npos) << why;
  }
}

TEST(Solver, ResultsAreBitwiseIdenticalForOneAndTwoThreads) {
  const Model model = BallAndFinger();
  const ProblemDefinition p = BallAndFingerProblem(model, 8);
  const std::vector<Eigen::VectorXd> guess = PerturbedGuess(model, p, 0.01, 3);
  std::vector<Trajectory> sols(2);
  std::vector<SolverSummary> sums(2);
  for (int threads : {1, 2}) {
    SolverOptions o;
    o.num_threads = threads;
    o.max_iterations = 8;
    o.constraint_method = ConstraintMethod::kLagrangeMultipliers;
    TrajectoryOptimizer opt(model, p, o);
    sums[threads - 1] = opt.Solve(guess, &sols[threads - 1]);
  }
  ASSERT_EQ(sums[0].iterations, sums[1].iterations);
  for (size_t k = 0; k < sols[0].q.size(); ++k) {
    EXPECT_EQ(sols[0].q[k], sols[1].q[k]) << k;
    EXPECT_EQ(sols[0].tau[k], sols[1].tau[k]) << k;
  }
  for (size_t i = 0; i < sums[0].log.size(); ++i) {
    EXPECT_EQ(sums[0].log[i].cost, sums[1].log[i].cost);
    EXPECT_EQ(sums[0].log[i].ratio, sums[1].log[i].ratio);
  }
}

// Bit for bit with separate evaluation and derivative passes; with trial derivatives (the
// default) an iterate's tau comes from the pass that evaluated it (a trial point's, or the
// warm start's re-evaluation, which takes its derivatives along), so the two agree to round-off.
TEST(Solver, TenWarmStartedSingleIterationsEqualOneTenIterationSolve) {
  const Model model = BallAndFinger();
  const ProblemDefinition p = BallAndFingerProblem(model, 6);
  const std::vector<Eigen::VectorXd> guess = PerturbedGuess(model, p, 0.01, 4);
  for (const bool trial_derivatives : {false, true}) {
    SCOPED_TRACE(trial_derivatives ? "trial derivatives" : "separate passes");
    SolverOptions ten;
    ten.max_iterations = 10;
    ten.fixed_iterations = true;
    ten.trial_derivatives = trial_derivatives;
    TrajectoryOptimizer a(model, p, ten);
    Trajectory sol_a;
    a.Solve(guess, &sol_a);
    SolverOptions one = ten;
    one.max_iterations = 1;
    TrajectoryOptimizer b(model, p, one);
    Trajectory sol_b;
    b.SetIterate(guess);
    for (int i = 0; i < 10; ++i) b.SolveWarmStart(&sol_b);
    for (size_t k = 0; k < sol_a.q.size(); ++k) {
      if (trial_derivatives) {
        EXPECT_LE((sol_a.q[k] - sol_b.q[k]).norm(), 1e-12 * std::max(1.0, sol_a.q[k].norm())) << k;
      } else {
        EXPECT_EQ(sol_a.q[k], sol_b.q[k]) << k;
      }
    }
    EXPECT_NEAR(a.trust_radius(), b.trust_radius(),
                trial_derivatives ? 1e-12 * a.trust_radius() : 0.0);
  }
}

TEST(Solver, AnIterationAllocatesNothingAfterTheFirst) {
  if (!test::AllocationCountingAvailable()) GTEST_SKIP() << "malloc is owned by a sanitizer";
  const Model model = BallAndFinger();
  const ProblemDefinition p = BallAndFingerProblem(model, 6);
  for (ConstraintMethod method :
       {ConstraintMethod::kPenalty, ConstraintMethod::kLagrangeMultipliers}) {
    SolverOptions o;
    o.max_iterations = 6;
    o.fixed_iterations = true;
    o.constraint_method = method;
    TrajectoryOptimizer opt(model, p, o);
    std::unique_ptr<test::ScopedAllocationCounter> counter;
    long allocations = -1;
    int corrected = 0;  // iterations 1-4 with a constraint correction (Lagrange)
    opt.AddCallback([&](const IterationSummary& s) {
      if (s.iteration == 1) counter = std::make_unique<test::ScopedAllocationCounter>();
      if (s.iteration == 5) allocations = counter->count();
      if (s.iteration >= 1 && s.iteration <= 4 && s.correction_norm > 0.0) ++corrected;
      return CallbackReturn::kContinue;
    });
    Trajectory sol;
    opt.Solve(PerturbedGuess(model, p, 0.01, 5), &sol);
    counter.reset();
    EXPECT_EQ(allocations, 0) << static_cast<int>(method);
    if (method == ConstraintMethod::kLagrangeMultipliers) {
      EXPECT_GT(corrected, 0);  // the correction ran inside the counted iterations
    }
  }
}

TEST(Solver, InvalidInputsThrowClearMessages) {
  const Model model = Pendulum();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 10);
  auto throws = [&](const ProblemDefinition& bad, const std::string& text) {
    EXPECT_THAT([&] { TrajectoryOptimizer(model, bad, SolverOptions{}); },
                ::testing::ThrowsMessage<InvalidArgument>(HasSubstr(text)));
  };
  ProblemDefinition bad = p;
  bad.time_step = 0.0;
  throws(bad, "time_step is 0; expected a finite positive number");
  bad = p;
  bad.num_steps = 0;
  throws(bad, "num_steps is 0");
  // A horizon whose solver memory cannot fit: refused up front with the estimate.
  bad = p;
  bad.num_steps = 2000000000;
  throws(bad, "num_steps is 2000000000 (about");
  bad = p;
  bad.Qv(0) = -1.0;
  throws(bad, "Qv(0) is -1; expected a non-negative number");
  bad = p;
  bad.R = Eigen::VectorXd::Zero(3);
  throws(bad, "R is of size 3; expected size 1 (model.nv())");
  bad = p;
  bad.q_init(0) = std::nan("");
  throws(bad, "q_init(0) is nan");
  bad = p;
  bad.q_nom.pop_back();
  throws(bad, "q_nom is 10 entries; expected 11 entries");
  bad = p;
  bad.unactuated_dofs = std::vector<int>{3};
  throws(bad, "unactuated_dofs[0] is 3");
  SolverOptions o;
  o.num_threads = 0;
  EXPECT_THAT([&] { TrajectoryOptimizer(model, p, o); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("num_threads is 0")));
  o.num_threads = 100000;  // above SolverOptions::kMaxNumThreads: an error, not a crash
  EXPECT_THAT([&] { TrajectoryOptimizer(model, p, o); },
              ::testing::ThrowsMessage<InvalidArgument>(
                  HasSubstr("num_threads is 100000; expected in [1, 256]")));
  std::string why;
  o = SolverOptions{};
  o.initial_trust_radius = -1;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_THAT(why, HasSubstr("initial_trust_radius is -1"));
  // An iteration count whose log alone cannot fit: refused with the estimate.
  o = SolverOptions{};
  o.max_iterations = 1000000000;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_THAT(why, HasSubstr("max_iterations is 1000000000; expected at most"));
  EXPECT_THAT(why, HasSubstr("GiB"));
  TrajectoryOptimizer opt(model, p, SolverOptions{});
  Trajectory sol;
  EXPECT_THAT([&] { opt.Solve(std::vector<Eigen::VectorXd>(3, p.q_init), &sol); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("q_guess is 3 configurations")));
}

TEST(Solver, ASingularHessianIsRegularizedAndTheSolveProceeds) {
  // No weight on anything but the final position: the early steps have no curvature, so H is
  // singular; the Levenberg-Marquardt shift makes it factorizable and the solve proceeds.
  const Model model = Pendulum(0.0);
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 10);
  p.Qfq.setConstant(10.0);
  p.SetConstantNominal(Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Zero(1));
  TrajectoryOptimizer opt(model, p, SolverOptions{});
  Trajectory sol;
  const std::vector<Eigen::VectorXd> guess(11, Eigen::VectorXd::Constant(1, 0.3));
  const SolverSummary s = opt.Solve(guess, &sol);
  EXPECT_NE(s.termination, TerminationType::kFailure) << s.message;
  ASSERT_FALSE(s.log.empty());
  EXPECT_GT(s.log[0].regularization, 0.0);
  EXPECT_LT(std::abs(sol.q.back()(0) - 1.0), 1e-3) << s.BriefReport();
}

TEST(Solver, StiffContactIsFactorizedWithRegularization) {
  // k = 2e8 N/m: H spans ~18 orders of magnitude and is numerically indefinite.
  const Model model = BallAndFinger();
  ProblemDefinition p = BallAndFingerProblem(model, 10);
  p.contact.parameters.stiffness = 2e8;
  SolverOptions o;
  o.max_iterations = 10;
  TrajectoryOptimizer opt(model, p, o);
  Trajectory sol;
  const SolverSummary s = opt.Solve(std::vector<Eigen::VectorXd>(11, p.q_init), &sol);
  EXPECT_NE(s.termination, TerminationType::kFailure) << s.message;
  EXPECT_LT(s.final_cost, s.initial_cost);
  // A free ball resting 1 mm deep at k = 2e8: without the shift the block Cholesky fails
  // (round-off ~ eps |H| ~ 500 against eigenvalues up to 2.4e18).
  ModelBuilder b("ball");
  b.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  JointSpec free;
  free.name = "free";
  free.type = JointType::kFloating;
  BodyInertia ball;
  ball.mass = 0.2;
  ball.I_BBcm_B = Eigen::Matrix3d::Identity() * 2e-4;
  const BodyIndex bb = b.AddBody("ball", ball, kWorldBody, free);
  b.AddGeometry("sphere", bb, Eigen::Isometry3d::Identity(), Sphere{0.05});
  const Model m = b.Build();
  ProblemDefinition q = ProblemDefinition::MakeDefault(m, 0.05, 20);
  q.q_init << 1, 0, 0, 0, 0, 0, 0.049;
  q.Qq.setConstant(1);
  q.Qv.setConstant(0.1);
  q.R.setConstant(100);
  q.Qfq.setConstant(10);
  q.Qfv.setConstant(1);
  q.SetConstantNominal(q.q_init, Eigen::VectorXd::Zero(6));
  q.contact.parameters.stiffness = 2e8;
  TrajectoryOptimizer ball_opt(m, q, o);
  const SolverSummary r = ball_opt.Solve(std::vector<Eigen::VectorXd>(21, q.q_init), &sol);
  EXPECT_NE(r.termination, TerminationType::kFailure) << r.message;
  ASSERT_FALSE(r.log.empty());
  EXPECT_GT(r.log[0].regularization, 0.0);
  EXPECT_LT(r.final_cost, r.initial_cost);
}

TEST(Solver, NonFiniteInitialCostIsAFailureNotACrash) {
  const Model model = Pendulum();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 10);
  p.R.setConstant(1.0);
  TrajectoryOptimizer opt(model, p, SolverOptions{});
  std::vector<Eigen::VectorXd> guess(11, p.q_init);
  guess[5](0) = 1e300;  // velocities overflow to inf
  Trajectory sol;
  const SolverSummary s = opt.Solve(guess, &sol);
  EXPECT_EQ(s.termination, TerminationType::kFailure);
  EXPECT_THAT(s.message, HasSubstr("not finite"));
}

TEST(Solver, SummaryReportsAndCsv) {
  const Model model = Pendulum();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 10);
  p.Qfq.setConstant(10.0);
  p.R.setConstant(0.01);
  p.SetConstantNominal(Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Zero(1));
  SolverOptions o;
  o.max_iterations = 3;
  o.fixed_iterations = true;
  TrajectoryOptimizer opt(model, p, o);
  Trajectory sol;
  const SolverSummary s = opt.Solve(std::vector<Eigen::VectorXd>(11, p.q_init), &sol);
  EXPECT_EQ(s.termination, TerminationType::kMaxIterations);
  EXPECT_EQ(s.iterations, 3);
  EXPECT_THAT(s.BriefReport(), HasSubstr("max_iterations after 3 iterations"));
  EXPECT_THAT(s.FullReport(), HasSubstr("derivatives"));
  const std::string csv = s.ToCsv();
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
  EXPECT_THAT(csv, HasSubstr("iteration,cost,merit"));
}

}  // namespace
}  // namespace idto

namespace idto {
namespace {

TEST(Solver, StationaryPointsConvergeAndWarmStartsKeepWorking) {
  // Solve to the optimum, then keep iterating from it: rejected steps at round-off level are
  // convergence (not failure), and fixed-iteration warm starts never fail there.
  const Model model = Pendulum();
  ProblemDefinition p = ProblemDefinition::MakeDefault(model, 0.05, 10);
  p.Qq.setConstant(0.1);
  p.Qv.setConstant(0.1);
  p.R.setConstant(0.01);
  p.Qfq.setConstant(10.0);
  p.SetConstantNominal(Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Zero(1));
  SolverOptions o;
  o.max_iterations = 500;
  o.cost_tolerance = 0.0;
  o.gradient_tolerance = 0.0;
  o.step_tolerance = 0.0;
  TrajectoryOptimizer opt(model, p, o);
  Trajectory sol;
  const SolverSummary s = opt.Solve(std::vector<Eigen::VectorXd>(11, p.q_init), &sol);
  EXPECT_EQ(s.termination, TerminationType::kConverged) << s.message;
  EXPECT_LT(s.iterations, 500);
  opt.mutable_options().fixed_iterations = true;
  opt.mutable_options().max_iterations = 50;
  const SolverSummary w = opt.SolveWarmStart(&sol);
  EXPECT_EQ(w.termination, TerminationType::kMaxIterations) << w.message;
  EXPECT_GE(opt.trust_radius(), 1e-12);
  // A new initial condition: the warm-started solver moves again.
  opt.ResetInitialConditions(Eigen::VectorXd::Constant(1, 0.2), Eigen::VectorXd::Zero(1));
  opt.mutable_options().fixed_iterations = false;
  opt.mutable_options().cost_tolerance = 1e-12;
  opt.mutable_options().max_iterations = 500;
  const SolverSummary r = opt.SolveWarmStart(&sol);
  EXPECT_NE(r.termination, TerminationType::kFailure) << r.message;
  EXPECT_LT(r.final_cost, r.initial_cost);
}

}  // namespace
}  // namespace idto
