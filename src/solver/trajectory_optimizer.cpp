// The minimizer (paper §5): a Gauss-Newton trust-region method over the Transcription. One
// iteration: derivatives, gradient and Hessian (the transcription), scaling, factorization with
// a Levenberg-Marquardt shift when needed, multipliers (Lagrange method), Newton and Cauchy
// points, then dogleg steps with a shrinking radius until one is accepted; named convergence
// tests after each step. The trust-region strategy lives in trust_region.hpp; with Lagrange
// multipliers the Newton step and the multipliers come from one banded KKT solve
// (idto/solver/banded_kkt.hpp), linear in N.

#include "idto/solver/trajectory_optimizer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/ticks.hpp"
#include "idto/core/errors.hpp"
#include "idto/math/penta_diagonal_matrix.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/problem/transcription.hpp"
#include "idto/solver/banded_kkt.hpp"
#include "solver/trust_region.hpp"

namespace idto {

namespace {

using Clock = std::chrono::steady_clock;
using internal::Ticks;
using internal::TicksSince;
using internal::TicksToSeconds;

double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

bool AllFinite(const Eigen::VectorXd& x) { return x.allFinite(); }

}  // namespace

class TrajectoryOptimizer::Impl {
 public:
  Impl(const Model& model, const ProblemDefinition& problem, const SolverOptions& options)
      : transcription_(model, problem), options_(options) {
    std::string why;
    if (!options_.IsValid(&why)) throw InvalidArgument("TrajectoryOptimizer: " + why);
    N_ = transcription_.num_steps();
    nq_ = transcription_.nq();
    nu_ = transcription_.num_unactuated();
    x_ = transcription_.MakeState();
    trial_ = transcription_.MakeState();
    derivatives_ = transcription_.MakeDerivatives();
    trial_derivatives_ = transcription_.MakeDerivatives();
    H_ = PentaDiagonalMatrix(N_, nq_);
    chol_ = internal::SplitPentaDiagonalCholesky(N_, nq_, options_.num_threads);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(N_ * nq_);
    g_ = g_merit_ = p_ = p_newton_ = p_cauchy_ = scratch_a_ = scratch_b_ = zero;
    D_ = Eigen::VectorXd::Ones(N_ * nq_);
    Prepare();
    for (int k = 0; k <= N_; ++k) x_.q[k] = problem.q_init;
    trust_radius_ = options_.initial_trust_radius;
  }

  // (Re)applies the options, which mutable_options() may change between solves.
  void Prepare() {
    std::string why;
    if (!options_.IsValid(&why)) throw InvalidArgument("TrajectoryOptimizer: " + why);
    transcription_.SetPenaltyWeight(
        options_.constraint_method == ConstraintMethod::kPenalty ? options_.penalty_weight : 0.0);
    transcription_.SetNumThreads(options_.num_threads);
    transcription_.SetDerivativeMethod(options_.derivative_method, options_.finite_difference_step);
    if (lagrange() && h_.size() != N_ * nu_) {
      h_ = lambda_ = linearized_h_ = correction_multipliers_ = Eigen::VectorXd::Zero(N_ * nu_);
      zero_gradient_ = correction_ = Eigen::VectorXd::Zero(N_ * nq_);
      A_.Resize(N_, nq_, nu_);
      kkt_.Resize(N_, nq_, nu_);
    }
    kkt_.set_extended_residual(options_.kkt_extended_residual);
    kkt_.set_extended_threshold(options_.kkt_extended_threshold);
    kkt_.set_num_threads(options_.num_threads);
    chol_.set_num_threads(options_.num_threads);
  }

  bool lagrange() const {
    return options_.constraint_method == ConstraintMethod::kLagrangeMultipliers && nu_ > 0;
  }

  void StoreSolution(Trajectory* solution) const {
    if (solution == nullptr) return;
    solution->q = x_.q;
    solution->v = x_.v;
    solution->tau = x_.tau;
    solution->tau.push_back(Eigen::VectorXd::Zero(transcription_.nv()));
  }

  // Sets the iterate from q (N + 1 configurations), checked; q_0 becomes q_init.
  void SetIterate(const std::vector<Eigen::VectorXd>& q, const char* function,
                  const std::string& argument) {
    const Model& model = transcription_.model();
    if (static_cast<int>(q.size()) != N_ + 1) {
      ThrowInvalidArgument(function, argument, std::to_string(q.size()) + " configurations",
                           std::to_string(N_ + 1) + " (num_steps + 1)");
    }
    for (int k = 0; k <= N_; ++k) {
      const std::string name = argument + "[" + std::to_string(k) + "]";
      model.CheckConfiguration(function, name.c_str(), q[k]);
      CheckFinite(function, name, q[k]);
    }
    for (int k = 0; k <= N_; ++k) {
      x_.q[k] = q[k];
      NormalizeQuaternions(model, &x_.q[k]);
    }
    x_.q[0] = transcription_.problem().q_init;
    NormalizeQuaternions(model, &x_.q[0]);
  }

  // Derivatives, gradient, Hessian, scaling, factorization, multipliers, Newton and Cauchy
  // points at the iterate. False (with the summary's termination set) on numerical failure.
  bool PrepareStep(IterationSummary* s, SolverSummary* summary) {
    if (!derivatives_at_x_) {
      const Clock::time_point t0 = Clock::now();
      const std::uint64_t k0 = Ticks();
      transcription_.CalcDerivatives(x_, &derivatives_);
      const std::uint64_t derivative_ticks = TicksSince(k0);
      s->time_derivatives = Seconds(t0, Clock::now());
      s->time_contact =
          TicksToSeconds(transcription_.TakeContactTicks(), derivative_ticks, s->time_derivatives);
      derivatives_at_x_ = true;
    }
    const Clock::time_point t1 = Clock::now();
    transcription_.CalcGradientAndHessian(x_, derivatives_, &g_, &H_);
    const Clock::time_point t2 = Clock::now();
    s->time_hessian = Seconds(t1, t2);
    internal::CalcScaling(H_, options_.scaling, &D_);
    g_merit_ = g_;
    merit_ = x_.cost;
    if (lagrange()) {
      // The KKT factorization includes H's: no separate Cholesky.
      const bool solved = SolveKkt(s, summary);
      s->time_multipliers = Seconds(t2, Clock::now());
      if (!solved) return false;
    } else {
      const bool factored =
          internal::FactorizeWithShift(&H_, &chol_, &scratch_a_, &s->regularization);
      s->time_factorization = Seconds(t2, Clock::now());
      if (!factored) {
        return Fail(summary, "the Hessian factorization failed at block " +
                                 std::to_string(chol_.failed_block()) +
                                 " even with regularization; last good iterate kept");
      }
      p_newton_ = -g_merit_;
      chol_.SolveInPlace(&p_newton_);
    }
    internal::CalcCauchyPoint(H_, g_merit_, D_, options_.num_threads, &scratch_a_, &scratch_b_,
                              &p_cauchy_);
    if (!AllFinite(p_newton_) || !AllFinite(p_cauchy_)) {
      return Fail(summary,
                  "the Newton or Cauchy step is not finite (non-finite derivatives); "
                  "last good iterate kept");
    }
    return true;
  }

  // The constrained Newton step: [H A^T; A 0][p; lambda] = -[g; h] (O(N)), then the merit
  // L + h^T lambda and its gradient g + A^T lambda.
  bool SolveKkt(IterationSummary* s, SolverSummary* summary) {
    transcription_.CalcConstraints(x_, &h_);
    for (int j = 0; j < N_; ++j) {
      for (int t = std::max(j - 1, 1); t <= std::min(j + 1, N_); ++t) {
        transcription_.ConstraintBlock(derivatives_, j, t, A_.Block(j, t));
      }
    }
    double shift = 0.0;
    const bool factored = FactorKktWithShift(&shift);
    s->regularization = shift;
    if (!factored) {
      return Fail(summary, kkt_.status().Message() +
                               " (also with the Hessian shifted by up to 1e-2 of its diagonal); "
                               "last good iterate kept");
    }
    kkt_.Solve(g_, h_, &p_newton_, &lambda_);
    kkt_.set_extended_first(kkt_.last_solve_needed_extended());
    A_.AddMultiplyTranspose(lambda_, &g_merit_);
    merit_ = x_.cost + h_.dot(lambda_);
    return true;
  }

  // Factors the KKT system; where round-off makes the Hessian's reduced blocks indefinite (stiff
  // contact: condition numbers beyond 1e12) shifts H's diagonal as the penalty route does and
  // retries. *mu: the relative shift added here (0 when none was needed).
  bool FactorKktWithShift(double* mu) {
    return internal::FactorWithShift(&H_, &scratch_b_, mu,
                                     [&] { return kkt_.Factor(H_, A_).ok(); });
  }

  bool Fail(SolverSummary* summary, const std::string& message) const {
    summary->termination = TerminationType::kFailure;
    summary->message = message;
    return false;
  }

  // The dogleg step for the current radius, the trial point and its ratio. Returns the
  // predicted reduction.
  // may_speculate: the trial point may be evaluated with its derivatives
  // (SolverOptions::trial_derivatives); it is unless the step is a full Newton step, which is
  // rejected about a third of the time (measured over the examples' solves, against 6 % for the
  // dogleg steps after a step that did not grow the radius).
  double TryStep(bool may_speculate, IterationSummary* s) {
    s->merit = merit_;
    s->gradient_norm = g_merit_.norm();
    s->trust_radius = trust_radius_;
    s->step_type = internal::CalcDoglegStep(p_newton_, p_cauchy_, D_, trust_radius_, &scratch_a_,
                                            &scratch_b_, &p_, &s->scaled_step_norm);
    internal::MultiplyInHalves(H_, p_, options_.num_threads, &scratch_a_);
    const double predicted =
        CorrectOntoConstraints(-(g_merit_.dot(p_) + 0.5 * p_.dot(scratch_a_)), s);
    s->step_norm = p_.norm();
    const Clock::time_point tc = Clock::now();
    const std::uint64_t kc = Ticks();
    ApplyStep();
    const bool with_derivatives = may_speculate && s->step_type != DoglegStep::kNewton;
    s->trial_with_derivatives = with_derivatives;
    const double trial_cost =
        with_derivatives ? transcription_.EvaluateWithDerivatives(&trial_, &trial_derivatives_)
                         : transcription_.Evaluate(&trial_);
    trial_merit_ = lagrange() ? transcription_.Merit(trial_, lambda_) : trial_cost;
    const std::uint64_t cost_ticks = TicksSince(kc);
    s->time_cost = Seconds(tc, Clock::now());
    s->time_contact += TicksToSeconds(transcription_.TakeContactTicks(), cost_ticks, s->time_cost);
    s->trial_cost = trial_cost;
    s->ratio = internal::ReductionRatio(merit_, trial_merit_, predicted);
    // The growth guard (Lagrange route, merit with multipliers): a point that the merit favours
    // but whose cost and violation both grew tenfold counts as a failed step.
    s->growth_guard = lagrange() && s->ratio > options_.acceptance_ratio &&
                      internal::GrowthGuardTrips(x_.cost, s->constraint_violation, trial_cost,
                                                 transcription_.ConstraintViolation(trial_));
    const double ratio_for_radius = s->growth_guard ? -1.0 : s->ratio;
    trust_radius_ = internal::UpdateTrustRadius(ratio_for_radius, s->scaled_step_norm,
                                                trust_radius_, options_.max_trust_radius);
    s->accepted = ratio_for_radius > options_.acceptance_ratio;
    return predicted;
  }

  // SolverOptions::constraint_correction: a dogleg step short of the Newton step moves onto the
  // linearized constraints h + A p = 0 by the correction c of least H-norm, A c = −(h + A p)
  // (the KKT factorization's solve with g = 0, unrefined), scaled to |D⁻¹c| <=
  // constraint_correction × Δ. Without it the violation falls only through Newton steps: the Cauchy
  // direction follows the merit L + hᵀλ, which is blind to h (docs/solver.md, "Constraint
  // correction"). predicted: the model's reduction for p_; returns that of the step kept, which is
  // p_ + c unless the correction makes it non-positive.
  double CorrectOntoConstraints(double predicted, IterationSummary* s) {
    if (!lagrange() || s->step_type == DoglegStep::kNewton ||
        !(options_.constraint_correction > 0.0)) {
      return predicted;
    }
    A_.Multiply(p_, &linearized_h_);
    linearized_h_ += h_;
    kkt_.SolveUnrefined(zero_gradient_, linearized_h_, &correction_, &correction_multipliers_);
    const double norm = correction_.cwiseQuotient(D_).norm();
    const double limit = options_.constraint_correction * trust_radius_;
    if (!(norm > 0.0) || !std::isfinite(norm)) return predicted;
    const double alpha = std::min(1.0, limit / norm);
    // The model's change from p to p + αc without a product with H: H c = −Aᵀν (the solve's
    // first row), so pᵀHc = −(A p)ᵀν and cᵀHc = (h + A p)ᵀν (A c = −(h + A p)).
    const double r_nu = linearized_h_.dot(correction_multipliers_);
    const double ap_nu = r_nu - h_.dot(correction_multipliers_);
    const double change =
        alpha * g_merit_.dot(correction_) - alpha * ap_nu + 0.5 * alpha * alpha * r_nu;
    const double corrected = predicted - change;
    if (!(corrected > 0.0) || !std::isfinite(corrected)) return predicted;
    p_ += alpha * correction_;
    s->correction_norm = alpha * norm;
    return corrected;
  }

  void ApplyStep() {
    trial_.q[0] = x_.q[0];
    for (int k = 1; k <= N_; ++k) {
      trial_.q[k] = x_.q[k] + p_.segment((k - 1) * nq_, nq_);
      NormalizeQuaternions(transcription_.model(), &trial_.q[k]);
    }
  }

  // The trial point becomes the iterate (with its derivatives when it brought them);
  // convergence tests.
  void HandleSuccessfulStep(const IterationSummary& s, SolverSummary* summary) {
    const double g_dot_p = g_merit_.dot(p_);
    const double step_norm = p_.norm();
    const double q_norm = QNorm();
    const double previous = x_.cost;
    std::swap(x_, trial_);
    derivatives_at_x_ = s.trial_with_derivatives;
    if (derivatives_at_x_) std::swap(derivatives_, trial_derivatives_);
    if (options_.fixed_iterations) return;
    std::string message;
    if (internal::CostChangeConverged(previous, x_.cost, options_, &message) ||
        internal::GradientConverged(g_dot_p, previous, options_, &message) ||
        internal::StepConverged(step_norm, q_norm, options_, &message)) {
      summary->termination = TerminationType::kConverged;
      summary->message = message;
    }
  }

  // A rejected step: the radius is floored so a warm-started solve (MPC) can move again when
  // its problem changes; a stationary point is convergence, a non-finite cost at the floor is
  // failure.
  void HandleUnsuccessfulStep(double predicted, SolverSummary* summary) {
    const bool at_floor = trust_radius_ < internal::kMinTrustRadius;
    if (at_floor) trust_radius_ = internal::kMinTrustRadius;
    if (!std::isfinite(trial_merit_) && at_floor) {
      Fail(summary,
           "the cost is not finite even for the smallest trust region; last good iterate kept");
      return;
    }
    if (options_.fixed_iterations) return;
    std::string message;
    const double step_norm = p_.norm();
    if (step_norm > 0.0 && internal::StepConverged(step_norm, QNorm(), options_, &message)) {
      summary->termination = TerminationType::kConverged;
      summary->message = message + " (rejected step)";
    } else if ((std::isfinite(predicted) &&
                internal::PredictedReductionNegligible(predicted, merit_)) ||
               at_floor) {
      summary->termination = TerminationType::kConverged;
      summary->message = "no reduction predicted above round-off (stationary point)";
    }
  }

  void RunCallbacks(SolverSummary* summary) {
    for (const IterationCallback& cb : callbacks_) {
      const CallbackReturn r = cb(summary->log.back());
      if (r == CallbackReturn::kAbort) {
        summary->termination = TerminationType::kUserAbort;
        summary->message = "aborted by a callback";
      } else if (r == CallbackReturn::kTerminateSuccessfully &&
                 summary->termination != TerminationType::kUserAbort) {
        summary->termination = TerminationType::kUserTermination;
        summary->message = "terminated by a callback";
      }
    }
  }

  SolverSummary Run(Trajectory* solution) {
    const Clock::time_point start = Clock::now();
    Prepare();
    SolverSummary summary;
    // With trial derivatives the initial guess is evaluated with its derivatives, which
    // iteration 0 needs: the whole pass is timed as iteration 0's derivatives.
    const bool fuse = options_.trial_derivatives && transcription_.CanEvaluateWithDerivatives();
    const Clock::time_point t_start = Clock::now();
    const std::uint64_t k_start = Ticks();
    derivatives_at_x_ = fuse && options_.max_iterations > 0;
    summary.initial_cost = derivatives_at_x_
                               ? transcription_.EvaluateWithDerivatives(&x_, &derivatives_)
                               : transcription_.Evaluate(&x_);
    const double start_seconds = Seconds(t_start, Clock::now());
    const double start_contact =
        TicksToSeconds(transcription_.TakeContactTicks(), TicksSince(k_start), start_seconds);
    summary.termination = TerminationType::kMaxIterations;
    if (!std::isfinite(summary.initial_cost)) {
      Fail(&summary, "the cost of the initial guess is not finite: " +
                         transcription_.DescribeNonFiniteCost(x_));
    }
    summary.log.reserve(options_.max_iterations);
    bool need_derivatives = true;
    bool speculate = true;  // the first trial point, and after steps likely to be followed
    for (int it = 0;
         it < options_.max_iterations && summary.termination == TerminationType::kMaxIterations;
         ++it) {
      IterationSummary s;
      s.iteration = it;
      s.cost = x_.cost;
      s.constraint_violation = transcription_.ConstraintViolation(x_);
      const Clock::time_point t0 = Clock::now();
      const double carried = it == 0 && derivatives_at_x_ ? start_seconds : 0.0;
      if (carried > 0.0) {
        s.time_derivatives = start_seconds;
        s.time_contact = start_contact;
      }
      if (need_derivatives && !PrepareStep(&s, &summary)) {
        s.time_total = Seconds(t0, Clock::now()) + carried;
        summary.log.push_back(s);
        break;
      }
      // Derivatives with the trial point when a next iteration will likely use them: not on
      // the last iteration, not after a rejection (rejections come in runs while the radius
      // shrinks) and not after a step that grew the radius (the next is then rejected 17 % of
      // the time, against 6 %): a wasted pass costs about the derivatives, an accepted one
      // saves about the evaluation (docs/solver.md, "Trial derivatives").
      const bool last = it + 1 == options_.max_iterations;
      const double predicted = TryStep(fuse && !last && speculate, &s);
      need_derivatives = s.accepted;
      speculate = s.accepted && trust_radius_ <= s.trust_radius;
      if (s.accepted) {
        HandleSuccessfulStep(s, &summary);
      } else {
        HandleUnsuccessfulStep(predicted, &summary);
      }
      s.time_total = Seconds(t0, Clock::now()) + carried;
      summary.log.push_back(s);
      ++summary.iterations;
      if (options_.verbosity > 0) {
        std::printf(
            "%4d cost %.6e rho %.3e radius %.3e %s\n", it, s.cost, s.ratio, s.trust_radius,
            s.accepted ? "accepted" : (s.growth_guard ? "rejected (growth guard)" : "rejected"));
      }
      RunCallbacks(&summary);
    }
    summary.final_cost = x_.cost;
    summary.constraint_violation = transcription_.ConstraintViolation(x_);
    summary.solve_time = Seconds(start, Clock::now());
    StoreSolution(solution);
    return summary;
  }

  double QNorm() const {
    double sum = 0.0;
    for (int k = 1; k <= N_; ++k) sum += x_.q[k].squaredNorm();
    return std::sqrt(sum);
  }

  // For the public evaluation entry points: the iterate becomes q, evaluated.
  void LoadIterate(const std::vector<Eigen::VectorXd>& q) {
    if (static_cast<int>(q.size()) != N_ + 1) {
      ThrowInvalidArgument("TrajectoryOptimizer", "q", std::to_string(q.size()) + " entries",
                           std::to_string(N_ + 1) + " (num_steps + 1)");
    }
    for (int k = 0; k <= N_; ++k) {
      transcription_.model().CheckConfiguration("TrajectoryOptimizer", "q[k]", q[k]);
      x_.q[k] = q[k];
    }
    Prepare();
    transcription_.Evaluate(&x_);
    derivatives_at_x_ = false;
  }

  Transcription transcription_;
  SolverOptions options_;
  int N_{0}, nq_{0}, nu_{0};
  std::vector<IterationCallback> callbacks_;

  TrajectoryState x_;                        // the iterate (q_0 = q_init) and what follows from it
  TrajectoryState trial_;                    // the trial point x + p
  TrajectoryDerivatives derivatives_;        // at x_ when derivatives_at_x_
  TrajectoryDerivatives trial_derivatives_;  // at trial_ when its step evaluated them
  bool derivatives_at_x_{false};
  PentaDiagonalMatrix H_;                      // Gauss-Newton Hessian at x_ (with any LM shift)
  internal::SplitPentaDiagonalCholesky chol_;  // its factor (penalty route)
  BlockConstraintJacobian A_;                  // dh/dq at x_ by blocks (Lagrange method)
  BandedKktSolver kkt_;                        // its KKT factorization with H_
  // N nq each: gradient of L; of the merit L + h^T lambda; scaling D; the step; Newton and
  // Cauchy points; scratch of the trust-region functions (no fixed meaning between calls).
  Eigen::VectorXd g_, g_merit_, D_, p_, p_newton_, p_cauchy_, scratch_a_, scratch_b_;
  Eigen::VectorXd h_, lambda_;  // N n_u: constraints at x_ and their multipliers
  // The constraint correction (CorrectOntoConstraints): zeros (N nq), h + A p (N nu), the
  // correction c (N nq) and its KKT solve's multipliers ν (N nu; H c = −Aᵀν).
  Eigen::VectorXd zero_gradient_, linearized_h_, correction_, correction_multipliers_;
  double merit_{0.0};         // L(x_) (+ h^T lambda with multipliers)
  double trial_merit_{0.0};   // the same at the trial point
  double trust_radius_{0.1};  // scaled coordinates
};

TrajectoryOptimizer::TrajectoryOptimizer(const Model& model, const ProblemDefinition& problem,
                                         const SolverOptions& options)
    : impl_(std::make_unique<Impl>(model, problem, options)) {}
TrajectoryOptimizer::~TrajectoryOptimizer() = default;
TrajectoryOptimizer::TrajectoryOptimizer(TrajectoryOptimizer&&) noexcept = default;
TrajectoryOptimizer& TrajectoryOptimizer::operator=(TrajectoryOptimizer&&) noexcept = default;

SolverSummary TrajectoryOptimizer::Solve(const std::vector<Eigen::VectorXd>& q_guess,
                                         Trajectory* solution) {
  impl_->SetIterate(q_guess, "TrajectoryOptimizer::Solve", "q_guess");
  impl_->trust_radius_ = impl_->options_.initial_trust_radius;
  // The KKT hint (each iteration's is the previous one's need for the double-double residual)
  // starts afresh, as the trust radius does; a warm start continues both.
  impl_->kkt_.set_extended_first(false);
  return impl_->Run(solution);
}

SolverSummary TrajectoryOptimizer::SolveWarmStart(Trajectory* solution) {
  return impl_->Run(solution);
}

void TrajectoryOptimizer::ResetInitialConditions(const Eigen::VectorXd& q_init,
                                                 const Eigen::VectorXd& v_init) {
  const Model& model = impl_->transcription_.model();
  const char* function = "TrajectoryOptimizer::ResetInitialConditions";
  model.CheckConfiguration(function, "q_init", q_init);
  model.CheckVelocity(function, "v_init", v_init);
  CheckFinite(function, "q_init", q_init);
  CheckFinite(function, "v_init", v_init);
  impl_->transcription_.SetInitialConditions(q_init, v_init);
  impl_->x_.q[0] = q_init;
  NormalizeQuaternions(model, &impl_->x_.q[0]);
}

void TrajectoryOptimizer::UpdateNominalTrajectory(const std::vector<Eigen::VectorXd>& q_nom,
                                                  const std::vector<Eigen::VectorXd>& v_nom) {
  ProblemDefinition candidate = impl_->transcription_.problem();
  candidate.q_nom = q_nom;
  candidate.v_nom = v_nom;
  candidate.Validate(impl_->transcription_.model());
  impl_->transcription_.SetProblem(std::move(candidate));
}

void TrajectoryOptimizer::SetIterate(const std::vector<Eigen::VectorXd>& q) {
  impl_->SetIterate(q, "TrajectoryOptimizer::SetIterate", "q");
}

void TrajectoryOptimizer::AddCallback(IterationCallback callback) {
  impl_->callbacks_.push_back(std::move(callback));
}

const ProblemDefinition& TrajectoryOptimizer::problem() const {
  return impl_->transcription_.problem();
}
const SolverOptions& TrajectoryOptimizer::options() const { return impl_->options_; }
SolverOptions& TrajectoryOptimizer::mutable_options() { return impl_->options_; }
const Model& TrajectoryOptimizer::model() const { return impl_->transcription_.model(); }
double TrajectoryOptimizer::trust_radius() const { return impl_->trust_radius_; }

double TrajectoryOptimizer::EvalCost(const std::vector<Eigen::VectorXd>& q) {
  impl_->LoadIterate(q);
  return impl_->x_.cost;
}

void TrajectoryOptimizer::EvalTrajectory(const std::vector<Eigen::VectorXd>& q,
                                         Trajectory* trajectory) {
  impl_->LoadIterate(q);
  impl_->StoreSolution(trajectory);
}

void TrajectoryOptimizer::EvalGradient(const std::vector<Eigen::VectorXd>& q, Eigen::VectorXd* g) {
  impl_->LoadIterate(q);
  impl_->transcription_.CalcDerivatives(impl_->x_, &impl_->derivatives_);
  g->resize(impl_->N_ * impl_->nq_);
  impl_->transcription_.CalcGradient(impl_->x_, impl_->derivatives_, g);
}

Eigen::MatrixXd TrajectoryOptimizer::EvalDenseHessian(const std::vector<Eigen::VectorXd>& q) {
  impl_->LoadIterate(q);
  impl_->transcription_.CalcDerivatives(impl_->x_, &impl_->derivatives_);
  impl_->transcription_.CalcHessian(impl_->x_, impl_->derivatives_, &impl_->H_);
  return impl_->H_.MakeDense();
}

void TrajectoryOptimizer::EvalConstraints(const std::vector<Eigen::VectorXd>& q,
                                          Eigen::VectorXd* h) {
  impl_->LoadIterate(q);
  h->resize(impl_->N_ * impl_->nu_);
  impl_->transcription_.CalcConstraints(impl_->x_, h);
}

}  // namespace idto
