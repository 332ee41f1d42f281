// The analytic TauDerivativeEvaluator: one derivative evaluation per time step. tau_k =
// ID(q_{k+1}, v_{k+1}, a_k) with contact; with P = d ID / d q (raw coordinates), B = d ID / d v
// + M / dt (v_{k+1} enters directly and through a_k) and M = M(q_{k+1}):
//   d tau_k / d q_{k+1} = P + B d v_{k+1} / d q_{k+1}
//   d tau_k / d q_k     = B d v_{k+1} / d q_k - (M / dt) d v_k / d q_k
//   d tau_k / d q_{k-1} = -(M / dt) d v_k / d q_{k-1}
// (the d v / d q blocks carry the derivative of N+(q) for quaternions).

#include <memory>

#include "core/parallel.hpp"
#include "core/ticks.hpp"
#include "idto/contact/contact_derivatives.hpp"
#include "idto/multibody/algorithms/rnea_derivatives-inl.hpp"
#include "idto/problem/transcription.hpp"
#include "problem/transcription_workspace.hpp"

namespace idto {
namespace {

// *out (nv x nq) += alpha X D for X (nv x nv) and D (nv x nq) a velocity partial (d v / d q or
// d v / d q_prev), which is block diagonal by joint: v_j depends on joint j's coordinates only.
// Block by block instead of a dense product: nv sum_j nv_j nq_j flops instead of nv^2 nq.
void AddTimesVelocityPartial(const Model& model, const Eigen::MatrixXd& X, const Eigen::MatrixXd& D,
                             double alpha, Eigen::MatrixXd* out) {
  for (BodyIndex b : model.moving_bodies()) {
    const int iv = model.velocity_start(b), iq = model.position_start(b);
    const int nv = model.joint_nv(b), nq = model.joint_nq(b);
    if (nv == 1 && nq == 1) {
      // A column axpy as a plain loop (Eigen's dynamic-size column expression costs more than
      // the spinner's three multiply-adds).
      const double scale = alpha * D(iv, iq);
      const Eigen::Index rows = X.rows();
      const double* x = X.data() + iv * rows;
      double* o = out->data() + iq * out->rows();
      for (Eigen::Index r = 0; r < rows; ++r) o[r] += scale * x[r];
    } else {
      // Tiny inner dimension (a joint's nv <= 6): a coefficient-wise product, not GEMM.
      out->middleCols(iq, nq).noalias() +=
          alpha * X.middleCols(iv, nv).lazyProduct(D.block(iv, iq, nv, nq));
    }
  }
}

class AnalyticEvaluator final : public TauDerivativeEvaluator {
 public:
  void Calc(const TrajectoryState& s, Transcription* t, TrajectoryDerivatives* d) const override {
    const Model& model = t->model();
    const ContactEngine* engine = t->engine();
    ParallelFor(0, t->num_steps(), t->num_threads(), [&](int k, int thread) {
      TranscriptionWorkspace& ws = t->workspace(thread);
      Data& data = ws.data;
      internal::ComputeRneaDerivativesTangent<double>(model, s.q[k + 1], s.v[k + 1], s.a[k],
                                                      nullptr, &data);
      if (engine != nullptr) {
        AddContactDerivatives(model, *engine, s.contact[k], data, &ws.contact_derivatives,
                              &data.dtau_dq_tangent, &data.dtau_dv);
      }
      ChainRule(*t, s, k, &ws, d);
    });
  }

  bool ProvidesTau() const override { return true; }

  // Per step: the RNEA derivatives (which yield ID(q, v, a) and the world-frame kinematics),
  // the contact evaluated on those kinematics, tau = ID - J^T f, the contact derivatives.
  void CalcWithTau(TrajectoryState* s, Transcription* t, TrajectoryDerivatives* d) const override {
    const Model& model = t->model();
    const ContactEngine* engine = t->engine();
    ParallelFor(0, t->num_steps(), t->num_threads(), [&](int k, int thread) {
      TranscriptionWorkspace& ws = t->workspace(thread);
      Data& data = ws.data;
      internal::ComputeRneaDerivativesTangent<double>(model, s->q[k + 1], s->v[k + 1], s->a[k],
                                                      nullptr, &data);
      s->tau[k] = data.tau;
      if (engine != nullptr) {
        ContactData& contact = s->contact[k];
        internal::CompleteKinematicsAfterRneaDerivatives(model, &data);
        const std::uint64_t t0 = internal::Ticks();
        engine->Evaluate(model, data, &contact);
        ws.contact_ticks += internal::TicksSince(t0);
        SubtractBodyForceTorques(model, contact.F_ext, data, &ws.F_subtree, &s->tau[k]);
        AddContactDerivatives(model, *engine, contact, data, &ws.contact_derivatives,
                              &data.dtau_dq_tangent, &data.dtau_dv);
      }
      ChainRule(*t, *s, k, &ws, d);
    });
  }

 private:
  // The three blocks of step k from the per-step partials in ws.data (module comment).
  static void ChainRule(const Transcription& t, const TrajectoryState& s, int k,
                        TranscriptionWorkspace* ws, TrajectoryDerivatives* d) {
    const Model& model = t.model();
    Data& data = ws->data;
    internal::RneaDerivativesToRawCoordinates(model, s.q[k + 1].data(), &data);
    ws->Mdt = (1.0 / t.time_step()) * data.M;
    ws->B = data.dtau_dv + ws->Mdt;
    d->dtau_dqp[k] = data.dtau_dq;
    AddTimesVelocityPartial(model, ws->B, d->dv_dq[k + 1], 1.0, &d->dtau_dqp[k]);
    if (k >= 1) {
      d->dtau_dq[k].setZero();
      AddTimesVelocityPartial(model, ws->B, d->dv_dqm[k + 1], 1.0, &d->dtau_dq[k]);
      AddTimesVelocityPartial(model, ws->Mdt, d->dv_dq[k], -1.0, &d->dtau_dq[k]);
    }
    if (k >= 2) {
      d->dtau_dqm[k].setZero();
      AddTimesVelocityPartial(model, ws->Mdt, d->dv_dqm[k], -1.0, &d->dtau_dqm[k]);
    }
  }
};

}  // namespace

std::unique_ptr<TauDerivativeEvaluator> MakeAnalyticEvaluator() {
  return std::make_unique<AnalyticEvaluator>();
}

}  // namespace idto
