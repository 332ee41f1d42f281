#pragma once

/// @file
/// PD+ tracking control (paper eq. 14): u = u_ff + Kp (q_d - q) + Kd (v_d - v) on the actuated
/// DoFs, with (q_d, v_d, u_ff) from a plan.

#include <vector>

#include <Eigen/Core>

#include "idto/multibody/model.hpp"

namespace idto::mpc {

/// Gains per actuated DoF.
struct PdGains {
  Eigen::VectorXd Kp;  ///< per velocity coordinate (nv); N m/rad or N/m; 0 on unactuated DoFs
  Eigen::VectorXd Kd;  ///< per velocity coordinate (nv); N m s/rad or N s/m
};

/// Maps a plan sample to generalized forces on the actuated DoFs.
class PdController {
 public:
  /// `actuated`: velocity indices driven by actuators (1-DoF joints only; floating and planar
  /// joints cannot be actuated here). Gains are nv-sized, non-negative (throws otherwise).
  PdController(const Model& model, const std::vector<int>& actuated, const PdGains& gains);

  /// u (nv): zero on unactuated DoFs; on actuated DoF i with position coordinate j:
  /// u_i = u_ff_i + Kp_i (q_d_j - q_j) + Kd_i (v_d_i - v_i). Inputs: q, q_d (nq), v, v_d, u_ff
  /// (nv).
  void Compute(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& q_d,
               const Eigen::VectorXd& v_d, const Eigen::VectorXd& u_ff, Eigen::VectorXd* u) const;

  const std::vector<int>& actuated() const { return actuated_; }

 private:
  std::vector<int> actuated_;
  std::vector<int> position_index_;  // per actuated DoF
  PdGains gains_;
  int nv_{0};
};

}  // namespace idto::mpc
