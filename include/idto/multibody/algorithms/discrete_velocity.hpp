#pragma once

/// @file
/// The velocity of the IDTO discretization (paper §4): v = N+(q) (q - q_prev) / dt, applied
/// without forming N+(q), and its exact partial derivatives with respect to both configurations
/// (including the dependence of N+ on q for quaternion joints).

#include <Eigen/Core>

#include "idto/multibody/model.hpp"

namespace idto {

/// v (nv) = N+(q) (q - q_prev) / dt for configurations q, q_prev (nq each), dt > 0.
/// Allocation-free when v already has nv entries.
void CalcDiscreteVelocity(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                          const Eigen::Ref<const Eigen::VectorXd>& q_prev, double dt,
                          Eigen::VectorXd* v);

/// Partials of CalcDiscreteVelocity at (q, q_prev), given its value v (nv):
/// *Nplus = N+(q) (nv x nq), *dv_dq = d v / d q (nv x nq, exact: for a floating joint the
/// angular rows are 4 / |Q|^2 G(Q_prev)^T / dt - 2 / |Q|^2 w Q^T), *dv_dq_prev = d v / d q_prev
/// (nv x nq, = -N+(q) / dt). Outputs must be preallocated nv x nq (allocation-free).
void CalcDiscreteVelocityPartials(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                                  const Eigen::Ref<const Eigen::VectorXd>& q_prev, double dt,
                                  const Eigen::Ref<const Eigen::VectorXd>& v,
                                  Eigen::MatrixXd* Nplus, Eigen::MatrixXd* dv_dq,
                                  Eigen::MatrixXd* dv_dq_prev);

}  // namespace idto
