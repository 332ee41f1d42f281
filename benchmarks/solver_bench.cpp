// Solver: time per iteration and its breakdown (paper Figs. 6 and 7) for the pendulum, the
// acrobot and a small contact problem, over horizons N = 10 ... 320 (1 thread), penalty vs
// Lagrange multipliers, and N = 40 with 2 threads.
//
// Each benchmark iteration is one solver iteration (SolveWarmStart with max_iterations = 1 and
// fixed_iterations), which also re-evaluates the cost at the current iterate once: the
// reported time is slightly above the in-solver iteration time. Every kRestartEvery-th one is a
// cold Solve from the initial guess, so the timed work cycles through the solve's first
// kRestartEvery iterations (the refinement of the Lagrange step costs more in later iterations,
// where K is worse conditioned: a run that went further would time other work). Runs of
// several cycles give their mean; a run of one iteration (the largest cases at a short
// --benchmark_min_time) times the cold first iteration only.
// Counters give the breakdown per iteration in microseconds (derivatives, hessian, factorization,
// multipliers, trial cost, and contact: the contact evaluations within derivatives and trial cost,
// CPU time summed over threads). The largest case (ball + finger, Lagrange, N = 320) takes about
// 5 ms per iteration. Names:
// "solver/<problem>/<penalty|lagrange>/threads:<T>/N:<N>".
//
// The KKT step alone (issue 17) on random problems of the sizes of the examples, over the same
// horizons: "solver/kkt/<size>/<route>/N:<N>", size spinner (n = 3, nu = 1), acrobot (n = 4,
// nu = 2), hopper (n = 5, nu = 3), ball_finger (n = 9, nu = 3) or allegro (n = 23, nu = 6); route
//   banded:   BandedKktSolver::Factor + Solve (λ and the Newton step p) + g_merit = g + Aᵀλ,
//             with one step of iterative refinement, its residual in double (banded_unrefined:
//             none; banded_extended: two steps with the residual in double-double;
//             banded_adaptive_taken: the step in double, then double-double steps as the
//             default takes them when the first correction exceeds extended_threshold(), here
//             with threshold 0, i.e. the maximum of kMaxExtendedSteps = 5;
//             banded_runtime_sizes: as banded, every block size through the run-time kernels,
//             set_compiled_block_sizes(false), the peer of the code compiled for m <= 8;
//             banded_2threads: as banded, with BandedKktSolver::set_num_threads(2));
//   dense:    today's route: block Cholesky of H, Y = L⁻¹Aᵀ, A H⁻¹ Aᵀ = YᵀY dense and its LLT,
//             λ, g_merit and p = −H⁻¹ g_merit (Aᵀ filled densely as CalcConstraints does);
//             not run for allegro at N = 320 (about 10 s and 0.3 GB);
//   cholesky: the block Cholesky of H and one solve in the natural order
//             (PentaDiagonalCholesky), the reference for "the ratio to the penta-diagonal
//             Cholesky";
//   cholesky_split, cholesky_split_2threads: the same in two halves, as the penalty method's
//             step takes it (internal::SplitPentaDiagonalCholesky; natural order below N = 8 or
//             blocks of 8), on 1 and 2 threads.

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "idto/idto.hpp"
#include "iteration_timing.hpp"
#include "math/split_penta_diagonal_cholesky.hpp"

namespace {

using idto::BodyIndex;

idto::BodyInertia Mass(double m, const Eigen::Vector3d& com) {
  idto::BodyInertia I;
  I.mass = m;
  I.p_BBcm = com;
  I.I_BBcm_B = Eigen::Matrix3d::Identity() * 1e-3 * m;
  return I;
}

idto::Model Pendulum() {
  idto::ModelBuilder b("pendulum");
  idto::JointSpec j;
  j.name = "hinge";
  j.type = idto::JointType::kRevolute;
  j.axis = Eigen::Vector3d::UnitY();
  j.damping = 0.1;
  b.AddBody("link", Mass(1.0, Eigen::Vector3d(0, 0, -1)), idto::kWorldBody, j);
  return b.Build();
}

idto::Model Acrobot() {
  idto::ModelBuilder b("acrobot");
  idto::JointSpec j1;
  j1.name = "shoulder";
  j1.type = idto::JointType::kRevolute;
  j1.axis = Eigen::Vector3d::UnitY();
  const BodyIndex l1 =
      b.AddBody("link1", Mass(1.0, Eigen::Vector3d(0, 0, -0.5)), idto::kWorldBody, j1);
  idto::JointSpec j2 = j1;
  j2.name = "elbow";
  j2.X_PJ.translation() << 0, 0, -1;
  b.AddBody("link2", Mass(1.0, Eigen::Vector3d(0, 0, -0.5)), l1, j2);
  return b.Build();
}

// A free ball on the ground pushed by a two-link finger (floating base + contact).
idto::Model BallAndFinger() {
  idto::ModelBuilder b("ball_and_finger");
  b.AddGeometry("ground", idto::kWorldBody, Eigen::Isometry3d::Identity(), idto::HalfSpace{});
  idto::JointSpec free;
  free.name = "ball_free";
  free.type = idto::JointType::kFloating;
  idto::BodyInertia ball;
  ball.mass = 0.2;
  ball.I_BBcm_B = Eigen::Matrix3d::Identity() * 2e-4;
  const BodyIndex bb = b.AddBody("ball", ball, idto::kWorldBody, free);
  b.AddGeometry("ball_sphere", bb, Eigen::Isometry3d::Identity(), idto::Sphere{0.05});
  idto::JointSpec j1;
  j1.name = "j1";
  j1.type = idto::JointType::kRevolute;
  j1.axis = Eigen::Vector3d::UnitY();
  j1.X_PJ.translation() << -0.3, 0.0, 0.3;
  const BodyIndex l1 = b.AddBody("l1", Mass(0.3, Eigen::Vector3d(0.1, 0, 0)), idto::kWorldBody, j1);
  idto::JointSpec j2 = j1;
  j2.name = "j2";
  j2.X_PJ.translation() << 0.2, 0.0, 0.0;
  const BodyIndex l2 = b.AddBody("l2", Mass(0.2, Eigen::Vector3d(0.1, 0, 0)), l1, j2);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() << 0.2, 0.0, 0.0;
  b.AddGeometry("tip", l2, X, idto::Sphere{0.02});
  return b.Build();
}

idto::ProblemDefinition MakeProblem(const idto::Model& model, const std::string& name, int N) {
  idto::ProblemDefinition p = idto::ProblemDefinition::MakeDefault(model, 0.05, N);
  p.Qq.setConstant(0.1);
  p.Qv.setConstant(0.1);
  p.R.setConstant(0.01);
  p.Qfq.setConstant(100.0);
  p.Qfv.setConstant(10.0);
  Eigen::VectorXd target = p.q_init;
  if (name == "pendulum") {
    target(0) = M_PI;
  } else if (name == "acrobot") {
    target << M_PI, 0.0;
    p.unactuated_dofs = std::vector<int>{0};
    p.R(0) = 100.0;
  } else {
    p.q_init << 1, 0, 0, 0, 0.0, 0.0, 0.049, 0.5, -1.2;
    target = p.q_init;
    target(4) = 0.2;
    p.R.head<6>().setConstant(100.0);
    p.contact.parameters.stiffness = 500.0;
    p.contact.parameters.smoothing = 0.01;
  }
  p.SetConstantNominal(target, Eigen::VectorXd::Zero(model.nv()));
  return p;
}

constexpr int kRestartEvery = 10;

void BM_SolverIteration(benchmark::State& state, const std::string& name, bool lagrange) {
  const int N = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const idto::Model model = name == "pendulum"  ? Pendulum()
                            : name == "acrobot" ? Acrobot()
                                                : BallAndFinger();
  const idto::ProblemDefinition p = MakeProblem(model, name, N);
  idto::SolverOptions o;
  o.max_iterations = 1;
  o.fixed_iterations = true;
  o.num_threads = threads;
  o.constraint_method =
      lagrange ? idto::ConstraintMethod::kLagrangeMultipliers : idto::ConstraintMethod::kPenalty;
  idto::TrajectoryOptimizer opt(model, p, o);
  const std::vector<Eigen::VectorXd> guess(N + 1, p.q_init);
  idto::Trajectory sol;
  // The first kRestartEvery iterations from the guess, over and over (iteration_timing.hpp).
  idto::bench::TimeSolverIterations(state, &opt, &sol, &guess, kRestartEvery);
  state.counters["nv"] = model.nv();
}

void Register() {
  for (const std::string name : {"pendulum", "acrobot", "ball_finger"}) {
    for (bool lagrange : {false, true}) {
      if (name == "pendulum" && lagrange) continue;  // no unactuated DoFs
      const std::string bench_name = "solver/" + name + "/" + (lagrange ? "lagrange" : "penalty");
      auto* b = benchmark::RegisterBenchmark(
          bench_name.c_str(),
          [name, lagrange](benchmark::State& s) { BM_SolverIteration(s, name, lagrange); });
      b->ArgNames({"N", "threads"})->Unit(benchmark::kMicrosecond)->UseRealTime();
      for (int N : {10, 20, 40, 80, 160, 320}) b->Args({N, 1});
      b->Args({40, 2});
    }
  }
}

// A random positive definite pentadiagonal H (block diagonally dominant), constraint blocks,
// g and h of the given sizes.
struct KktProblem {
  idto::PentaDiagonalMatrix H;
  idto::BlockConstraintJacobian A;
  Eigen::VectorXd g, h;
};

KktProblem RandomKktProblem(int N, int n, int nu) {
  std::mt19937 engine(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto random = [&](int rows, int cols, double scale) {
    Eigen::MatrixXd M(rows, cols);
    for (int j = 0; j < cols; ++j)
      for (int i = 0; i < rows; ++i) M(i, j) = scale * u(engine);
    return M;
  };
  KktProblem P{idto::PentaDiagonalMatrix(N, n), idto::BlockConstraintJacobian(N, n, nu), {}, {}};
  for (int k = 0; k < N; ++k) {
    const Eigen::MatrixXd R = random(n, n, 0.1 / n);
    P.H.C(k) = R + R.transpose();
    P.H.C(k).diagonal().array() += 3.0;
    if (k >= 1) P.H.B(k) = random(n, n, 0.1 / n);
    if (k >= 2) P.H.A(k) = random(n, n, 0.1 / n);
    for (int s = k - 1; s <= k + 1; ++s) {
      if (P.A.HasBlock(k, s)) P.A.Block(k, s) = random(nu, n, 1.0);
    }
  }
  P.g = random(N * n, 1, 1.0);
  P.h = random(N * nu, 1, 1.0);
  return P;
}

// extended: 0 the residual in double (the threshold infinite), 1 always in double-double (two
// steps), 2 a step in double then one in double-double (the default's adaptive step, taken).
void BM_KktBanded(benchmark::State& state, int n, int nu, int refinement_steps, int extended = 0,
                  int threads = 1, bool compiled_sizes = true) {
  const int N = static_cast<int>(state.range(0));
  const KktProblem P = RandomKktProblem(N, n, nu);
  idto::BandedKktSolver kkt(N, n, nu);
  kkt.set_refinement_steps(refinement_steps);
  kkt.set_extended_residual(extended == 1);
  kkt.set_extended_threshold(extended == 2 ? 0.0 : std::numeric_limits<double>::infinity());
  kkt.set_num_threads(threads);
  kkt.set_compiled_block_sizes(compiled_sizes);
  Eigen::VectorXd p(N * n), lambda(N * nu), g_merit(N * n);
  for (auto _ : state) {
    if (!kkt.Factor(P.H, P.A).ok()) {
      state.SkipWithError(kkt.status().Message().c_str());
      break;
    }
    kkt.Solve(P.g, P.h, &p, &lambda);
    g_merit = P.g;
    P.A.AddMultiplyTranspose(lambda, &g_merit);
    benchmark::DoNotOptimize(p.data());
    benchmark::DoNotOptimize(g_merit.data());
  }
}

void BM_KktDense(benchmark::State& state, int n, int nu) {
  const int N = static_cast<int>(state.range(0));
  const KktProblem P = RandomKktProblem(N, n, nu);
  idto::PentaDiagonalCholesky chol(N, n);
  const int m = N * nu;
  Eigen::MatrixXd At(N * n, m), Y(N * n, m), S(m, m);
  Eigen::LLT<Eigen::MatrixXd> S_llt(m);
  Eigen::VectorXd work(N * n), lambda(m), g_merit(N * n), p(N * n);
  for (auto _ : state) {
    chol.compute(P.H);
    At.setZero();
    for (int j = 0; j < N; ++j) {
      for (int s = j - 1; s <= j + 1; ++s) {
        if (P.A.HasBlock(j, s)) {
          At.block((s - 1) * n, j * nu, n, nu) = P.A.Block(j, s).transpose();
        }
      }
    }
    Y = At;
    for (int j = 0; j < N; ++j) {
      chol.SolveLowerInPlace(Y.middleCols(j * nu, nu), std::max(j - 2, 0));
    }
    S.setZero();
    S.selfadjointView<Eigen::Lower>().rankUpdate(Y.transpose());
    S_llt.compute(S);
    work = P.g;
    chol.SolveLowerInPlace(&work);
    lambda = P.h;
    lambda.noalias() -= Y.transpose() * work;
    S_llt.solveInPlace(lambda);
    g_merit = P.g;
    g_merit.noalias() += At * lambda;
    p = -g_merit;
    chol.SolveInPlace(&p);
    benchmark::DoNotOptimize(p.data());
  }
}

void BM_KktCholesky(benchmark::State& state, int n) {
  const int N = static_cast<int>(state.range(0));
  const KktProblem P = RandomKktProblem(N, n, 0);
  idto::PentaDiagonalCholesky chol(N, n);
  Eigen::VectorXd p(N * n);
  for (auto _ : state) {
    chol.compute(P.H);
    p = -P.g;
    chol.SolveInPlace(&p);
    benchmark::DoNotOptimize(p.data());
  }
}

// The penalty route's Newton step: the two-half factorization and solve (1 or 2 threads), the
// same arithmetic on either.
void BM_KktCholeskySplit(benchmark::State& state, int n, int threads) {
  const int N = static_cast<int>(state.range(0));
  const KktProblem P = RandomKktProblem(N, n, 0);
  idto::internal::SplitPentaDiagonalCholesky chol(N, n, threads);
  Eigen::VectorXd p(N * n);
  for (auto _ : state) {
    if (!chol.compute(P.H)) return state.SkipWithError("factorization failed");
    p = -P.g;
    chol.SolveInPlace(&p);
    benchmark::DoNotOptimize(p.data());
  }
}

void RegisterKkt() {
  struct Size {
    const char* name;
    int n, nu;
  };
  for (const Size size : {Size{"spinner", 3, 1}, Size{"acrobot", 4, 2}, Size{"hopper", 5, 3},
                          Size{"ball_finger", 9, 3}, Size{"allegro", 23, 6}}) {
    const std::string prefix = std::string("solver/kkt/") + size.name + "/";
    const int n = size.n;
    const int nu = size.nu;
    auto* banded = benchmark::RegisterBenchmark(
        (prefix + "banded").c_str(), [n, nu](benchmark::State& s) { BM_KktBanded(s, n, nu, 1); });
    auto* unrefined =
        benchmark::RegisterBenchmark((prefix + "banded_unrefined").c_str(),
                                     [n, nu](benchmark::State& s) { BM_KktBanded(s, n, nu, 0); });
    auto* extended = benchmark::RegisterBenchmark(
        (prefix + "banded_extended").c_str(),
        [n, nu](benchmark::State& s) { BM_KktBanded(s, n, nu, 1, 1); });
    auto* adaptive = benchmark::RegisterBenchmark(
        (prefix + "banded_adaptive_taken").c_str(),
        [n, nu](benchmark::State& s) { BM_KktBanded(s, n, nu, 1, 2); });
    auto* runtime_sizes = benchmark::RegisterBenchmark(
        (prefix + "banded_runtime_sizes").c_str(),
        [n, nu](benchmark::State& s) { BM_KktBanded(s, n, nu, 1, 0, 1, false); });
    auto* two_threads = benchmark::RegisterBenchmark(
        (prefix + "banded_2threads").c_str(),
        [n, nu](benchmark::State& s) { BM_KktBanded(s, n, nu, 1, 0, 2); });
    auto* dense = benchmark::RegisterBenchmark(
        (prefix + "dense").c_str(), [n, nu](benchmark::State& s) { BM_KktDense(s, n, nu); });
    auto* chol = benchmark::RegisterBenchmark((prefix + "cholesky").c_str(),
                                              [n](benchmark::State& s) { BM_KktCholesky(s, n); });
    auto* split =
        benchmark::RegisterBenchmark((prefix + "cholesky_split").c_str(),
                                     [n](benchmark::State& s) { BM_KktCholeskySplit(s, n, 1); });
    auto* split2 =
        benchmark::RegisterBenchmark((prefix + "cholesky_split_2threads").c_str(),
                                     [n](benchmark::State& s) { BM_KktCholeskySplit(s, n, 2); });
    for (auto* b : {banded, unrefined, extended, adaptive, runtime_sizes, two_threads, dense, chol,
                    split, split2}) {
      b->ArgNames({"N"})->Unit(benchmark::kMicrosecond)->UseRealTime();
      for (int N : {10, 20, 40, 80, 160, 320}) {
        if (b == dense && n * N > 23 * 160) continue;
        b->Args({N});
      }
    }
  }
}

const bool kRegistered = (Register(), RegisterKkt(), true);

}  // namespace
