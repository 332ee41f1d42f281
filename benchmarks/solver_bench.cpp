// Solver: time per iteration and its breakdown (paper Figs. 6 and 7) for the pendulum, the
// acrobot and a small contact problem, over horizons N = 10 ... 320 (1 thread), penalty vs
// Lagrange multipliers, and N = 40 with 2 threads.
//
// Each benchmark iteration is one solver iteration (SolveWarmStart with max_iterations = 1 and
// fixed_iterations), which also re-evaluates the cost at the current iterate once: the
// reported time is slightly above the in-solver iteration time. Counters give the breakdown
// per iteration in microseconds (derivatives, hessian, factorization, multipliers, trial cost,
// and contact: the contact evaluations within derivatives and trial cost, CPU time summed over
// threads). The largest case (ball + finger, Lagrange, N = 320) takes about 0.7 s per
// iteration, so any --benchmark_min_time below that runs it exactly once.
// Names: "solver/<problem>/<penalty|lagrange>/threads:<T>/N:<N>".

#include <cmath>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Core>

#include "idto/idto.hpp"
#include "iteration_timing.hpp"

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
  opt.SetIterate(std::vector<Eigen::VectorXd>(N + 1, p.q_init));
  idto::Trajectory sol;
  idto::bench::TimeSolverIterations(state, &opt, &sol);
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

const bool kRegistered = (Register(), true);

}  // namespace
