#pragma once

// The equality-constraint multipliers of the Lagrange method (paper §5.2.2), dense route:
// lambda = (A H^-1 A^T)^-1 (h - A H^-1 g) with H factored once, through Y = L^-1 A^T so that
// A H^-1 A^T = Y^T Y and A H^-1 g = Y^T (L^-1 g). O((N n_u)^2 N nq) time and (N n_u)^2 memory.
// Private to src/.

#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "idto/math/penta_diagonal_matrix.hpp"
#include "idto/problem/trajectory_state.hpp"
#include "idto/problem/transcription.hpp"

namespace idto::internal {

class DenseMultipliers {
 public:
  // Buffers for N steps of nq coordinates and n_u constraints per step (allocates).
  void Resize(int num_steps, int nq, int num_unactuated);

  // With chol = the factor of H: *lambda (N n_u) and *g_merit = g + A^T lambda (N nq). False
  // with *why set when A H^-1 A^T is not positive definite. `h` (N n_u) is the constraint value.
  bool Compute(const Transcription& transcription, const TrajectoryDerivatives& derivatives,
               const PentaDiagonalCholesky& chol, const Eigen::VectorXd& g,
               const Eigen::VectorXd& h, Eigen::VectorXd* lambda, Eigen::VectorXd* g_merit,
               std::string* why);

 private:
  int N_{0}, nq_{0}, nu_{0};
  Eigen::MatrixXd At_;  // A^T = (dh/dq)^T: (N nq) x (N n_u)
  Eigen::MatrixXd Y_;   // L^-1 A^T: (N nq) x (N n_u)
  Eigen::MatrixXd S_;   // A H^-1 A^T = Y^T Y: (N n_u) square, lower triangle
  Eigen::LLT<Eigen::MatrixXd> S_llt_;
  Eigen::VectorXd Linv_g_;  // L^-1 g: N nq
};

}  // namespace idto::internal
