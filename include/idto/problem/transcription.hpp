#pragma once

/// @file
/// The IDTO transcription (paper §4 and its appendix): for a trajectory q_0..q_N, the
/// velocities, accelerations, generalized forces with contact, the cost L(q), the unactuated-DoF
/// constraints h(q), the derivative blocks d tau_j / d q_s, the gradient and the
/// block-pentadiagonal Gauss-Newton Hessian. Each time step's work is independent and runs in
/// parallel; every reduction runs in a fixed order, so results are bitwise identical for any
/// thread count. The minimizer (solver/) sees the problem only through this class.
///
/// Derivatives go through one seam, TauDerivativeEvaluator: analytic (the default), forward or
/// central differences; another method plugs in there without touching the minimizer.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "idto/contact/contact_engine.hpp"
#include "idto/math/penta_diagonal_matrix.hpp"
#include "idto/multibody/model.hpp"
#include "idto/problem/derivative_method.hpp"
#include "idto/problem/problem_definition.hpp"
#include "idto/problem/trajectory_state.hpp"

namespace idto {

struct TranscriptionWorkspace;
class Transcription;

/// The derivative seam: fills TrajectoryDerivatives::dtau_dqm/dtau_dq/dtau_dqp at a state
/// whose velocity partials (Nplus, dv_dq, dv_dqm) are already computed.
class TauDerivativeEvaluator {
 public:
  virtual ~TauDerivativeEvaluator() = default;
  /// `transcription` provides the per-thread workspaces and the tau evaluation.
  virtual void Calc(const TrajectoryState& state, Transcription* transcription,
                    TrajectoryDerivatives* derivatives) const = 0;
  /// Whether CalcWithTau is implemented: the method's per-step pass yields tau_k as well.
  virtual bool ProvidesTau() const { return false; }
  /// tau_k (and the contact) of every step of *state, whose q, v and a are set, and the
  /// derivatives, in one pass per step (Transcription::EvaluateWithDerivatives). The default
  /// throws std::logic_error: only evaluators whose ProvidesTau() is true implement it.
  virtual void CalcWithTau(TrajectoryState* state, Transcription* transcription,
                           TrajectoryDerivatives* derivatives) const;
};

/// Finite differences of tau_k with respect to q_s (forward or central), reusing the contact
/// pairs a perturbation does not move; relative_step 0 picks sqrt(eps) (forward, and central
/// with contact) or cbrt(eps) (central without contact).
std::unique_ptr<TauDerivativeEvaluator> MakeFiniteDifferenceEvaluator(DerivativeMethod method,
                                                                      double relative_step);

/// Exact derivatives (DerivativeMethod::kAnalytic): analytic RNEA derivatives and contact
/// derivatives (contact_derivatives.hpp) at each step, then the chain rule through v and a.
std::unique_ptr<TauDerivativeEvaluator> MakeAnalyticEvaluator();

/// The evaluator of a DerivativeMethod: the one place a new method is added.
std::unique_ptr<TauDerivativeEvaluator> MakeTauDerivativeEvaluator(DerivativeMethod method,
                                                                   double relative_step);

class Transcription {
 public:
  /// Validates the problem (throws InvalidArgument naming the field). Contact is on when the
  /// problem enables it and the model has at least one pair that can touch.
  Transcription(const Model& model, const ProblemDefinition& problem);
  ~Transcription();
  Transcription(Transcription&&) noexcept;
  Transcription& operator=(Transcription&&) noexcept;

  const Model& model() const { return model_; }
  const ProblemDefinition& problem() const { return problem_; }
  /// Replaces q_init, v_init (sizes checked by the caller).
  void SetInitialConditions(const Eigen::VectorXd& q_init, const Eigen::VectorXd& v_init);
  /// Replaces the problem (validated by the caller against the same model, with the same
  /// horizon and contact: e.g. a new nominal trajectory).
  void SetProblem(ProblemDefinition problem);

  int num_steps() const { return N_; }
  int nq() const { return nq_; }
  int nv() const { return nv_; }
  /// Number of unactuated DoFs n_u; h has N n_u entries.
  int num_unactuated() const { return static_cast<int>(unactuated_.size()); }
  const std::vector<int>& unactuated_dofs() const { return unactuated_; }
  /// The contact engine, or null when the problem has no contact.
  const ContactEngine* engine() const { return engine_ ? &*engine_ : nullptr; }

  /// Weight w of w/2 |h|^2 placed on R's unactuated entries (the penalty method); 0 keeps R.
  void SetPenaltyWeight(double weight);
  /// Threads for the per-step work (>= 1); creates the per-thread workspaces.
  void SetNumThreads(int num_threads);
  int num_threads() const { return num_threads_; }
  /// The derivative method behind CalcDerivatives (MakeTauDerivativeEvaluator); a no-op when
  /// unchanged, so repeated solves do not allocate.
  void SetDerivativeMethod(DerivativeMethod method, double relative_step);
  /// A derivative evaluator of the caller's own (not null): replaces the method's.
  void SetDerivativeEvaluator(std::unique_ptr<TauDerivativeEvaluator> evaluator);

  /// A state / derivatives sized for this problem (allocates; call once).
  TrajectoryState MakeState() const;
  TrajectoryDerivatives MakeDerivatives() const;

  /// From state->q: v, a, tau (and contact), and the cost, which it returns. Allocation-free.
  double Evaluate(TrajectoryState* state);
  /// L(q) of an evaluated state (fixed summation order).
  double Cost(const TrajectoryState& state) const;
  /// For an evaluated state whose cost is not finite: which input is to blame (a non-finite q,
  /// v or tau with its step, or the YAML key of the cost term that overflows).
  std::string DescribeNonFiniteCost(const TrajectoryState& state) const;
  /// sum_k |tau_k(unactuated)|^2 of an evaluated state.
  double ConstraintViolation(const TrajectoryState& state) const;
  /// The velocity partials, then the evaluator's d tau / d q blocks.
  void CalcDerivatives(const TrajectoryState& state, TrajectoryDerivatives* derivatives);
  /// Whether EvaluateWithDerivatives is available: the derivative method yields tau in its
  /// per-step pass (the analytic method; not finite differences).
  bool CanEvaluateWithDerivatives() const { return evaluator_->ProvidesTau(); }
  /// Evaluate and CalcDerivatives in one pass over the steps: the analytic RNEA derivatives
  /// produce ID(q, v, a) and the poses and velocities the contact needs, so the separate
  /// kinematics and inverse dynamics of Evaluate are saved. The same quantities as Evaluate
  /// followed by CalcDerivatives, up to round-off in tau and the contact (other arithmetic, the
  /// same formulas); returns the cost. Allocation-free. Throws std::logic_error when
  /// !CanEvaluateWithDerivatives().
  double EvaluateWithDerivatives(TrajectoryState* state, TrajectoryDerivatives* derivatives);
  /// g = dL / d(q_1..q_N) (N nq), preallocated.
  void CalcGradient(const TrajectoryState& state, const TrajectoryDerivatives& derivatives,
                    Eigen::VectorXd* g);
  /// The Gauss-Newton Hessian (N blocks of nq), preallocated.
  void CalcHessian(const TrajectoryState& state, const TrajectoryDerivatives& derivatives,
                   PentaDiagonalMatrix* H);
  /// CalcGradient and CalcHessian in one parallel phase (the same results, bit for bit).
  void CalcGradientAndHessian(const TrajectoryState& state,
                              const TrajectoryDerivatives& derivatives, Eigen::VectorXd* g,
                              PentaDiagonalMatrix* H);
  /// h (N n_u): the unactuated rows of tau_0..tau_{N-1} (resized when its size differs; no
  /// allocation when it is already N n_u).
  void CalcConstraints(const TrajectoryState& state, Eigen::VectorXd* h) const;
  /// The merit L(q) + lambda^T h(q) of an evaluated state for multipliers lambda (N n_u),
  /// summed onto the cost in step order. Throws InvalidArgument when lambda is not N n_u.
  double Merit(const TrajectoryState& state, const Eigen::VectorXd& lambda) const;
  /// Constraint Jacobian block d h_j / d q_s (n_u x nq) for s in {j-1, j, j+1} ∩ [1, N].
  void ConstraintBlock(const TrajectoryDerivatives& derivatives, int j, int s,
                       Eigen::Ref<Eigen::MatrixXd> block) const;
  /// (dh / dq)^T as a dense (N nq) x (N n_u) matrix (a test oracle; the solver uses blocks;
  /// resized).
  void CalcDenseConstraintJacobianTranspose(const TrajectoryDerivatives& derivatives,
                                            Eigen::MatrixXd* At) const;

  /// Ticks spent in contact evaluation by all threads since the last call (see core ticks).
  std::uint64_t TakeContactTicks();

  // ---- For derivative evaluators (TauDerivativeEvaluator implementations). ----
  /// The workspace of thread `thread` of the current ParallelFor.
  TranscriptionWorkspace& workspace(int thread) { return *workspaces_[thread]; }
  /// tau = ID(q, v, a) - J^T f(q, v) with thread scratch ws; the contact evaluation goes to
  /// *contact (ws's own when null); `reuse_from` and `moved` enable pair reuse.
  void CalcTau(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
               TranscriptionWorkspace* ws, Eigen::VectorXd* tau, ContactData* contact = nullptr,
               const ContactData* reuse_from = nullptr,
               const std::vector<char>* moved = nullptr) const;
  /// The bodies whose pose or velocity position coordinate i moves (num_bodies flags).
  const std::vector<char>& bodies_moved_by(int i) const { return moved_by_q_[i]; }
  double time_step() const { return dt_; }

 private:
  // Weights of step k's position and velocity residuals (dt Q for k < N, Qf for k = N).
  const Eigen::VectorXd& Wq(int k) const { return k < N_ ? Wq_run_ : problem_.Qfq; }
  const Eigen::VectorXd& Wv(int k) const { return k < N_ ? Wv_run_ : problem_.Qfv; }
  void CalcGradientRow(const TrajectoryState& s, const TrajectoryDerivatives& d, int k,
                       TranscriptionWorkspace* ws, Eigen::VectorXd* g) const;
  void CalcHessianRow(const TrajectoryState& s, const TrajectoryDerivatives& d, int k,
                      TranscriptionWorkspace* ws, PentaDiagonalMatrix* H) const;
  // v_0..v_N and a_0..a_{N-1} from state->q (serial: each v_k is cheap).
  void CalcVelocities(TrajectoryState* s) const;
  // N+, d v_k / d q_k and d v_k / d q_{k-1}, k = 1..N.
  void CalcVelocityPartials(const TrajectoryState& s, TrajectoryDerivatives* d) const;
  // The limit bounds and weights (times dt) from problem_.limits and the model.
  void SetUpLimits();
  // 1/2 dt sum of the weighted squared limit excesses of q_k, v_k (k >= 1) and tau_k (k < N).
  double LimitCost(const TrajectoryState& s, int k) const;

  Model model_;
  ProblemDefinition problem_;
  int N_{0}, nq_{0}, nv_{0};
  double dt_{0.0};
  std::vector<int> unactuated_;
  std::optional<ContactEngine> engine_;
  double penalty_weight_{0.0};
  // Effective torque weight R (penalty on unactuated entries), and dt R, dt Qq, dt Qv.
  Eigen::VectorXd R_eff_, WR_, Wq_run_, Wv_run_;
  int num_threads_{1};
  std::vector<std::unique_ptr<TranscriptionWorkspace>> workspaces_;
  std::unique_ptr<TauDerivativeEvaluator> evaluator_;
  DerivativeMethod derivative_method_{DerivativeMethod::kAnalytic};
  double relative_step_{0.0};
  bool custom_evaluator_{false};
  // Limit penalties: bounds (nq, nv, nv; +-inf where none) and weights times dt (0: off).
  Eigen::VectorXd q_lo_, q_hi_, v_lo_, v_hi_, tau_lo_, tau_hi_;
  double wq_lim_{0.0}, wv_lim_{0.0}, wt_lim_{0.0};
  // For each position coordinate: the bodies whose pose or velocity it moves (num_bodies).
  std::vector<std::vector<char>> moved_by_q_;
};

}  // namespace idto
