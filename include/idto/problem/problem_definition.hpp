#pragma once

/// @file
/// The IDTO problem (paper §4): minimize over q_1..q_N
///   L(q) = sum_{k=0}^{N-1} dt [ 1/2 |q_k - qbar_k|^2_Qq + 1/2 |v_k - vbar_k|^2_Qv
///                               + 1/2 |tau_k|^2_R ]
///        + 1/2 |q_N - qbar_N|^2_Qfq + 1/2 |v_N - vbar_N|^2_Qfv
/// subject to h(q) = 0 (the unactuated rows of every tau_k), with q_0 = q_init, v_0 = v_init,
///   v_k = N+(q_k) (q_k - q_{k-1}) / dt,   a_k = (v_{k+1} - v_k) / dt,
///   tau_k = InverseDynamics(q_{k+1}, v_{k+1}, a_k) - J(q_{k+1})^T f(q_{k+1}, v_{k+1}).

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "idto/contact/contact_engine.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// Joint limits as smooth penalties in the cost (docs/solver.md, "Joint limits"): for each
/// limited entry x with bounds [lo, hi], the residual r = x - hi above, x - lo below, 0 inside
/// adds 1/2 w dt r^2 per time step: on q_k and v_k (k = 1..N) and on tau_k (k = 0..N-1). The
/// residuals are Gauss-Newton terms like the tracking ones (zero inside the limits, quadratic
/// outside). A weight of 0 (the default) turns that kind of limit off.
struct LimitPenalties {
  double position_weight{0.0};  ///< w on q outside [q_lower, q_upper]
  double velocity_weight{0.0};  ///< w on |v_i| above v_max_i
  double effort_weight{0.0};    ///< w on |tau_i| above tau_max_i
  /// Bounds; empty: the model's (Model::position_lower_limits() etc., from the URDF). q_lower,
  /// q_upper: nq (quaternion entries unbounded); v_max, tau_max: nv (>= 0; +inf: none).
  Eigen::VectorXd q_lower, q_upper, v_max, tau_max;

  bool any() const { return position_weight > 0 || velocity_weight > 0 || effort_weight > 0; }
};

/// Everything that defines one trajectory optimization problem on a Model.
struct ProblemDefinition {
  double time_step{0.05};  ///< dt, s (> 0)
  int num_steps{20};       ///< N (>= 1): the horizon is N dt

  Eigen::VectorXd q_init;  ///< q_0 (nq); quaternions are normalized on use
  Eigen::VectorXd v_init;  ///< v_0 (nv)

  /// Nominal trajectory qbar_k (nq each) and vbar_k (nv each), k = 0..N (N + 1 entries).
  std::vector<Eigen::VectorXd> q_nom;
  std::vector<Eigen::VectorXd> v_nom;

  /// Diagonal weights (non-negative): running Qq (nq), Qv (nv), R (nv); terminal Qfq (nq),
  /// Qfv (nv).
  Eigen::VectorXd Qq, Qv, R, Qfq, Qfv;

  /// Velocity indices whose generalized force must vanish. Unset: the model's base DoFs
  /// (floating and planar joints on the world, Model::is_base_velocity()).
  std::optional<std::vector<int>> unactuated_dofs;

  /// Contact: pairs, parameters, pruning. Disabled when `enable_contact` is false or the
  /// model has fewer than two geometries.
  bool enable_contact{true};
  ContactOptions contact;

  /// Joint limits as penalties (off by default).
  LimitPenalties limits;

  /// Throws InvalidArgument naming the field, the value found and what was expected: sizes,
  /// non-finite entries, negative weights, non-positive time step, N < 1, bad DoF indices.
  void Validate(const Model& model) const;

  /// The unactuated DoFs in effect (sorted, unique).
  std::vector<int> UnactuatedDofs(const Model& model) const;

  /// A problem with zero weights, q_init = neutral, v_init = 0 and nominal = q_init for all k.
  static ProblemDefinition MakeDefault(const Model& model, double time_step, int num_steps);
  /// Sets every nominal configuration to q and velocity to v.
  void SetConstantNominal(const Eigen::VectorXd& q, const Eigen::VectorXd& v);
};

}  // namespace idto
