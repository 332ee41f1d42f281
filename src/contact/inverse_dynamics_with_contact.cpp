#include "idto/contact/inverse_dynamics_with_contact.hpp"

#include "core/ticks.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"

namespace idto {

void CalcKinematicsAndContact(const Model& model, const ContactEngine& engine,
                              const Eigen::Ref<const Eigen::VectorXd>& q,
                              const Eigen::Ref<const Eigen::VectorXd>& v, Data* data,
                              ContactData* contact, const ContactReuse* reuse,
                              std::uint64_t* contact_ticks) {
  ForwardKinematics(model, q, v, data);
  const std::uint64_t t0 = contact_ticks != nullptr ? internal::Ticks() : 0;
  if (reuse != nullptr) {
    engine.EvaluateChanged(model, *data, *reuse->reference, *reuse->body_moved, contact);
  } else {
    engine.Evaluate(model, *data, contact);
  }
  if (contact_ticks != nullptr) *contact_ticks += internal::TicksSince(t0);
}

const Eigen::VectorXd& InverseDynamicsWithContact(
    const Model& model, const ContactEngine* engine, const Eigen::Ref<const Eigen::VectorXd>& q,
    const Eigen::Ref<const Eigen::VectorXd>& v, const Eigen::Ref<const Eigen::VectorXd>& a,
    Data* data, ContactData* contact, const ContactReuse* reuse, std::uint64_t* contact_ticks) {
  if (engine == nullptr) return InverseDynamics(model, q, v, a, data);
  CalcKinematicsAndContact(model, *engine, q, v, data, contact, reuse, contact_ticks);
  return InverseDynamicsAfterKinematics(model, v, a, &contact->F_ext, data);
}

}  // namespace idto
