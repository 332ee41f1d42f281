#pragma once

/// @file
/// What the transcription computes at one iterate q_0..q_N (TrajectoryState), and the partial
/// derivatives it needs for the gradient and the Gauss-Newton Hessian (TrajectoryDerivatives).
/// N = ProblemDefinition::num_steps; every member states its shape and who computes it.

#include <vector>

#include <Eigen/Core>

#include "idto/contact/contact_engine.hpp"

namespace idto {

/// The iterate and the quantities derived from it (paper §4, eq. 3-5).
struct TrajectoryState {
  /// q_k, k = 0..N (N + 1 entries, nq each; q_0 = q_init). Set by the caller (the minimizer).
  std::vector<Eigen::VectorXd> q;
  /// v_k = N+(q_k) (q_k - q_{k-1}) / dt, k = 0..N (v_0 = v_init); nv each. Transcription::Evaluate.
  std::vector<Eigen::VectorXd> v;
  /// a_k = (v_{k+1} - v_k) / dt, k = 0..N-1; nv each. Transcription::Evaluate.
  std::vector<Eigen::VectorXd> a;
  /// tau_k = ID(q_{k+1}, v_{k+1}, a_k) - J^T f(q_{k+1}, v_{k+1}), k = 0..N-1; nv each.
  /// Transcription::Evaluate.
  std::vector<Eigen::VectorXd> tau;
  /// The contact evaluation behind tau_k, k = 0..N-1 (empty when the problem has no contact).
  /// Transcription::Evaluate; the finite differences reuse the pairs a perturbation leaves.
  std::vector<ContactData> contact;
  /// L(q), with the penalty term when it is on. Transcription::Evaluate.
  double cost{0.0};
};

/// Partial derivatives at one TrajectoryState, all dense blocks of the sparse Jacobians.
struct TrajectoryDerivatives {
  /// N+(q_k), k = 0..N (entry 0 unused); nv x nq. Transcription::CalcDerivatives.
  std::vector<Eigen::MatrixXd> Nplus;
  /// d v_k / d q_k (exact, with the dependence of N+ on q_k), k = 0..N (entry 0 unused);
  /// nv x nq. Transcription::CalcDerivatives.
  std::vector<Eigen::MatrixXd> dv_dq;
  /// d v_k / d q_{k-1} = -N+(q_k) / dt, k = 0..N (entry 0 unused); nv x nq.
  /// Transcription::CalcDerivatives.
  std::vector<Eigen::MatrixXd> dv_dqm;
  /// d tau_k / d q_{k-1}, d tau_k / d q_k, d tau_k / d q_{k+1}, k = 0..N-1; nv x nq each
  /// (d tau_0 / d q_0 and d tau_0 / d q_{-1} unused: q_0 is fixed). The derivative evaluator
  /// (TauDerivativeEvaluator) behind Transcription::CalcDerivatives.
  std::vector<Eigen::MatrixXd> dtau_dqm, dtau_dq, dtau_dqp;
  /// Scratch of the evaluators: M(q_k), k = 0..N; nv x nv.
  std::vector<Eigen::MatrixXd> M;

  /// d tau_j / d q_s for s in {j - 1, j, j + 1} (nv x nq).
  const Eigen::MatrixXd& DtauDq(int j, int s) const {
    if (s == j - 1) return dtau_dqm[j];
    if (s == j) return dtau_dq[j];
    return dtau_dqp[j];
  }
};

}  // namespace idto
