#include "idto/solver/trajectory_optimizer.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>

#include <Eigen/Cholesky>

#include "core/parallel.hpp"
#include "idto/contact/contact_engine.hpp"
#include "idto/core/errors.hpp"
#include "idto/math/quaternion.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/multibody/data.hpp"
#include "idto/solver/penta_diagonal_matrix.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace idto {

namespace {

using Clock = std::chrono::steady_clock;

// Smallest trust radius (scaled coordinates); reaching it means no progress is possible.
constexpr double kMinTrustRadius = 1e-12;
double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// A cheap monotonic tick counter for the contact share, read twice per contact evaluation:
// the time-stamp counter on x86 (about 10 ns a read on this project's machine, against 25 ns
// for steady_clock::now()), nanoseconds of steady_clock elsewhere. Ticks are converted to
// seconds with the tick rate measured over the phase that contains them.
std::uint64_t Ticks() {
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#else
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch())
          .count());
#endif
}

// Ticks since t0 (0 if the counter went back, e.g. a thread moved to a core whose counter lags).
std::uint64_t TicksSince(std::uint64_t t0) {
  const std::uint64_t t1 = Ticks();
  return t1 > t0 ? t1 - t0 : 0;
}

// `ticks` counted inside a phase that lasted `phase_ticks` and `phase_seconds`, in seconds.
double TicksToSeconds(std::uint64_t ticks, std::uint64_t phase_ticks, double phase_seconds) {
  if (ticks == 0 || phase_ticks == 0) return 0.0;
  return phase_seconds * static_cast<double>(ticks) / static_cast<double>(phase_ticks);
}

// Per-thread scratch for dynamics, contact and finite differences.
struct Workspace {
  Workspace(const Model& model, const ContactEngine* engine)
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
        scratch_vq(Eigen::MatrixXd::Zero(model.nv(), model.nq())) {
    if (engine != nullptr) contact = engine->MakeData(model);
  }
  Data data;
  ContactData contact;
  // Ticks this thread spent in ContactEngine::Evaluate/EvaluateChanged since the last
  // TakeContactTicks() (written by this thread only; read after the parallel loop).
  std::uint64_t contact_ticks{0};
  Eigen::VectorXd v, v_next, a, a_next, tau_a, tau_b, tau_c, tau_d, q;
  // Assembly scratch (nested Eigen products would otherwise allocate temporaries).
  Eigen::VectorXd scratch_v;
  Eigen::MatrixXd scratch_vq;
};

}  // namespace

class TrajectoryOptimizer::Impl {
 public:
  Impl(const Model& model, const ProblemDefinition& problem, const SolverOptions& options)
      : model_(model), problem_(problem), options_(options) {
    problem_.Validate(model_);
    std::string why;
    if (!options_.IsValid(&why)) throw InvalidArgument("TrajectoryOptimizer: " + why);
    N_ = problem_.num_steps;
    nq_ = model_.nq();
    nv_ = model_.nv();
    dt_ = problem_.time_step;
    unactuated_ = problem_.UnactuatedDofs(model_);
    nu_ = static_cast<int>(unactuated_.size());
    if (problem_.enable_contact && model_.geometries().size() >= 2) {
      engine_.emplace(model_, problem_.contact);
      if (engine_->num_pairs() == 0) engine_.reset();
    }
    const Eigen::VectorXd zq = Eigen::VectorXd::Zero(nq_), zv = Eigen::VectorXd::Zero(nv_);
    const Eigen::MatrixXd zvq = Eigen::MatrixXd::Zero(nv_, nq_);
    q_.assign(N_ + 1, zq);
    trial_q_.assign(N_ + 1, zq);
    v_.assign(N_ + 1, zv);
    a_.assign(N_, zv);
    tau_.assign(N_, zv);
    trial_v_ = v_;
    trial_a_ = a_;
    trial_tau_ = tau_;
    Nplus_.assign(N_ + 1, zvq);
    dv_dq_.assign(N_ + 1, zvq);
    dv_dqm_.assign(N_ + 1, zvq);
    dtau_dqm_.assign(N_, zvq);
    dtau_dq_.assign(N_, zvq);
    dtau_dqp_.assign(N_, zvq);
    M_.assign(N_ + 1, Eigen::MatrixXd::Zero(nv_, nv_));
    H_ = PentaDiagonalMatrix(N_, nq_);
    chol_ = PentaDiagonalCholesky(N_, nq_);
    const int n = N_ * nq_;
    g_ = Eigen::VectorXd::Zero(n);
    g_merit_ = g_;
    D_ = Eigen::VectorXd::Ones(n);
    p_ = g_;
    p_newton_ = g_;
    p_cauchy_ = g_;
    work_ = g_;
    work2_ = g_;
    if (engine_) {
      contact_.assign(N_, engine_->MakeData(model_));
      trial_contact_ = contact_;
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
    Prepare();
    for (int k = 0; k <= N_; ++k) q_[k] = problem_.q_init;
    trust_radius_ = options_.initial_trust_radius;
  }

  // (Re)sizes what depends on options that mutable_options() may change between solves.
  void Prepare() {
    std::string why;
    if (!options_.IsValid(&why)) throw InvalidArgument("TrajectoryOptimizer: " + why);
    UpdateEffectiveWeights();
    workspaces_.reserve(options_.num_threads);
    while (static_cast<int>(workspaces_.size()) < options_.num_threads) {
      workspaces_.emplace_back(model_, engine_ ? &*engine_ : nullptr);
    }
    const int m = N_ * nu_;
    if (options_.constraint_method == ConstraintMethod::kLagrangeMultipliers && nu_ > 0 &&
        h_.size() != m) {
      h_ = Eigen::VectorXd::Zero(m);
      lambda_ = h_;
      At_ = Eigen::MatrixXd::Zero(N_ * nq_, m);
      HinvAt_ = At_;
      S_ = Eigen::MatrixXd::Zero(m, m);
      // compute() sizes the factor and defines its status (LLT(size) leaves it undefined).
      S_llt_.compute(Eigen::MatrixXd::Identity(m, m));
    }
  }

  // ---------------------------------------------------------------------------------------
  // Kinematics of the discretization.

  // v = N+(q) (q - q_prev) / dt without forming N+.
  void Velocity(const Eigen::VectorXd& q, const Eigen::VectorXd& q_prev, Eigen::VectorXd* v) const {
    for (BodyIndex b : model_.moving_bodies()) {
      const int iq = model_.position_start(b), iv = model_.velocity_start(b);
      if (model_.joint_type(b) == JointType::kFloating) {
        // w = 4 / |Q|^2 G(Q)^T (Q - Q_prev) / dt; the rest is linear.
        const Eigen::Matrix<double, 4, 3> G = QuaternionRateMatrix(q.data() + iq);
        const double n2 = q.segment<4>(iq).squaredNorm();
        v->segment<3>(iv) =
            (4.0 / (n2 * dt_)) * G.transpose() * (q.segment<4>(iq) - q_prev.segment<4>(iq));
        v->segment<3>(iv + 3) = (q.segment<3>(iq + 4) - q_prev.segment<3>(iq + 4)) / dt_;
      } else {
        for (int k = 0; k < model_.joint_nq(b); ++k) {
          (*v)(iv + k) = (q(iq + k) - q_prev(iq + k)) / dt_;
        }
      }
    }
  }

  // d v_k / d q_k (exact, including the dependence of N+ on q_k) and d v_k / d q_{k-1}.
  void VelocityPartials(int k) {
    const Eigen::VectorXd& q = q_[k];
    const Eigen::VectorXd& q_prev = q_[k - 1];
    Eigen::MatrixXd& A = dv_dq_[k];
    Eigen::MatrixXd& B = dv_dqm_[k];
    CalcNplusMatrix(model_, q, &Nplus_[k]);
    A = Nplus_[k] / dt_;
    B = -A;
    for (JointIndex j : model_.floating_joints()) {
      const int iq = model_.position_start(j), iv = model_.velocity_start(j);
      const Eigen::Vector4d Q = q.segment<4>(iq);
      const double n2 = Q.squaredNorm();
      // w = 4/|Q|^2 G(Q_prev)^T Q / dt, so dw/dQ = 4/|Q|^2 G(Q_prev)^T / dt - 2/|Q|^2 w Q^T.
      const Eigen::Matrix<double, 4, 3> G_prev = QuaternionRateMatrix(q_prev.data() + iq);
      const Eigen::Vector3d w = v_[k].segment<3>(iv);
      A.block<3, 4>(iv, iq) =
          (4.0 / (n2 * dt_)) * G_prev.transpose() - (2.0 / n2) * w * Q.transpose();
    }
  }

  // tau = ID(q, v, a) - J^T f(q, v), using workspace ws. The contact evaluation goes to
  // `contact` (ws->contact when null).
  void Tau(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
           Workspace* ws, Eigen::VectorXd* tau, ContactData* contact = nullptr) const {
    if (engine_) {
      ContactData* cd = contact != nullptr ? contact : &ws->contact;
      ForwardKinematics(model_, q, v, &ws->data);
      const std::uint64_t t0 = Ticks();
      engine_->Evaluate(model_, ws->data, cd);
      ws->contact_ticks += TicksSince(t0);
      *tau = InverseDynamicsAfterKinematics(model_, v, a, &cd->F_ext, &ws->data);
    } else {
      *tau = InverseDynamics(model_, q, v, a, &ws->data);
    }
  }

  // As Tau for a state that differs from the one `reference` was evaluated at only in the poses
  // and velocities of the bodies flagged in `moved`: other pairs reuse their contact results.
  void TauChanged(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                  const ContactData& reference, const std::vector<char>& moved, Workspace* ws,
                  Eigen::VectorXd* tau) const {
    if (!engine_) {
      *tau = InverseDynamics(model_, q, v, a, &ws->data);
      return;
    }
    ForwardKinematics(model_, q, v, &ws->data);
    const std::uint64_t t0 = Ticks();
    engine_->EvaluateChanged(model_, ws->data, reference, moved, &ws->contact);
    ws->contact_ticks += TicksSince(t0);
    *tau = InverseDynamicsAfterKinematics(model_, v, a, &ws->contact.F_ext, &ws->data);
  }

  // The contact evaluation ticks of every thread since the last call, summed (CPU time over
  // threads, so it may exceed the wall time of the phase); resets them.
  std::uint64_t TakeContactTicks() {
    std::uint64_t total = 0;
    for (Workspace& ws : workspaces_) {
      total += ws.contact_ticks;
      ws.contact_ticks = 0;
    }
    return total;
  }

  // v, a, tau for trajectory q into (v, a, tau); returns the cost.
  // The contact evaluation of each tau_k goes to (*contact)[k] when contact is given (kept for
  // the finite differences, which reuse the pairs a perturbation does not move).
  double Evaluate(const std::vector<Eigen::VectorXd>& q, std::vector<Eigen::VectorXd>* v,
                  std::vector<Eigen::VectorXd>* a, std::vector<Eigen::VectorXd>* tau,
                  std::vector<ContactData>* contact = nullptr) {
    (*v)[0] = problem_.v_init;
    for (int k = 1; k <= N_; ++k) Velocity(q[k], q[k - 1], &(*v)[k]);
    for (int k = 0; k < N_; ++k) (*a)[k] = ((*v)[k + 1] - (*v)[k]) / dt_;
    ParallelFor(0, N_, options_.num_threads, [&](int k, int thread) {
      Tau(q[k + 1], (*v)[k + 1], (*a)[k], &workspaces_[thread], &(*tau)[k],
          contact != nullptr && engine_ ? &(*contact)[k] : nullptr);
    });
    return Cost(q, *v, *tau);
  }

  double Cost(const std::vector<Eigen::VectorXd>& q, const std::vector<Eigen::VectorXd>& v,
              const std::vector<Eigen::VectorXd>& tau) const {
    // Fixed summation order: bitwise identical for any thread count.
    double L = 0.0;
    for (int k = 0; k < N_; ++k) {
      const Eigen::VectorXd& eq = q[k];
      double running = 0.0;
      for (int i = 0; i < nq_; ++i) {
        const double e = eq(i) - problem_.q_nom[k](i);
        running += problem_.Qq(i) * e * e;
      }
      for (int i = 0; i < nv_; ++i) {
        const double e = v[k](i) - problem_.v_nom[k](i);
        running += problem_.Qv(i) * e * e + R_eff_(i) * tau[k](i) * tau[k](i);
      }
      L += 0.5 * dt_ * running;
    }
    double terminal = 0.0;
    for (int i = 0; i < nq_; ++i) {
      const double e = q[N_](i) - problem_.q_nom[N_](i);
      terminal += problem_.Qfq(i) * e * e;
    }
    for (int i = 0; i < nv_; ++i) {
      const double e = v[N_](i) - problem_.v_nom[N_](i);
      terminal += problem_.Qfv(i) * e * e;
    }
    return L + 0.5 * terminal;
  }

  double ConstraintViolation(const std::vector<Eigen::VectorXd>& tau) const {
    double s = 0.0;
    for (int k = 0; k < N_; ++k) {
      for (int d : unactuated_) s += tau[k](d) * tau[k](d);
    }
    return s;
  }

  // ---------------------------------------------------------------------------------------
  // Derivatives: d tau_j / d q_s for s = j-1, j, j+1 by finite differences, except
  // d tau_{k+1} / d q_k, which only acts through a_{k+1}: M(q_{k+2}) N+(q_{k+1}) / dt^2.

  void CalcDerivatives() {
    for (int k = 1; k <= N_; ++k) VelocityPartials(k);
    const bool central = options_.derivative_method == DerivativeMethod::kCentralDifferences;
    const double rel = options_.finite_difference_step > 0.0 ? options_.finite_difference_step
                       : central ? std::cbrt(std::numeric_limits<double>::epsilon())
                                 : std::sqrt(std::numeric_limits<double>::epsilon());
    ParallelFor(1, N_ + 1, options_.num_threads, [&](int k, int thread) {
      Workspace& ws = workspaces_[thread];
      ws.q = q_[k];
      for (int i = 0; i < nq_; ++i) {
        const double h = rel * std::max(1.0, std::abs(q_[k](i)));
        // tau_{k-1}(q_k + s e_i) into out_prev, tau_k into out_here.
        auto perturbed = [&](double s, Eigen::VectorXd* out_prev, Eigen::VectorXd* out_here) {
          // Only bodies downstream of coordinate i's joint move: their pairs are re-evaluated,
          // the others reuse the iterate's contact results (exactly equal there).
          ws.q(i) = q_[k](i) + s;
          Velocity(ws.q, q_[k - 1], &ws.v);
          ws.a = (ws.v - v_[k - 1]) / dt_;
          if (engine_) {
            TauChanged(ws.q, ws.v, ws.a, contact_[k - 1], moved_by_q_[i], &ws, out_prev);
          } else {
            Tau(ws.q, ws.v, ws.a, &ws, out_prev);
          }
          if (k < N_) {
            Velocity(q_[k + 1], ws.q, &ws.v_next);
            ws.a_next = (ws.v_next - ws.v) / dt_;
            if (engine_) {
              TauChanged(q_[k + 1], ws.v_next, ws.a_next, contact_[k], moved_by_q_[i], &ws,
                         out_here);
            } else {
              Tau(q_[k + 1], ws.v_next, ws.a_next, &ws, out_here);
            }
          }
          ws.q(i) = q_[k](i);
        };
        if (central) {
          perturbed(h, &ws.tau_a, &ws.tau_b);
          perturbed(-h, &ws.tau_c, &ws.tau_d);
          dtau_dqp_[k - 1].col(i) = (ws.tau_a - ws.tau_c) / (2.0 * h);
          if (k < N_) dtau_dq_[k].col(i) = (ws.tau_b - ws.tau_d) / (2.0 * h);
        } else {
          perturbed(h, &ws.tau_a, &ws.tau_b);
          dtau_dqp_[k - 1].col(i) = (ws.tau_a - tau_[k - 1]) / h;
          if (k < N_) dtau_dq_[k].col(i) = (ws.tau_b - tau_[k]) / h;
        }
      }
      // d tau_{k+1} / d q_k = -M(q_{k+2}) (d v_{k+1} / d q_k) / dt.
      if (k + 1 <= N_ - 1) {
        M_[k + 2] = MassMatrix(model_, q_[k + 2], &ws.data);
        dtau_dqm_[k + 1].noalias() = (-1.0 / dt_) * M_[k + 2] * dv_dqm_[k + 1];
      }
    });
  }

  // d tau_j / d q_s for s in {j-1, j, j+1}.
  const Eigen::MatrixXd& DtauDq(int j, int s) const {
    if (s == j - 1) return dtau_dqm_[j];
    if (s == j) return dtau_dq_[j];
    return dtau_dqp_[j];
  }

  // Weights of step k's position and velocity residuals (dt Q for k < N, Qf for k = N).
  const Eigen::VectorXd& Wq(int k) const { return k < N_ ? Wq_run_ : problem_.Qfq; }
  const Eigen::VectorXd& Wv(int k) const { return k < N_ ? Wv_run_ : problem_.Qfv; }

  void CalcGradient(Eigen::VectorXd* g) {
    ParallelFor(1, N_ + 1, options_.num_threads, [&](int k, int thread) {
      Eigen::VectorXd& t = workspaces_[thread].scratch_v;
      auto gk = g->segment((k - 1) * nq_, nq_);
      gk = Wq(k).cwiseProduct(q_[k] - problem_.q_nom[k]);
      t = Wv(k).cwiseProduct(v_[k] - problem_.v_nom[k]);
      gk.noalias() += dv_dq_[k].transpose() * t;
      if (k < N_) {
        t = Wv(k + 1).cwiseProduct(v_[k + 1] - problem_.v_nom[k + 1]);
        gk.noalias() += dv_dqm_[k + 1].transpose() * t;
      }
      for (int j = k - 1; j <= k + 1; ++j) {
        if (j < 0 || j > N_ - 1) continue;
        t = WR_.cwiseProduct(tau_[j]);
        gk.noalias() += DtauDq(j, k).transpose() * t;
      }
    });
  }

  // out += X^T diag(w) Y, with scratch T (nv x nq): no temporaries.
  static void AddWeightedProduct(const Eigen::MatrixXd& X, const Eigen::VectorXd& w,
                                 const Eigen::MatrixXd& Y, Eigen::MatrixXd* T,
                                 Eigen::MatrixXd* out) {
    T->noalias() = w.asDiagonal() * Y;
    out->noalias() += X.transpose() * (*T);
  }

  // Gauss-Newton Hessian, one block row per task (rows are independent: deterministic).
  void CalcHessian() {
    ParallelFor(1, N_ + 1, options_.num_threads, [&](int k, int thread) {
      Eigen::MatrixXd& T = workspaces_[thread].scratch_vq;
      const int r = k - 1;
      Eigen::MatrixXd& C = H_.C(r);
      C.setZero();
      C.diagonal() = Wq(k);
      AddWeightedProduct(dv_dq_[k], Wv(k), dv_dq_[k], &T, &C);
      if (k < N_) AddWeightedProduct(dv_dqm_[k + 1], Wv(k + 1), dv_dqm_[k + 1], &T, &C);
      for (int j = k - 1; j <= k + 1; ++j) {
        if (j < 0 || j > N_ - 1) continue;
        AddWeightedProduct(DtauDq(j, k), WR_, DtauDq(j, k), &T, &C);
      }
      // Exact symmetry of the diagonal block.
      for (int c = 0; c < nq_; ++c) {
        for (int i = c + 1; i < nq_; ++i) {
          const double m = 0.5 * (C(i, c) + C(c, i));
          C(i, c) = m;
          C(c, i) = m;
        }
      }
      if (k >= 2) {
        Eigen::MatrixXd& B = H_.B(r);
        B.setZero();
        AddWeightedProduct(dv_dq_[k], Wv(k), dv_dqm_[k], &T, &B);
        for (int j = k - 1; j <= k; ++j) {
          if (j > N_ - 1) continue;
          AddWeightedProduct(DtauDq(j, k), WR_, DtauDq(j, k - 1), &T, &B);
        }
      }
      if (k >= 3) {
        Eigen::MatrixXd& A = H_.A(r);
        A.setZero();
        AddWeightedProduct(DtauDq(k - 1, k), WR_, DtauDq(k - 1, k - 2), &T, &A);
      }
    });
  }

  // h(q) and A^T = (d h / d q)^T.
  void CalcConstraints(Eigen::VectorXd* h, Eigen::MatrixXd* At) const {
    for (int j = 0; j < N_; ++j) {
      for (int u = 0; u < nu_; ++u) (*h)(j * nu_ + u) = tau_[j](unactuated_[u]);
    }
    if (At == nullptr) return;
    At->setZero();
    for (int j = 0; j < N_; ++j) {
      for (int s = j - 1; s <= j + 1; ++s) {
        if (s < 1 || s > N_) continue;
        const Eigen::MatrixXd& T = DtauDq(j, s);
        for (int u = 0; u < nu_; ++u) {
          At->block((s - 1) * nq_, j * nu_ + u, nq_, 1) = T.row(unactuated_[u]).transpose();
        }
      }
    }
  }

  // ---------------------------------------------------------------------------------------

  void UpdateEffectiveWeights() {
    R_eff_ = problem_.R;
    if (options_.constraint_method == ConstraintMethod::kPenalty && options_.penalty_weight > 0.0) {
      for (int d : unactuated_) R_eff_(d) = options_.penalty_weight;
    }
    WR_ = dt_ * R_eff_;
    Wq_run_ = dt_ * problem_.Qq;
    Wv_run_ = dt_ * problem_.Qv;
  }

  void StoreSolution(Trajectory* solution) const {
    if (solution == nullptr) return;
    solution->q = q_;
    solution->v = v_;
    solution->tau = tau_;
    solution->tau.push_back(Eigen::VectorXd::Zero(nv_));
  }

  void SetGuess(const std::vector<Eigen::VectorXd>& q_guess) {
    if (static_cast<int>(q_guess.size()) != N_ + 1) {
      ThrowInvalidArgument("TrajectoryOptimizer::Solve", "q_guess",
                           std::to_string(q_guess.size()) + " configurations",
                           std::to_string(N_ + 1) + " (num_steps + 1)");
    }
    for (int k = 0; k <= N_; ++k) {
      model_.CheckConfiguration("TrajectoryOptimizer::Solve",
                                ("q_guess[" + std::to_string(k) + "]").c_str(), q_guess[k]);
      CheckFinite("TrajectoryOptimizer::Solve", "q_guess[" + std::to_string(k) + "]", q_guess[k]);
      q_[k] = q_guess[k];
      NormalizeQuaternions(model_, &q_[k]);
    }
    q_[0] = problem_.q_init;
    NormalizeQuaternions(model_, &q_[0]);
  }

  // Factors H_. A Gauss-Newton Hessian is positive semi-definite in exact arithmetic, but with
  // stiff contact its entries span ~18 orders of magnitude and round-off can make it
  // numerically indefinite (or a block singular). Then retry with H + mu diag(H) (scale
  // invariant, a Levenberg-Marquardt shift), mu = 1e-12, 1e-10, ..., 1e-2; the shift stays in
  // H_, so the step and the predicted reduction use the same model. *mu is the shift used.
  bool Factorize(double* mu) {
    *mu = 0.0;
    chol_.compute(H_);
    if (chol_.info() == PentaDiagonalCholesky::Info::kSuccess) return true;
    H_.Diagonal(&work_);
    double applied = 0.0;
    for (double next = 1e-12; next <= 1e-2 * (1 + 1e-9); next *= 100.0) {
      for (int r = 0; r < N_; ++r) {
        for (int i = 0; i < nq_; ++i) {
          const double d = work_(r * nq_ + i);
          // Rows without curvature get an absolute shift relative to the largest entry.
          H_.C(r)(i, i) += (next - applied) * (d > 0.0 ? d : 1.0);
        }
      }
      applied = next;
      chol_.compute(H_);
      if (chol_.info() == PentaDiagonalCholesky::Info::kSuccess) {
        *mu = applied;
        return true;
      }
    }
    return false;
  }

  // Dogleg in scaled coordinates (p = D p~). Returns the step kind; p_ holds the step.
  DoglegStep Dogleg(double radius, double* scaled_norm) {
    // Newton: |D^-1 p_N|.
    work_ = p_newton_.cwiseQuotient(D_);
    const double newton_norm = work_.norm();
    if (newton_norm <= radius) {
      p_ = p_newton_;
      *scaled_norm = newton_norm;
      return DoglegStep::kNewton;
    }
    work2_ = p_cauchy_.cwiseQuotient(D_);
    const double cauchy_norm = work2_.norm();
    if (cauchy_norm >= radius) {
      p_ = (radius / cauchy_norm) * p_cauchy_;
      *scaled_norm = radius;
      return DoglegStep::kCauchy;
    }
    // |u + t (w - u)| = radius with u = D^-1 p_C, w = D^-1 p_N, t in [0, 1].
    work_ -= work2_;  // w - u
    const double a = work_.squaredNorm();
    const double b = 2.0 * work2_.dot(work_);
    const double c = cauchy_norm * cauchy_norm - radius * radius;
    const double disc = std::sqrt(std::max(0.0, b * b - 4.0 * a * c));
    // Numerically stable root of the quadratic (c < 0, so the roots have opposite signs).
    const double t = b >= 0 ? (-2.0 * c) / (b + disc) : (disc - b) / (2.0 * a);
    p_ = p_cauchy_ + t * (p_newton_ - p_cauchy_);
    *scaled_norm = radius;
    return DoglegStep::kDogleg;
  }

  void ApplyStep(const Eigen::VectorXd& p, std::vector<Eigen::VectorXd>* q_out) const {
    (*q_out)[0] = q_[0];
    for (int k = 1; k <= N_; ++k) {
      (*q_out)[k] = q_[k] + p.segment((k - 1) * nq_, nq_);
      NormalizeQuaternions(model_, &(*q_out)[k]);
    }
  }

  SolverSummary Run(Trajectory* solution) {
    const Clock::time_point start = Clock::now();
    Prepare();
    SolverSummary summary;
    const bool lagrange =
        options_.constraint_method == ConstraintMethod::kLagrangeMultipliers && nu_ > 0;
    double cost = Evaluate(q_, &v_, &a_, &tau_, &contact_);
    TakeContactTicks();  // the initial evaluation belongs to no iteration's phases
    summary.initial_cost = cost;
    if (!std::isfinite(cost)) {
      summary.termination = TerminationType::kFailure;
      summary.message = "the cost of the initial guess is not finite";
      summary.final_cost = cost;
      summary.solve_time = Seconds(start, Clock::now());
      StoreSolution(solution);
      return summary;
    }
    bool need_derivatives = true;
    double merit = cost;
    summary.log.reserve(options_.max_iterations);
    summary.termination = TerminationType::kMaxIterations;
    for (int it = 0; it < options_.max_iterations; ++it) {
      IterationSummary s;
      s.iteration = it;
      s.cost = cost;
      s.constraint_violation = ConstraintViolation(tau_);
      const Clock::time_point t0 = Clock::now();
      if (need_derivatives) {
        const std::uint64_t k0 = Ticks();
        CalcDerivatives();
        const std::uint64_t derivative_ticks = TicksSince(k0);
        const Clock::time_point t1 = Clock::now();
        s.time_derivatives = Seconds(t0, t1);
        s.time_contact = TicksToSeconds(TakeContactTicks(), derivative_ticks, s.time_derivatives);
        CalcGradient(&g_);
        CalcHessian();
        const Clock::time_point t2 = Clock::now();
        s.time_hessian = Seconds(t1, t2);
        // Scaling from the Hessian's diagonal.
        H_.Diagonal(&D_);
        for (int i = 0; i < D_.size(); ++i) {
          const double d = D_(i);
          if (options_.scaling == ScalingMethod::kNone || !(d > 0.0) || !std::isfinite(d)) {
            D_(i) = 1.0;
          } else {
            D_(i) = options_.scaling == ScalingMethod::kSqrt ? 1.0 / std::sqrt(d)
                                                             : 1.0 / std::sqrt(std::sqrt(d));
          }
        }
        if (!Factorize(&s.regularization)) {
          s.time_factorization = Seconds(t2, Clock::now());
          summary.termination = TerminationType::kFailure;
          summary.message = "the Hessian factorization failed at block " +
                            std::to_string(chol_.failed_block()) +
                            " even with regularization; last good iterate kept";
          summary.log.push_back(s);
          break;
        }
        const Clock::time_point t3 = Clock::now();
        s.time_factorization = Seconds(t2, t3);
        g_merit_ = g_;
        merit = cost;
        if (lagrange) {
          // lambda = (A H^-1 A^T)^-1 (h - A H^-1 g), with H factored once.
          // With H = L L^T and Y = L^-1 A^T: A H^-1 A^T = Y^T Y and A H^-1 g = Y^T (L^-1 g), so
          // only forward substitutions are needed, and those skip each constraint column's
          // leading zero blocks (the rows of tau_j only involve q_{j-1}, q_j, q_{j+1}).
          CalcConstraints(&h_, &At_);
          HinvAt_ = At_;  // becomes Y
          for (int j = 0; j < N_; ++j) {
            chol_.SolveLowerInPlace(HinvAt_.middleCols(j * nu_, nu_), std::max(j - 2, 0));
          }
          S_.setZero();
          S_.selfadjointView<Eigen::Lower>().rankUpdate(HinvAt_.transpose());
          S_llt_.compute(S_);  // reads the lower triangle only
          if (S_llt_.info() != Eigen::Success) {
            summary.termination = TerminationType::kFailure;
            summary.message = "A H^-1 A^T is not positive definite (constraints not independent)";
            summary.log.push_back(s);
            break;
          }
          work_ = g_;
          chol_.SolveLowerInPlace(&work_);  // L^-1 g
          lambda_ = h_;
          lambda_.noalias() -= HinvAt_.transpose() * work_;
          S_llt_.solveInPlace(lambda_);
          g_merit_.noalias() += At_ * lambda_;
          merit = cost + h_.dot(lambda_);
          s.time_multipliers = Seconds(t3, Clock::now());
        }
        // Newton and Cauchy steps (on the merit's quadratic model).
        p_newton_ = -g_merit_;
        chol_.SolveInPlace(&p_newton_);
        work2_ = D_.cwiseProduct(D_.cwiseProduct(g_merit_));  // D^2 g
        H_.Multiply(work2_, &work_);
        const double gHg = work2_.dot(work_);
        const double gg = D_.cwiseProduct(g_merit_).squaredNorm();
        if (gHg > 0.0) {
          p_cauchy_ = (-gg / gHg) * work2_;
        } else {
          p_cauchy_ = -work2_;
        }
        need_derivatives = false;
      }
      s.merit = merit;
      s.gradient_norm = g_merit_.norm();
      s.trust_radius = trust_radius_;
      s.step_type = Dogleg(trust_radius_, &s.scaled_step_norm);
      s.step_norm = p_.norm();
      // Predicted reduction of the quadratic model.
      H_.Multiply(p_, &work_);
      const double predicted = -(g_merit_.dot(p_) + 0.5 * p_.dot(work_));
      const Clock::time_point tc = Clock::now();
      const std::uint64_t kc = Ticks();
      ApplyStep(p_, &trial_q_);
      const double trial_cost =
          Evaluate(trial_q_, &trial_v_, &trial_a_, &trial_tau_, &trial_contact_);
      double trial_merit = trial_cost;
      if (lagrange) {
        for (int j = 0; j < N_; ++j) {
          for (int u = 0; u < nu_; ++u) {
            trial_merit += lambda_(j * nu_ + u) * trial_tau_[j](unactuated_[u]);
          }
        }
      }
      const std::uint64_t cost_ticks = TicksSince(kc);
      s.time_cost = Seconds(tc, Clock::now());
      s.time_contact += TicksToSeconds(TakeContactTicks(), cost_ticks, s.time_cost);
      s.trial_cost = trial_cost;
      const double actual = merit - trial_merit;
      s.ratio = std::isfinite(trial_merit) && predicted > 0.0
                    ? actual / predicted
                    : -std::numeric_limits<double>::infinity();
      // Radius update (Nocedal & Wright, Algorithm 4.1).
      if (s.ratio < 0.25) {
        trust_radius_ = 0.25 * s.scaled_step_norm;
      } else if (s.ratio > 0.75 && s.scaled_step_norm >= trust_radius_ * (1.0 - 1e-12)) {
        trust_radius_ = std::min(2.0 * trust_radius_, options_.max_trust_radius);
      }
      s.accepted = s.ratio > options_.acceptance_ratio;
      const double step_ratio = s.step_norm / std::max(1.0, QNorm());
      const double gp = std::abs(g_merit_.dot(p_)) / std::max(1.0, std::abs(cost));
      if (s.accepted) {
        std::swap(q_, trial_q_);
        std::swap(v_, trial_v_);
        std::swap(a_, trial_a_);
        std::swap(tau_, trial_tau_);
        std::swap(contact_, trial_contact_);
        const double previous = cost;
        cost = trial_cost;
        need_derivatives = true;
        s.time_total = Seconds(t0, Clock::now());
        summary.log.push_back(s);
        ++summary.iterations;
        if (!options_.fixed_iterations) {
          const double change = std::abs(previous - cost) / std::max(1.0, std::abs(previous));
          if (change < options_.cost_tolerance) {
            summary.termination = TerminationType::kConverged;
            summary.message = "relative cost change below cost_tolerance";
          } else if (gp < options_.gradient_tolerance) {
            summary.termination = TerminationType::kConverged;
            summary.message = "|g^T p| / L below gradient_tolerance";
          } else if (step_ratio < options_.step_tolerance) {
            summary.termination = TerminationType::kConverged;
            summary.message = "relative step below step_tolerance";
          }
        }
      } else {
        s.time_total = Seconds(t0, Clock::now());
        summary.log.push_back(s);
        ++summary.iterations;
        // Near a stationary point the predicted reduction sinks to round-off and steps are
        // rejected for noise: that is convergence, not failure. The radius is floored so a
        // warm-started solve (MPC) can move again when its problem changes.
        const bool negligible = !(std::abs(predicted) > 1e-14 * std::max(1.0, std::abs(merit)));
        const bool at_floor = trust_radius_ < kMinTrustRadius;
        if (at_floor) trust_radius_ = kMinTrustRadius;
        if (!std::isfinite(trial_merit) && at_floor) {
          summary.termination = TerminationType::kFailure;
          summary.message =
              "the cost is not finite even for the smallest trust region; last good iterate kept";
        } else if (!options_.fixed_iterations) {
          if (step_ratio < options_.step_tolerance && s.step_norm > 0.0) {
            summary.termination = TerminationType::kConverged;
            summary.message = "relative step below step_tolerance (rejected step)";
          } else if (negligible || at_floor) {
            summary.termination = TerminationType::kConverged;
            summary.message = "no reduction predicted above round-off (stationary point)";
          }
        }
      }
      if (options_.verbosity > 0) {
        std::printf("%4d cost %.6e rho %.3e radius %.3e %s\n", it, s.cost, s.ratio, s.trust_radius,
                    s.accepted ? "accepted" : "rejected");
      }
      for (const IterationCallback& cb : callbacks_) {
        const CallbackReturn r = cb(summary.log.back());
        if (r != CallbackReturn::kContinue) {
          summary.termination = TerminationType::kUserTermination;
          summary.message =
              r == CallbackReturn::kAbort ? "aborted by a callback" : "terminated by a callback";
        }
      }
      if (summary.termination != TerminationType::kMaxIterations) break;
    }
    summary.final_cost = cost;
    summary.constraint_violation = ConstraintViolation(tau_);
    summary.solve_time = Seconds(start, Clock::now());
    StoreSolution(solution);
    return summary;
  }

  double QNorm() const {
    double s = 0.0;
    for (int k = 1; k <= N_; ++k) s += q_[k].squaredNorm();
    return std::sqrt(s);
  }

  // For the public evaluation entry points: set q_ (and derived quantities) to q.
  void LoadIterate(const std::vector<Eigen::VectorXd>& q) {
    if (static_cast<int>(q.size()) != N_ + 1) {
      ThrowInvalidArgument("TrajectoryOptimizer", "q", std::to_string(q.size()) + " entries",
                           std::to_string(N_ + 1) + " (num_steps + 1)");
    }
    for (int k = 0; k <= N_; ++k) {
      model_.CheckConfiguration("TrajectoryOptimizer", "q[k]", q[k]);
      q_[k] = q[k];
    }
    Evaluate(q_, &v_, &a_, &tau_, &contact_);
  }

  Model model_;
  ProblemDefinition problem_;
  SolverOptions options_;
  int N_{0}, nq_{0}, nv_{0}, nu_{0};
  double dt_{0.0};
  std::vector<int> unactuated_;
  Eigen::VectorXd R_eff_, WR_, Wq_run_, Wv_run_;
  std::optional<ContactEngine> engine_;
  std::vector<Workspace> workspaces_;
  std::vector<IterationCallback> callbacks_;

  std::vector<Eigen::VectorXd> q_, v_, a_, tau_;
  // Contact evaluation of each tau_k at the iterate (and at the trial point).
  std::vector<ContactData> contact_, trial_contact_;
  // For each position coordinate: the bodies whose pose or velocity it moves (num_bodies).
  std::vector<std::vector<char>> moved_by_q_;
  std::vector<Eigen::VectorXd> trial_q_, trial_v_, trial_a_, trial_tau_;
  std::vector<Eigen::MatrixXd> Nplus_, dv_dq_, dv_dqm_, dtau_dqm_, dtau_dq_, dtau_dqp_, M_;
  PentaDiagonalMatrix H_;
  PentaDiagonalCholesky chol_;
  Eigen::VectorXd g_, g_merit_, D_, p_, p_newton_, p_cauchy_, work_, work2_;
  Eigen::VectorXd h_, lambda_;
  Eigen::MatrixXd At_, HinvAt_, S_;
  Eigen::LLT<Eigen::MatrixXd> S_llt_;
  double trust_radius_{0.1};
};

TrajectoryOptimizer::TrajectoryOptimizer(const Model& model, const ProblemDefinition& problem,
                                         const SolverOptions& options)
    : impl_(std::make_unique<Impl>(model, problem, options)) {}
TrajectoryOptimizer::~TrajectoryOptimizer() = default;
TrajectoryOptimizer::TrajectoryOptimizer(TrajectoryOptimizer&&) noexcept = default;
TrajectoryOptimizer& TrajectoryOptimizer::operator=(TrajectoryOptimizer&&) noexcept = default;

SolverSummary TrajectoryOptimizer::Solve(const std::vector<Eigen::VectorXd>& q_guess,
                                         Trajectory* solution) {
  impl_->SetGuess(q_guess);
  impl_->trust_radius_ = impl_->options_.initial_trust_radius;
  return impl_->Run(solution);
}

SolverSummary TrajectoryOptimizer::SolveWarmStart(Trajectory* solution) {
  return impl_->Run(solution);
}

void TrajectoryOptimizer::ResetInitialConditions(const Eigen::VectorXd& q_init,
                                                 const Eigen::VectorXd& v_init) {
  ProblemDefinition& p = impl_->problem_;
  impl_->model_.CheckConfiguration("TrajectoryOptimizer::ResetInitialConditions", "q_init", q_init);
  impl_->model_.CheckVelocity("TrajectoryOptimizer::ResetInitialConditions", "v_init", v_init);
  CheckFinite("TrajectoryOptimizer::ResetInitialConditions", "q_init", q_init);
  CheckFinite("TrajectoryOptimizer::ResetInitialConditions", "v_init", v_init);
  p.q_init = q_init;
  p.v_init = v_init;
  impl_->q_[0] = q_init;
  NormalizeQuaternions(impl_->model_, &impl_->q_[0]);
}

void TrajectoryOptimizer::UpdateNominalTrajectory(const std::vector<Eigen::VectorXd>& q_nom,
                                                  const std::vector<Eigen::VectorXd>& v_nom) {
  ProblemDefinition candidate = impl_->problem_;
  candidate.q_nom = q_nom;
  candidate.v_nom = v_nom;
  candidate.Validate(impl_->model_);
  impl_->problem_ = std::move(candidate);
}

void TrajectoryOptimizer::SetIterate(const std::vector<Eigen::VectorXd>& q) { impl_->SetGuess(q); }

void TrajectoryOptimizer::AddCallback(IterationCallback callback) {
  impl_->callbacks_.push_back(std::move(callback));
}

const ProblemDefinition& TrajectoryOptimizer::problem() const { return impl_->problem_; }
const SolverOptions& TrajectoryOptimizer::options() const { return impl_->options_; }
SolverOptions& TrajectoryOptimizer::mutable_options() { return impl_->options_; }
const Model& TrajectoryOptimizer::model() const { return impl_->model_; }
double TrajectoryOptimizer::trust_radius() const { return impl_->trust_radius_; }

double TrajectoryOptimizer::EvalCost(const std::vector<Eigen::VectorXd>& q) {
  impl_->LoadIterate(q);
  return impl_->Cost(impl_->q_, impl_->v_, impl_->tau_);
}

void TrajectoryOptimizer::EvalTrajectory(const std::vector<Eigen::VectorXd>& q,
                                         Trajectory* trajectory) {
  impl_->LoadIterate(q);
  impl_->StoreSolution(trajectory);
}

void TrajectoryOptimizer::EvalGradient(const std::vector<Eigen::VectorXd>& q, Eigen::VectorXd* g) {
  impl_->LoadIterate(q);
  impl_->CalcDerivatives();
  g->resize(impl_->N_ * impl_->nq_);
  impl_->CalcGradient(g);
}

Eigen::MatrixXd TrajectoryOptimizer::EvalDenseHessian(const std::vector<Eigen::VectorXd>& q) {
  impl_->LoadIterate(q);
  impl_->CalcDerivatives();
  impl_->CalcHessian();
  return impl_->H_.MakeDense();
}

void TrajectoryOptimizer::EvalConstraints(const std::vector<Eigen::VectorXd>& q,
                                          Eigen::VectorXd* h) {
  impl_->LoadIterate(q);
  h->resize(impl_->N_ * impl_->nu_);
  impl_->CalcConstraints(h, nullptr);
}

}  // namespace idto
