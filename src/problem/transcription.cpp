#include "idto/problem/transcription.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "core/parallel.hpp"
#include "idto/contact/inverse_dynamics_with_contact.hpp"
#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/discrete_velocity.hpp"
#include "math/block_kernels.hpp"
#include "problem/transcription_workspace.hpp"

namespace idto {

namespace {

// How far x lies outside [lo, hi] (signed; 0 inside).
inline double Excess(double x, double lo, double hi) {
  return x > hi ? x - hi : (x < lo ? x - lo : 0.0);
}

// out_i += w excess_i: the limit residuals' contribution to a weighted residual vector.
template <typename Out>
void AddExcess(const Eigen::VectorXd& x, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
               double w, Out* out) {
  for (Eigen::Index i = 0; i < x.size(); ++i) (*out)(i) += w * Excess(x(i), lo(i), hi(i));
}

// *out = base + w on the entries outside [lo, hi] (the Gauss-Newton weight of the limit terms).
const Eigen::VectorXd& ActiveWeights(const Eigen::VectorXd& base, const Eigen::VectorXd& x,
                                     const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, double w,
                                     Eigen::VectorXd* out) {
  if (w <= 0.0) return base;
  *out = base;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (x(i) > hi(i) || x(i) < lo(i)) (*out)(i) += w;
  }
  return *out;
}

double ExcessSquared(const Eigen::VectorXd& x, const Eigen::VectorXd& lo,
                     const Eigen::VectorXd& hi) {
  double sum = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double e = Excess(x(i), lo(i), hi(i));
    sum += e * e;
  }
  return sum;
}

}  // namespace

Transcription::Transcription(const Model& model, const ProblemDefinition& problem)
    : model_(model), problem_(problem) {
  problem_.Validate(model_);
  N_ = problem_.num_steps;
  nq_ = model_.nq();
  nv_ = model_.nv();
  dt_ = problem_.time_step;
  unactuated_ = problem_.UnactuatedDofs(model_);
  if (problem_.enable_contact && model_.geometries().size() >= 2) {
    engine_.emplace(model_, problem_.contact);
    if (engine_->num_pairs() == 0) engine_.reset();
  }
  // Bodies downstream of each position coordinate's joint (welded bodies included).
  moved_by_q_.assign(nq_, std::vector<char>(model_.num_bodies(), 0));
  for (BodyIndex b = 1; b < model_.num_bodies(); ++b) {
    for (BodyIndex m = model_.mobilized_body(b); m != kWorldBody; m = model_.moving_parent(m)) {
      for (int k = 0; k < model_.joint_nq(m); ++k) {
        moved_by_q_[model_.position_start(m) + k][b] = 1;
      }
    }
  }
  SetPenaltyWeight(0.0);
  SetNumThreads(1);
  SetDerivativeMethod(DerivativeMethod::kAnalytic, 0.0);
}

Transcription::~Transcription() = default;
Transcription::Transcription(Transcription&&) noexcept = default;
Transcription& Transcription::operator=(Transcription&&) noexcept = default;

void Transcription::SetInitialConditions(const Eigen::VectorXd& q_init,
                                         const Eigen::VectorXd& v_init) {
  problem_.q_init = q_init;
  problem_.v_init = v_init;
}

void Transcription::SetProblem(ProblemDefinition problem) {
  problem_ = std::move(problem);
  SetPenaltyWeight(penalty_weight_);
}

void Transcription::SetPenaltyWeight(double weight) {
  penalty_weight_ = weight;
  R_eff_ = problem_.R;
  if (weight > 0.0) {
    for (int d : unactuated_) R_eff_(d) = weight;
  }
  WR_ = dt_ * R_eff_;
  Wq_run_ = dt_ * problem_.Qq;
  Wv_run_ = dt_ * problem_.Qv;
  SetUpLimits();
}

void Transcription::SetUpLimits() {
  const LimitPenalties& l = problem_.limits;
  const auto either = [](const Eigen::VectorXd& given, const Eigen::VectorXd& model) {
    return given.size() > 0 ? given : model;
  };
  q_lo_ = either(l.q_lower, model_.position_lower_limits());
  q_hi_ = either(l.q_upper, model_.position_upper_limits());
  v_hi_ = either(l.v_max, model_.velocity_limits());
  tau_hi_ = either(l.tau_max, model_.effort_limits());
  v_lo_ = -v_hi_;
  tau_lo_ = -tau_hi_;
  wq_lim_ = dt_ * l.position_weight;
  wv_lim_ = dt_ * l.velocity_weight;
  wt_lim_ = dt_ * l.effort_weight;
}

void Transcription::SetNumThreads(int num_threads) {
  if (num_threads < 1) {
    ThrowInvalidArgument("Transcription::SetNumThreads", "num_threads", std::to_string(num_threads),
                         ">= 1");
  }
  num_threads_ = num_threads;
  workspaces_.reserve(num_threads);
  while (static_cast<int>(workspaces_.size()) < num_threads) {
    workspaces_.push_back(std::make_unique<TranscriptionWorkspace>(model_, engine()));
  }
}

void Transcription::SetDerivativeMethod(DerivativeMethod method, double relative_step) {
  // Only on change: repeated solves (MPC) re-apply their options without allocating.
  if (evaluator_ && !custom_evaluator_ && method == derivative_method_ &&
      relative_step == relative_step_) {
    return;
  }
  evaluator_ = MakeTauDerivativeEvaluator(method, relative_step);
  derivative_method_ = method;
  relative_step_ = relative_step;
  custom_evaluator_ = false;
}

void Transcription::SetDerivativeEvaluator(std::unique_ptr<TauDerivativeEvaluator> evaluator) {
  if (evaluator == nullptr) {
    ThrowInvalidArgument("Transcription::SetDerivativeEvaluator", "evaluator", "null",
                         "an evaluator");
  }
  evaluator_ = std::move(evaluator);
  custom_evaluator_ = true;
}

std::unique_ptr<TauDerivativeEvaluator> MakeTauDerivativeEvaluator(DerivativeMethod method,
                                                                   double relative_step) {
  switch (method) {
    case DerivativeMethod::kForwardDifferences:
    case DerivativeMethod::kCentralDifferences:
      return MakeFiniteDifferenceEvaluator(method, relative_step);
    case DerivativeMethod::kAnalytic:
      return MakeAnalyticEvaluator();
  }
  ThrowInvalidArgument("MakeTauDerivativeEvaluator", "method",
                       std::to_string(static_cast<int>(method)), "a DerivativeMethod");
}

TrajectoryState Transcription::MakeState() const {
  const Eigen::VectorXd zq = Eigen::VectorXd::Zero(nq_), zv = Eigen::VectorXd::Zero(nv_);
  TrajectoryState s;
  s.q.assign(N_ + 1, zq);
  s.v.assign(N_ + 1, zv);
  s.a.assign(N_, zv);
  s.tau.assign(N_, zv);
  if (engine_) s.contact.assign(N_, engine_->MakeData(model_));
  return s;
}

TrajectoryDerivatives Transcription::MakeDerivatives() const {
  const Eigen::MatrixXd zvq = Eigen::MatrixXd::Zero(nv_, nq_);
  TrajectoryDerivatives d;
  d.Nplus.assign(N_ + 1, zvq);
  d.dv_dq.assign(N_ + 1, zvq);
  d.dv_dqm.assign(N_ + 1, zvq);
  d.dtau_dqm.assign(N_, zvq);
  d.dtau_dq.assign(N_, zvq);
  d.dtau_dqp.assign(N_, zvq);
  d.M.assign(N_ + 1, Eigen::MatrixXd::Zero(nv_, nv_));
  return d;
}

void Transcription::CalcTau(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                            const Eigen::VectorXd& a, TranscriptionWorkspace* ws,
                            Eigen::VectorXd* tau, ContactData* contact,
                            const ContactData* reuse_from, const std::vector<char>* moved) const {
  const ContactReuse reuse{reuse_from, moved};
  *tau = InverseDynamicsWithContact(model_, engine(), q, v, a, &ws->data,
                                    contact != nullptr ? contact : &ws->contact,
                                    reuse_from != nullptr ? &reuse : nullptr, &ws->contact_ticks);
}

void Transcription::CalcVelocities(TrajectoryState* s) const {
  s->v[0] = problem_.v_init;
  for (int k = 1; k <= N_; ++k) CalcDiscreteVelocity(model_, s->q[k], s->q[k - 1], dt_, &s->v[k]);
  for (int k = 0; k < N_; ++k) s->a[k] = (s->v[k + 1] - s->v[k]) / dt_;
}

double Transcription::Evaluate(TrajectoryState* s) {
  CalcVelocities(s);
  ParallelFor(0, N_, num_threads_, [&](int k, int thread) {
    CalcTau(s->q[k + 1], s->v[k + 1], s->a[k], workspaces_[thread].get(), &s->tau[k],
            engine_ ? &s->contact[k] : nullptr);
  });
  s->cost = Cost(*s);
  return s->cost;
}

double Transcription::Cost(const TrajectoryState& s) const {
  // Fixed summation order: bitwise identical for any thread count.
  double L = 0.0;
  for (int k = 0; k < N_; ++k) {
    double running = 0.0;
    for (int i = 0; i < nq_; ++i) {
      const double e = s.q[k](i) - problem_.q_nom[k](i);
      running += problem_.Qq(i) * e * e;
    }
    for (int i = 0; i < nv_; ++i) {
      const double e = s.v[k](i) - problem_.v_nom[k](i);
      running += problem_.Qv(i) * e * e + R_eff_(i) * s.tau[k](i) * s.tau[k](i);
    }
    L += 0.5 * dt_ * running + LimitCost(s, k);
  }
  double terminal = 0.0;
  for (int i = 0; i < nq_; ++i) {
    const double e = s.q[N_](i) - problem_.q_nom[N_](i);
    terminal += problem_.Qfq(i) * e * e;
  }
  for (int i = 0; i < nv_; ++i) {
    const double e = s.v[N_](i) - problem_.v_nom[N_](i);
    terminal += problem_.Qfv(i) * e * e;
  }
  return L + 0.5 * terminal + LimitCost(s, N_);
}

double Transcription::LimitCost(const TrajectoryState& s, int k) const {
  double sum = 0.0;
  if (k >= 1) {
    sum += wq_lim_ * ExcessSquared(s.q[k], q_lo_, q_hi_);
    sum += wv_lim_ * ExcessSquared(s.v[k], v_lo_, v_hi_);
  }
  if (k < N_) sum += wt_lim_ * ExcessSquared(s.tau[k], tau_lo_, tau_hi_);
  return 0.5 * sum;
}

std::string Transcription::DescribeNonFiniteCost(const TrajectoryState& s) const {
  for (int k = 0; k <= N_; ++k) {
    if (!s.q[k].allFinite()) return "q_" + std::to_string(k) + " (the guess) is not finite";
    if (!s.v[k].allFinite())
      return "v_" + std::to_string(k) + " is not finite (time_step too small?)";
    if (k < N_ && !s.tau[k].allFinite()) {
      return "tau_" + std::to_string(k) + " (inverse dynamics with contact) is not finite";
    }
  }
  // Each term of the cost on its own, in the order of the YAML keys.
  const auto term = [&](const Eigen::VectorXd& w, auto value) {
    double sum = 0.0;
    for (int k = 0; k <= N_; ++k) sum += value(k, w);
    return sum;
  };
  struct Term {
    const char* key;
    double value;
  };
  const auto sq = [](const Eigen::VectorXd& w, const Eigen::VectorXd& e) {
    return w.dot(e.cwiseProduct(e));
  };
  const Term terms[] = {
      {"problem.weights.Qq", term(problem_.Qq,
                                  [&](int k, const Eigen::VectorXd& w) {
                                    return k < N_ ? sq(w, s.q[k] - problem_.q_nom[k]) : 0.0;
                                  })},
      {"problem.weights.Qv", term(problem_.Qv,
                                  [&](int k, const Eigen::VectorXd& w) {
                                    return k < N_ ? sq(w, s.v[k] - problem_.v_nom[k]) : 0.0;
                                  })},
      {"problem.weights.R",
       term(R_eff_,
            [&](int k, const Eigen::VectorXd& w) { return k < N_ ? sq(w, s.tau[k]) : 0.0; })},
      {"problem.weights.Qfq", sq(problem_.Qfq, s.q[N_] - problem_.q_nom[N_])},
      {"problem.weights.Qfv", sq(problem_.Qfv, s.v[N_] - problem_.v_nom[N_])},
  };
  for (const Term& t : terms) {
    if (!std::isfinite(0.5 * dt_ * t.value)) {
      return std::string(t.key) + ": its term of the cost overflows (" + std::to_string(t.value) +
             "); expected weights and states whose squares fit";
    }
  }
  return "problem.limits: the limit penalties overflow";
}

double Transcription::ConstraintViolation(const TrajectoryState& s) const {
  double sum = 0.0;
  for (int k = 0; k < N_; ++k) {
    for (int d : unactuated_) sum += s.tau[k](d) * s.tau[k](d);
  }
  return sum;
}

void Transcription::CalcVelocityPartials(const TrajectoryState& s, TrajectoryDerivatives* d) const {
  for (int k = 1; k <= N_; ++k) {
    CalcDiscreteVelocityPartials(model_, s.q[k], s.q[k - 1], dt_, s.v[k], &d->Nplus[k],
                                 &d->dv_dq[k], &d->dv_dqm[k]);
  }
}

void Transcription::CalcDerivatives(const TrajectoryState& s, TrajectoryDerivatives* d) {
  CalcVelocityPartials(s, d);
  evaluator_->Calc(s, this, d);
}

double Transcription::EvaluateWithDerivatives(TrajectoryState* s, TrajectoryDerivatives* d) {
  CalcVelocities(s);
  CalcVelocityPartials(*s, d);
  evaluator_->CalcWithTau(s, this, d);
  s->cost = Cost(*s);
  return s->cost;
}

void TauDerivativeEvaluator::CalcWithTau(TrajectoryState*, Transcription*,
                                         TrajectoryDerivatives*) const {
  throw std::logic_error(
      "TauDerivativeEvaluator::CalcWithTau: this derivative method does not evaluate tau "
      "(ProvidesTau() is false); call Evaluate and CalcDerivatives");
}

namespace {

// out += M^T t (M: rows x cols). Below 8 rows as plain dot products (Eigen's dynamic-size
// matrix-vector product spends most of its time dispatching on the spinner's 3 x 3 blocks).
template <typename Out>
void AddTransposeTimes(const Eigen::MatrixXd& M, const Eigen::VectorXd& t, Out&& out) {
  const int rows = static_cast<int>(M.rows());
  if (rows >= 8) {
    out.noalias() += M.transpose() * t;
    return;
  }
  for (int c = 0; c < M.cols(); ++c) {
    const double* m = M.data() + static_cast<long>(c) * rows;
    double sum = 0.0;
    for (int r = 0; r < rows; ++r) sum += m[r] * t[r];
    out[c] += sum;
  }
}

}  // namespace

void Transcription::CalcGradientRow(const TrajectoryState& s, const TrajectoryDerivatives& d, int k,
                                    TranscriptionWorkspace* ws, Eigen::VectorXd* g) const {
  Eigen::VectorXd& t = ws->scratch_v;
  auto gk = g->segment((k - 1) * nq_, nq_);
  gk = Wq(k).cwiseProduct(s.q[k] - problem_.q_nom[k]);
  if (wq_lim_ > 0.0) AddExcess(s.q[k], q_lo_, q_hi_, wq_lim_, &gk);
  t = Wv(k).cwiseProduct(s.v[k] - problem_.v_nom[k]);
  if (wv_lim_ > 0.0) AddExcess(s.v[k], v_lo_, v_hi_, wv_lim_, &t);
  AddTransposeTimes(d.dv_dq[k], t, gk);
  if (k < N_) {
    t = Wv(k + 1).cwiseProduct(s.v[k + 1] - problem_.v_nom[k + 1]);
    if (wv_lim_ > 0.0) AddExcess(s.v[k + 1], v_lo_, v_hi_, wv_lim_, &t);
    AddTransposeTimes(d.dv_dqm[k + 1], t, gk);
  }
  for (int j = k - 1; j <= k + 1; ++j) {
    if (j < 0 || j > N_ - 1) continue;
    t = WR_.cwiseProduct(s.tau[j]);
    if (wt_lim_ > 0.0) AddExcess(s.tau[j], tau_lo_, tau_hi_, wt_lim_, &t);
    AddTransposeTimes(d.DtauDq(j, k), t, gk);
  }
}

void Transcription::CalcGradient(const TrajectoryState& s, const TrajectoryDerivatives& d,
                                 Eigen::VectorXd* g) {
  ParallelFor(1, N_ + 1, num_threads_,
              [&](int k, int thread) { CalcGradientRow(s, d, k, workspaces_[thread].get(), g); });
}

void Transcription::CalcGradientAndHessian(const TrajectoryState& s, const TrajectoryDerivatives& d,
                                           Eigen::VectorXd* g, PentaDiagonalMatrix* H) {
  // One parallel phase for both (each row's work is the one CalcGradient and CalcHessian do).
  ParallelFor(1, N_ + 1, num_threads_, [&](int k, int thread) {
    CalcGradientRow(s, d, k, workspaces_[thread].get(), g);
    CalcHessianRow(s, d, k, workspaces_[thread].get(), H);
  });
}

namespace {

// The lower triangle of *out += D1^T diag(w) D2 for D1, D2 velocity partials (d v_k / d q_k or
// d v_k / d q_{k-1}): both are block diagonal by joint (v_j depends on joint j's coordinates
// only), so the product is too: sum_j nq_j^2 nv_j flops instead of nq^2 nv. With D1 != D2 (the
// sub-diagonal block B) the whole joint block is formed.
void AddVelocityGram(const Model& model, const Eigen::MatrixXd& D1, const Eigen::VectorXd& w,
                     const Eigen::MatrixXd& D2, bool lower_only, Eigen::MatrixXd* out) {
  for (BodyIndex b : model.moving_bodies()) {
    const int iv = model.velocity_start(b), iq = model.position_start(b);
    const int nv = model.joint_nv(b), nq = model.joint_nq(b);
    for (int c = 0; c < nq; ++c) {
      for (int r = lower_only ? c : 0; r < nq; ++r) {
        double sum = 0.0;
        for (int i = 0; i < nv; ++i) sum += D1(iv + i, iq + r) * w(iv + i) * D2(iv + i, iq + c);
        (*out)(iq + r, iq + c) += sum;
      }
    }
  }
}

// G^T = (diag(sqrt_w) X)^T (nq x nv), the transposed weighted rows of a torque partial X
// (nv x nq): H's torque terms are then sums of G1^T G2 = (G1^T)(G2^T)^T, products of two matrices
// with nq rows (internal::AddProductNT).
template <typename Derived>
void ScaleRowsTransposed(const Eigen::VectorXd& sqrt_w, const Eigen::MatrixXd& X,
                         const Eigen::MatrixBase<Derived>& Gt_out) {
  auto& Gt = const_cast<Eigen::MatrixBase<Derived>&>(Gt_out);
  Gt.noalias() = (sqrt_w.asDiagonal() * X).transpose();
}

}  // namespace

void Transcription::CalcHessianRow(const TrajectoryState& s, const TrajectoryDerivatives& d, int k,
                                   TranscriptionWorkspace* ws, PentaDiagonalMatrix* H) const {
  // Weights with the active limit terms added (the plain weights when limits are off).
  const auto w_v = [&](int i, Eigen::VectorXd* out) -> const Eigen::VectorXd& {
    return ActiveWeights(Wv(i), s.v[i], v_lo_, v_hi_, wv_lim_, out);
  };
  const auto w_tau = [&](int j) -> const Eigen::VectorXd& {
    return ActiveWeights(WR_, s.tau[j], tau_lo_, tau_hi_, wt_lim_, &ws->w_tau);
  };
  const int r = k - 1;
  const int nv = model_.nv();
  // S^T: the transposed weighted torque partials w.r.t. q_k of the steps j = k-1, k, k+1 that
  // exist, side by side (j = k-1 first); S_prev^T: those of j = k-1, k w.r.t. q_{k-1}.
  Eigen::MatrixXd& St = ws->stacked_t;
  Eigen::MatrixXd& St_prev = ws->stacked_prev_t;
  const int j_first = std::max(k - 1, 0), j_last = std::min(k + 1, N_ - 1);
  int cols = 0, cols_prev = 0;
  for (int j = j_first; j <= j_last; ++j, cols += nv) {
    ws->sqrt_w = w_tau(j).cwiseSqrt();
    ScaleRowsTransposed(ws->sqrt_w, d.DtauDq(j, k), St.middleCols(cols, nv));
    if (k >= 2 && j <= k) {
      ScaleRowsTransposed(ws->sqrt_w, d.DtauDq(j, k - 1), St_prev.middleCols(cols_prev, nv));
      cols_prev += nv;
    }
  }
  Eigen::MatrixXd& C = H->C(r);
  C.setZero();
  C.diagonal() = ActiveWeights(Wq(k), s.q[k], q_lo_, q_hi_, wq_lim_, &ws->w_q);
  const Eigen::VectorXd& wv_k = w_v(k, &ws->w_v);
  AddVelocityGram(model_, d.dv_dq[k], wv_k, d.dv_dq[k], true, &C);
  if (k < N_) {
    AddVelocityGram(model_, d.dv_dqm[k + 1], w_v(k + 1, &ws->w_v_next), d.dv_dqm[k + 1], true, &C);
  }
  internal::AddProductNT(1.0, St.leftCols(cols), St.leftCols(cols), true, C);
  // Exact symmetry of the diagonal block: the upper triangle is the lower one.
  C.triangularView<Eigen::StrictlyUpper>() = C.transpose();
  if (k >= 2) {
    // B = sum over j = k-1, k of (d tau_j/d q_k)^T W (d tau_j/d q_{k-1}): the first columns of
    // S^T.
    Eigen::MatrixXd& B = H->B(r);
    B.setZero();
    AddVelocityGram(model_, d.dv_dq[k], wv_k, d.dv_dqm[k], false, &B);
    internal::AddProductNT(1.0, St.leftCols(cols_prev), St_prev.leftCols(cols_prev), false, B);
  }
  if (k >= 3) {
    // A = (d tau_{k-1}/d q_k)^T W (d tau_{k-1}/d q_{k-2}).
    Eigen::MatrixXd& A = H->A(r);
    Eigen::MatrixXd& Gt = ws->scratch_qv;
    ws->sqrt_w = w_tau(k - 1).cwiseSqrt();
    ScaleRowsTransposed(ws->sqrt_w, d.DtauDq(k - 1, k - 2), Gt);
    A.setZero();
    internal::AddProductNT(1.0, St.leftCols(nv), Gt, false, A);
  }
}

void Transcription::CalcHessian(const TrajectoryState& s, const TrajectoryDerivatives& d,
                                PentaDiagonalMatrix* H) {
  // One block row per task: rows are independent, so the result is deterministic.
  ParallelFor(1, N_ + 1, num_threads_,
              [&](int k, int thread) { CalcHessianRow(s, d, k, workspaces_[thread].get(), H); });
}

void Transcription::CalcConstraints(const TrajectoryState& s, Eigen::VectorXd* h) const {
  const int nu = num_unactuated();
  if (h->size() != N_ * nu) h->resize(N_ * nu);
  for (int j = 0; j < N_; ++j) {
    for (int u = 0; u < nu; ++u) (*h)(j * nu + u) = s.tau[j](unactuated_[u]);
  }
}

double Transcription::Merit(const TrajectoryState& s, const Eigen::VectorXd& lambda) const {
  const int nu = num_unactuated();
  if (lambda.size() != N_ * nu) {
    ThrowInvalidArgument("Transcription::Merit", "lambda",
                         std::to_string(lambda.size()) + " entries",
                         std::to_string(N_ * nu) + " (num_steps x num_unactuated)");
  }
  double sum = s.cost;
  for (int j = 0; j < N_; ++j) {
    for (int u = 0; u < nu; ++u) sum += lambda(j * nu + u) * s.tau[j](unactuated_[u]);
  }
  return sum;
}

void Transcription::ConstraintBlock(const TrajectoryDerivatives& d, int j, int s,
                                    Eigen::Ref<Eigen::MatrixXd> block) const {
  const Eigen::MatrixXd& T = d.DtauDq(j, s);
  for (int u = 0; u < num_unactuated(); ++u) block.row(u) = T.row(unactuated_[u]);
}

void Transcription::CalcDenseConstraintJacobianTranspose(const TrajectoryDerivatives& d,
                                                         Eigen::MatrixXd* At) const {
  const int nu = num_unactuated();
  At->setZero(N_ * nq_, N_ * nu);
  for (int j = 0; j < N_; ++j) {
    for (int s = j - 1; s <= j + 1; ++s) {
      if (s < 1 || s > N_) continue;
      const Eigen::MatrixXd& T = d.DtauDq(j, s);
      for (int u = 0; u < nu; ++u) {
        At->block((s - 1) * nq_, j * nu + u, nq_, 1) = T.row(unactuated_[u]).transpose();
      }
    }
  }
}

std::uint64_t Transcription::TakeContactTicks() {
  std::uint64_t total = 0;
  for (auto& ws : workspaces_) {
    total += ws->contact_ticks;
    ws->contact_ticks = 0;
  }
  return total;
}

}  // namespace idto
