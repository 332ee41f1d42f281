// The analytic TauDerivativeEvaluator: one derivative evaluation per time step. tau_k =
// ID(q_{k+1}, v_{k+1}, a_k) with contact; with P = d ID / d q (raw coordinates), B = d ID / d v
// + M / dt (v_{k+1} enters directly and through a_k) and M = M(q_{k+1}):
//   d tau_k / d q_{k+1} = P + B d v_{k+1} / d q_{k+1}
//   d tau_k / d q_k     = B d v_{k+1} / d q_k - (M / dt) d v_k / d q_k
//   d tau_k / d q_{k-1} = -(M / dt) d v_k / d q_{k-1}
// (the d v / d q blocks carry the derivative of N+(q) for quaternions).

#include <memory>

#include "core/parallel.hpp"
#include "idto/contact/contact_derivatives.hpp"
#include "idto/multibody/algorithms/rnea_derivatives-inl.hpp"
#include "idto/problem/transcription.hpp"
#include "problem/transcription_workspace.hpp"

namespace idto {
namespace {

class AnalyticEvaluator final : public TauDerivativeEvaluator {
 public:
  void Calc(const TrajectoryState& s, Transcription* t, TrajectoryDerivatives* d) const override {
    const Model& model = t->model();
    const ContactEngine* engine = t->engine();
    const double inv_dt = 1.0 / t->time_step();
    ParallelFor(0, t->num_steps(), t->num_threads(), [&](int k, int thread) {
      TranscriptionWorkspace& ws = t->workspace(thread);
      Data& data = ws.data;
      ComputeRneaDerivatives(model, s.q[k + 1], s.v[k + 1], s.a[k], nullptr, &data);
      if (engine != nullptr) {
        AddContactDerivatives(model, *engine, s.contact[k], data, &ws.contact_derivatives,
                              &data.dtau_dq_tangent, &data.dtau_dv);
        internal::RneaDerivativesToRawCoordinates(model, s.q[k + 1].data(), &data);
      }
      ws.Mdt = inv_dt * data.M;
      ws.B = data.dtau_dv + ws.Mdt;
      d->dtau_dqp[k] = data.dtau_dq;
      d->dtau_dqp[k].noalias() += ws.B * d->dv_dq[k + 1];
      if (k >= 1) {
        d->dtau_dq[k].noalias() = ws.B * d->dv_dqm[k + 1];
        d->dtau_dq[k].noalias() -= ws.Mdt * d->dv_dq[k];
      }
      if (k >= 2) d->dtau_dqm[k].noalias() = -ws.Mdt * d->dv_dqm[k];
    });
  }
};

}  // namespace

std::unique_ptr<TauDerivativeEvaluator> MakeAnalyticEvaluator() {
  return std::make_unique<AnalyticEvaluator>();
}

}  // namespace idto
