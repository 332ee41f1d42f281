#pragma once

// Per-thread scratch of the transcription and its derivative evaluators (private to src/).

#include <cstdint>

#include <Eigen/Core>

#include "idto/contact/contact_derivatives.hpp"
#include "idto/contact/contact_engine.hpp"
#include "idto/multibody/data.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

struct TranscriptionWorkspace {
  TranscriptionWorkspace(const Model& model, const ContactEngine* engine)
      : data(model),
        v(Eigen::VectorXd::Zero(model.nv())),
        v_next(Eigen::VectorXd::Zero(model.nv())),
        a(Eigen::VectorXd::Zero(model.nv())),
        a_next(Eigen::VectorXd::Zero(model.nv())),
        tau_a(Eigen::VectorXd::Zero(model.nv())),
        tau_b(Eigen::VectorXd::Zero(model.nv())),
        tau_c(Eigen::VectorXd::Zero(model.nv())),
        tau_d(Eigen::VectorXd::Zero(model.nv())),
        q(Eigen::VectorXd::Zero(model.nq())),
        scratch_v(Eigen::VectorXd::Zero(model.nv())),
        stacked_t(Eigen::MatrixXd::Zero(model.nq(), 3 * model.nv())),
        stacked_prev_t(Eigen::MatrixXd::Zero(model.nq(), 2 * model.nv())),
        scratch_qv(Eigen::MatrixXd::Zero(model.nq(), model.nv())),
        sqrt_w(Eigen::VectorXd::Zero(model.nv())),
        Mdt(Eigen::MatrixXd::Zero(model.nv(), model.nv())),
        B(Eigen::MatrixXd::Zero(model.nv(), model.nv())),
        w_q(Eigen::VectorXd::Zero(model.nq())),
        w_v(Eigen::VectorXd::Zero(model.nv())),
        w_v_next(Eigen::VectorXd::Zero(model.nv())),
        w_tau(Eigen::VectorXd::Zero(model.nv())) {
    if (engine != nullptr) contact_derivatives = MakeContactDerivativeWorkspace(model, *engine);
    if (engine != nullptr) contact = engine->MakeData(model);
    F_subtree.setZero(6, model.num_bodies());
  }
  Data data;
  ContactData contact;
  // Ticks this thread spent in contact evaluation since the last TakeContactTicks() (written
  // by this thread only; read after the parallel loop).
  std::uint64_t contact_ticks{0};
  // Finite differences: perturbed q, v, a and their tau (nq / nv each).
  Eigen::VectorXd v, v_next, a, a_next, tau_a, tau_b, tau_c, tau_d, q;
  // Assembly scratch (nested Eigen products would otherwise allocate temporaries): nv.
  Eigen::VectorXd scratch_v;
  // Hessian rows (Transcription::CalcHessianRow): the transposed weighted torque partials side
  // by side over the steps that involve q_k (nq x 3 nv) and q_{k-1} (nq x 2 nv), one such block
  // (nq x nv), and the square roots of a step's torque weights (nv).
  Eigen::MatrixXd stacked_t, stacked_prev_t, scratch_qv;
  Eigen::VectorXd sqrt_w;
  // Analytic derivatives: M / dt and d ID / d v + M / dt (nv x nv), and the contact part's
  // scratch.
  Eigen::MatrixXd Mdt, B;
  // Evaluation with derivatives: the contact forces summed over each moving body's subtree
  // (6 x num_bodies; SubtractBodyForceTorques).
  Eigen::Matrix<double, 6, Eigen::Dynamic> F_subtree;
  // Hessian rows with limit penalties: the weights with the active limit terms (nq, nv, nv, nv).
  Eigen::VectorXd w_q, w_v, w_v_next, w_tau;
  ContactDerivativeWorkspace contact_derivatives;
};

}  // namespace idto
