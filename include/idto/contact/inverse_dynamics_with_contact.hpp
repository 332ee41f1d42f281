#pragma once

/// @file
/// The one protocol for generalized forces with contact, used by the transcription (tau_k of
/// the paper's eq. 5) and the built-in plant: forward kinematics at (q, v), then the contact
/// evaluation on those poses and velocities, then RNEA with the contact body forces.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "idto/contact/contact_engine.hpp"
#include "idto/multibody/data.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// An earlier evaluation whose results pairs between unmoved bodies may reuse (the finite
/// differences: perturbing one coordinate moves only the bodies downstream of its joint).
struct ContactReuse {
  const ContactData* reference{nullptr};         ///< evaluation of the same engine
  const std::vector<char>* body_moved{nullptr};  ///< num_bodies flags
};

/// Forward kinematics of (q (nq), v (nv)) into *data, then the contact evaluation into
/// *contact (ContactEngine::Evaluate, or EvaluateChanged when `reuse` is given). When
/// `contact_ticks` is given, the ticks spent in the contact evaluation are added to it (see
/// SolverSummary's contact share). Allocation-free.
void CalcKinematicsAndContact(const Model& model, const ContactEngine& engine,
                              const Eigen::Ref<const Eigen::VectorXd>& q,
                              const Eigen::Ref<const Eigen::VectorXd>& v, Data* data,
                              ContactData* contact, const ContactReuse* reuse = nullptr,
                              std::uint64_t* contact_ticks = nullptr);

/// tau (nv) = ID(q, v, a) - sum_c J_c^T f_c(q, v): inverse dynamics with the compliant contact
/// forces of `engine` at (q, v). `engine` may be null (no contact): plain inverse dynamics.
/// *contact receives the contact evaluation (unused when engine is null); `reuse` and
/// `contact_ticks` as in CalcKinematicsAndContact. Returns data->tau. Allocation-free.
const Eigen::VectorXd& InverseDynamicsWithContact(const Model& model, const ContactEngine* engine,
                                                  const Eigen::Ref<const Eigen::VectorXd>& q,
                                                  const Eigen::Ref<const Eigen::VectorXd>& v,
                                                  const Eigen::Ref<const Eigen::VectorXd>& a,
                                                  Data* data, ContactData* contact,
                                                  const ContactReuse* reuse = nullptr,
                                                  std::uint64_t* contact_ticks = nullptr);

}  // namespace idto
