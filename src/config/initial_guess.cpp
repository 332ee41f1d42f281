#include "idto/config/config.hpp"

// The first iterate of an example: constant, nominal, or interpolated (quaternions slerped).

#include <vector>

#include <Eigen/Geometry>

namespace idto {

Eigen::VectorXd InterpolateConfiguration(const Model& model, const Eigen::VectorXd& q_a,
                                         const Eigen::VectorXd& q_b, double s) {
  model.CheckConfiguration("InterpolateConfiguration", "q_a", q_a);
  model.CheckConfiguration("InterpolateConfiguration", "q_b", q_b);
  Eigen::VectorXd q = (1.0 - s) * q_a + s * q_b;
  for (JointIndex j : model.floating_joints()) {
    const int start = model.position_start(j);
    const Eigen::Quaterniond Qa =
        Eigen::Quaterniond(q_a(start), q_a(start + 1), q_a(start + 2), q_a(start + 3)).normalized();
    const Eigen::Quaterniond Qb =
        Eigen::Quaterniond(q_b(start), q_b(start + 1), q_b(start + 2), q_b(start + 3)).normalized();
    Eigen::Quaterniond Q = Qa.slerp(s, Qb).normalized();
    q(start) = Q.w();
    q(start + 1) = Q.x();
    q(start + 2) = Q.y();
    q(start + 3) = Q.z();
  }
  return q;
}

std::vector<Eigen::VectorXd> MakeInitialGuess(const ExampleConfig& config) {
  const ProblemDefinition& problem = config.problem;
  const int N = problem.num_steps;
  std::vector<Eigen::VectorXd> q(N + 1, problem.q_init);
  switch (config.initial_guess) {
    case InitialGuessType::kConstant:
      break;
    case InitialGuessType::kNominal:
      for (int k = 1; k <= N; ++k) q[k] = problem.q_nom[k];
      break;
    case InitialGuessType::kInterpolate:
      for (int k = 1; k <= N; ++k) {
        q[k] = InterpolateConfiguration(config.model, problem.q_init, problem.q_nom[N],
                                        static_cast<double>(k) / N);
      }
      break;
  }
  return q;
}

std::vector<Eigen::VectorXd> ControllerInitialGuess(const ExampleConfig& config) {
  const ProblemDefinition& problem = ControllerProblem(config);
  if (!config.mpc_initial_guess && problem.num_steps == config.problem.num_steps &&
      problem.q_init == config.problem.q_init) {
    return MakeInitialGuess(config);
  }
  ExampleConfig controller = config;
  controller.problem = problem;
  controller.initial_guess = config.mpc_initial_guess.value_or(config.initial_guess);
  return MakeInitialGuess(controller);
}

}  // namespace idto
