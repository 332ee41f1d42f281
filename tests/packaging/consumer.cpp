// Built against an installed idto by .ci/run: proves headers, library and CMake package work,
// using models from the installed share/idto.
#include <idto/idto.hpp>

#include <cmath>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: idto_consumer SHARE_DIR (the installed share/idto)\n";
    return 2;
  }
  const std::string share = argv[1];
  std::cout << "idto " << IDTO_VERSION_STRING << " found\n";
  try {
    idto::CheckPositive("consumer", "dt", -1.0);
    std::cerr << "expected an exception\n";
    return 1;
  } catch (const idto::InvalidArgument& e) {
    std::cout << "errors work: " << e.what() << "\n";
  }
  // Dynamics on an installed model: RNEA = M a + bias.
  idto::UrdfOptions options;
  options.base = idto::BaseType::kFloating;
  const idto::Model model = idto::ParseUrdfFile(share + "/models/quadruped.urdf", options);
  idto::Data data(model);
  Eigen::VectorXd q = model.NeutralConfiguration();
  const Eigen::VectorXd v = Eigen::VectorXd::Constant(model.nv(), 0.3);
  const Eigen::VectorXd a = Eigen::VectorXd::Constant(model.nv(), -0.2);
  const Eigen::VectorXd tau = idto::InverseDynamics(model, q, v, a, &data);
  const Eigen::VectorXd bias = idto::BiasTerm(model, q, v, &data);
  const Eigen::MatrixXd M = idto::MassMatrix(model, q, &data);
  const double err = (tau - (M * a + bias)).norm();
  std::cout << "quadruped: nq " << model.nq() << ", nv " << model.nv() << ", |RNEA - (Ma + b)| "
            << err << "\n";
  if (!(err < 1e-9)) return 1;
  // A short solve: the installed pendulum swings towards upright.
  const idto::Model pendulum = idto::ParseUrdfFile(share + "/models/pendulum.urdf");
  idto::ProblemDefinition problem = idto::ProblemDefinition::MakeDefault(pendulum, 0.05, 40);
  problem.Qq.setConstant(0.1);
  problem.Qv.setConstant(0.1);
  problem.R.setConstant(0.01);
  problem.Qfq.setConstant(1000.0);
  problem.Qfv.setConstant(100.0);
  problem.SetConstantNominal(Eigen::VectorXd::Constant(pendulum.nq(), M_PI),
                             Eigen::VectorXd::Zero(pendulum.nv()));
  idto::SolverOptions solver;
  solver.max_iterations = 300;
  idto::TrajectoryOptimizer optimizer(pendulum, problem, solver);
  idto::Trajectory solution;
  const idto::SolverSummary summary = optimizer.Solve(
      std::vector<Eigen::VectorXd>(problem.num_steps + 1, problem.q_init), &solution);
  std::cout << summary.BriefReport() << "\n";
  return summary.termination == idto::TerminationType::kFailure ? 1 : 0;
}
