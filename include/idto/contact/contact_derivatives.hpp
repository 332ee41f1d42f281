#pragma once

/// @file
/// Exact derivatives of the contact generalized forces tau_c(q, v) = -sum_pairs J_c(q)^T f_c(q,
/// v) with respect to q (tangent space) and v, to be added to those of RNEA
/// (ComputeRneaDerivatives) for d tau / d q and d tau / d v of inverse dynamics with contact.
///
/// Per evaluated pair, with F = (p_C x f, f) the spatial force on B at the world origin (A gets
/// -F), the derivative of F with respect to the rigid motions of A and B (world twists
/// eps = (theta, rho)) and to their spatial velocities V = (w, v at the world origin) is
/// assembled analytically from:
///  - the geometry: d(phi, n, p_WA, p_WB) / d eps. For analytic pairs it is exact: the
///    templated pair code (analytic_distance.hpp) runs on a 6-direction dual number over the
///    motion of B, and the motion of A follows from the invariance of the pair under a common
///    rigid motion (phi unchanged, n rotated, the witnesses carried along). Pairs answered by
///    FCL use a central difference over those six directions (step 1e-4 rad / 1e-4 m),
///    reported as such (ContactDerivativeStats::num_fcl_pairs);
///  - the contact velocity v_c = (v_B - v_A) + (w_B - w_A) x p_C, whose point p_C moves;
///  - the law (ContactForce's partials; at a dissipation branch point the right-hand branch).
/// The chain to q and v uses the world motion subspaces S, the velocity derivative directions
/// u (dV/dq = s x V + u) recorded by ComputeRneaDerivatives, and the derivative of J^T itself
/// (d S_j / d x_k = s_k x S_j for k before j).

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "idto/contact/contact_engine.hpp"
#include "idto/multibody/data.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// Scratch of AddContactDerivatives, sized by MakeContactDerivativeWorkspace (nothing is
/// allocated afterwards).
struct ContactDerivativeWorkspace {
  /// 6 x nv: Jacobians (world twists) of bodies A and B, their velocity derivatives dV/dq, and
  /// the derivative of a pair's spatial force with respect to q (tangent) and v.
  Eigen::Matrix<double, 6, Eigen::Dynamic> J_A, J_B, dV_A, dV_B, dF_dx, dF_dv;
  /// Net contact force (world origin) on each moving body, then summed over subtrees; 6 x nb.
  Eigen::Matrix<double, 6, Eigen::Dynamic> F_net;
  /// Velocity columns of the joints from the root to a body (capacity nv).
  std::vector<int> chain_A, chain_B, chain_union;
  /// Per velocity column: membership flags (nv), reset after each pair.
  std::vector<char> in_A, in_B;
  /// The (mobilized) body pairs in contact and the sum of their pairs' d F / d(eps, V)
  /// (6 x 24 each); capacity: the engine's number of pairs.
  std::vector<std::pair<BodyIndex, BodyIndex>> body_pairs;
  std::vector<Eigen::Matrix<double, 6, 24>> body_pair_D;
};

/// Counts of the last AddContactDerivatives call.
struct ContactDerivativeStats {
  int num_pairs{0};      ///< pairs differentiated (the evaluated ones)
  int num_fcl_pairs{0};  ///< of which by central differences of FCL's answer
};

/// A workspace for `model` and `engine`.
ContactDerivativeWorkspace MakeContactDerivativeWorkspace(const Model& model,
                                                          const ContactEngine& engine);

/// Adds d tau_c / d q (tangent coordinates, as Data::dtau_dq_tangent) to *dtau_dq_tangent
/// (nv x nv) and d tau_c / d v to *dtau_dv (nv x nv), for the pairs evaluated in `contact`.
/// `rnea` must hold ComputeRneaDerivatives at the (q, v) of `contact` (its S_, dV_dq_, body
/// velocities and poses are used); `contact` must hold engine.Evaluate at that (q, v) (the
/// pairs it pruned exert less than the engine's force tolerance and are left out, as in tau).
/// Allocation-free. Returns the counts.
ContactDerivativeStats AddContactDerivatives(const Model& model, const ContactEngine& engine,
                                             const ContactData& contact, const Data& rnea,
                                             ContactDerivativeWorkspace* ws,
                                             Eigen::MatrixXd* dtau_dq_tangent,
                                             Eigen::MatrixXd* dtau_dv);

/// *tau (nv) -= J(q)^T F_ext: the generalized forces of body forces F_ext (6 x num_bodies, each
/// column [moment about the body's origin; force], world frame: ContactData::F_ext), through
/// the world-frame motion subspaces of a ComputeRneaDerivatives pass at q in `rnea` (its S_ and
/// the poses X_WB_ of every body, welded ones after CompleteKinematicsAfterRneaDerivatives).
/// With tau = ID(q, v, a) from that pass this is InverseDynamics with the external forces, up to
/// round-off. F_subtree: scratch, 6 x num_bodies (resized only when its size differs).
void SubtractBodyForceTorques(const Model& model, const BodyForces& F_ext, const Data& rnea,
                              Eigen::Matrix<double, 6, Eigen::Dynamic>* F_subtree,
                              Eigen::VectorXd* tau);

}  // namespace idto
