// The finite-difference TauDerivativeEvaluator: d tau_j / d q_s for s = j-1, j, j+1 by forward
// or central differences, except d tau_{k+1} / d q_k, which acts only through a_{k+1} and is
// exact: -M(q_{k+2}) (d v_{k+1} / d q_k) / dt.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "core/parallel.hpp"
#include "idto/multibody/algorithms/discrete_velocity.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/problem/transcription.hpp"
#include "problem/transcription_workspace.hpp"

namespace idto {
namespace {

class FiniteDifferenceEvaluator final : public TauDerivativeEvaluator {
 public:
  FiniteDifferenceEvaluator(bool central, double relative_step)
      : central_(central), requested_step_(relative_step) {}

  void Calc(const TrajectoryState& s, Transcription* t, TrajectoryDerivatives* d) const override {
    const double step = RelativeStep(t->engine() != nullptr);
    ParallelFor(1, t->num_steps() + 1, t->num_threads(), [&](int k, int thread) {
      TranscriptionWorkspace& ws = t->workspace(thread);
      DifferenceStep(s, k, step, t, &ws, d);
      // d tau_{k+1} / d q_k = -M(q_{k+2}) (d v_{k+1} / d q_k) / dt.
      if (k + 1 <= t->num_steps() - 1) {
        d->M[k + 2] = MassMatrix(t->model(), s.q[k + 2], &ws.data);
        d->dtau_dqm[k + 1].noalias() = (-1.0 / t->time_step()) * d->M[k + 2] * d->dv_dqm[k + 1];
      }
    });
  }

 private:
  // tau_{k-1} and tau_k with q_k replaced by ws->q (its coordinate i moved): into *out_prev and
  // (k < N) *out_here. Only bodies downstream of coordinate i's joint move: their pairs are
  // re-evaluated, the others reuse the iterate's contact results (exactly equal there).
  static void Perturbed(const TrajectoryState& s, int k, int i, const Transcription& t,
                        TranscriptionWorkspace* ws, Eigen::VectorXd* out_prev,
                        Eigen::VectorXd* out_here) {
    const double dt = t.time_step();
    const bool contact = t.engine() != nullptr;
    const std::vector<char>* moved = &t.bodies_moved_by(i);
    CalcDiscreteVelocity(t.model(), ws->q, s.q[k - 1], dt, &ws->v);
    ws->a = (ws->v - s.v[k - 1]) / dt;
    t.CalcTau(ws->q, ws->v, ws->a, ws, out_prev, nullptr, contact ? &s.contact[k - 1] : nullptr,
              contact ? moved : nullptr);
    if (k < t.num_steps()) {
      CalcDiscreteVelocity(t.model(), s.q[k + 1], ws->q, dt, &ws->v_next);
      ws->a_next = (ws->v_next - ws->v) / dt;
      t.CalcTau(s.q[k + 1], ws->v_next, ws->a_next, ws, out_here, nullptr,
                contact ? &s.contact[k] : nullptr, contact ? moved : nullptr);
    }
  }

  // Columns of d tau_{k-1} / d q_k and d tau_k / d q_k.
  void DifferenceStep(const TrajectoryState& s, int k, double relative_step, Transcription* t,
                      TranscriptionWorkspace* ws, TrajectoryDerivatives* d) const {
    const int N = t->num_steps();
    ws->q = s.q[k];
    for (int i = 0; i < t->nq(); ++i) {
      const double qi = s.q[k](i);
      const double h = relative_step * std::max(1.0, std::abs(qi));
      // Divide by the step actually applied: q_i +- h rounded to a double.
      const double q_plus = qi + h;
      if (central_) {
        const double q_minus = qi - h;
        const double h_applied = q_plus - q_minus;
        ws->q(i) = q_plus;
        Perturbed(s, k, i, *t, ws, &ws->tau_a, &ws->tau_b);
        ws->q(i) = q_minus;
        Perturbed(s, k, i, *t, ws, &ws->tau_c, &ws->tau_d);
        d->dtau_dqp[k - 1].col(i) = (ws->tau_a - ws->tau_c) / h_applied;
        if (k < N) d->dtau_dq[k].col(i) = (ws->tau_b - ws->tau_d) / h_applied;
      } else {
        const double h_applied = q_plus - qi;
        ws->q(i) = q_plus;
        Perturbed(s, k, i, *t, ws, &ws->tau_a, &ws->tau_b);
        d->dtau_dqp[k - 1].col(i) = (ws->tau_a - s.tau[k - 1]) / h_applied;
        if (k < N) d->dtau_dq[k].col(i) = (ws->tau_b - s.tau[k]) / h_applied;
      }
      ws->q(i) = qi;
    }
  }

  // The relative step: the requested one, else sqrt(eps) for forward differences, and for
  // central differences sqrt(eps) with contact and cbrt(eps) without. With contact, friction
  // inside its stiction band and the dissipation's branch points make cbrt(eps) ~ 6e-6
  // truncation-limited; sqrt(eps) measured more accurate at 8 of 15 points of the trade-off
  // report and worse at none (docs/tradeoffs.md §3). Without contact cbrt(eps) is the better
  // central step (the pendulum: 5.7e-10 against 2e-8 at 1e-7, docs/solver.md).
  double RelativeStep(bool contact) const {
    if (requested_step_ > 0.0) return requested_step_;
    const double eps = std::numeric_limits<double>::epsilon();
    return central_ && !contact ? std::cbrt(eps) : std::sqrt(eps);
  }

  bool central_;
  double requested_step_;
};

}  // namespace

std::unique_ptr<TauDerivativeEvaluator> MakeFiniteDifferenceEvaluator(DerivativeMethod method,
                                                                      double relative_step) {
  return std::make_unique<FiniteDifferenceEvaluator>(
      method == DerivativeMethod::kCentralDifferences, relative_step);
}

}  // namespace idto
