#include "idto/mpc/controller.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"

namespace idto::mpc {

void MpcOptions::Validate(const Model& model) const {
  static constexpr const char* kWhere = "MpcOptions";
  CheckPositive(kWhere, "control_rate", control_rate);
  if (iterations_per_step < 1) {
    ThrowInvalidArgument(kWhere, "iterations_per_step", std::to_string(iterations_per_step),
                         "at least 1");
  }
  for (size_t k = 0; k < relative_positions.size(); ++k) {
    const int j = relative_positions[k];
    if (j < 0 || j >= model.nq()) {
      ThrowInvalidArgument(kWhere, "relative_positions[" + std::to_string(k) + "]",
                           std::to_string(j),
                           "a position index in [0, " + std::to_string(model.nq()) + ")");
    }
  }
  for (size_t k = 0; k < relative_goals.size(); ++k) {
    const RelativeGoal& g = relative_goals[k];
    const std::string name = "relative_goals[" + std::to_string(k) + "]";
    if (std::find(relative_positions.begin(), relative_positions.end(), g.position) ==
        relative_positions.end()) {
      ThrowInvalidArgument(kWhere, name + ".position", std::to_string(g.position),
                           "a position index listed in relative_positions");
    }
    for (size_t i = 0; i < k; ++i) {
      if (relative_goals[i].position == g.position) {
        ThrowInvalidArgument(kWhere, name + ".position", std::to_string(g.position),
                             "a position without a goal in an earlier entry");
      }
    }
    if (!std::isfinite(g.goal)) {
      ThrowInvalidArgument(kWhere, name + ".goal", FormatValue(g.goal), "a finite position");
    }
  }
  for (size_t k = 0; k < orientation_leads.size(); ++k) {
    const OrientationLead& lead = orientation_leads[k];
    const std::string name = "orientation_leads[" + std::to_string(k) + "]";
    bool is_quaternion = false;
    for (const JointIndex j : model.floating_joints()) {
      is_quaternion = is_quaternion || model.position_start(j) == lead.position_start;
    }
    if (!is_quaternion) {
      ThrowInvalidArgument(kWhere, name + ".position_start", std::to_string(lead.position_start),
                           "the first position index of a floating joint's quaternion");
    }
    if (!(std::isfinite(lead.max_angle) && lead.max_angle > 0.0)) {
      ThrowInvalidArgument(kWhere, name + ".max_angle", FormatValue(lead.max_angle),
                           "a finite positive angle in rad");
    }
  }
}

namespace {

Eigen::Quaterniond QuaternionAt(const Eigen::VectorXd& q, int s) {
  return Eigen::Quaterniond(q(s), q(s + 1), q(s + 2), q(s + 3)).normalized();
}

void SetQuaternionAt(const Eigen::Quaterniond& Q, int s, Eigen::VectorXd* q) {
  (*q)(s) = Q.w();
  (*q)(s + 1) = Q.x();
  (*q)(s + 2) = Q.y();
  (*q)(s + 3) = Q.z();
}

}  // namespace

Eigen::Quaterniond LeadOrientation(const Eigen::Quaterniond& measured,
                                   const Eigen::Quaterniond& target, double max_angle) {
  Eigen::Quaterniond E = target * measured.conjugate();  // measured -> target, in J
  if (E.w() < 0.0) E.coeffs() = -E.coeffs();
  const double s = E.vec().norm();
  const double angle = 2.0 * std::atan2(s, E.w());
  if (angle <= max_angle || s == 0.0) return target;
  const Eigen::AngleAxisd step(max_angle, E.vec() / s);
  return (Eigen::Quaterniond(step) * measured).normalized();
}

void Plan::Sample(const Model& model, double t, Eigen::VectorXd* q_d, Eigen::VectorXd* v_d,
                  Eigen::VectorXd* u_ff) const {
  if (q_d != nullptr) {
    q_spline.Evaluate(t, q_d);
    NormalizeQuaternions(model, q_d);
  }
  if (v_d != nullptr) v_spline.Evaluate(t, v_d);
  if (u_ff != nullptr) tau_spline.Evaluate(t, u_ff);
}

Controller::Controller(const Model& model, const ProblemDefinition& problem,
                       const SolverOptions& solver, const MpcOptions& options)
    : model_(model), problem_(problem), options_(options) {
  problem_.Validate(model_);
  options_.Validate(model_);
  if (options_.actuated.empty()) {
    const std::vector<int> unactuated = problem_.UnactuatedDofs(model_);
    for (int i = 0; i < model_.nv(); ++i) {
      if (!std::binary_search(unactuated.begin(), unactuated.end(), i)) {
        options_.actuated.push_back(i);
      }
    }
  }
  PdGains gains = options_.gains;
  if (gains.Kp.size() == 0) gains.Kp = Eigen::VectorXd::Zero(model_.nv());
  if (gains.Kd.size() == 0) gains.Kd = Eigen::VectorXd::Zero(model_.nv());
  pd_ = std::make_unique<PdController>(model_, options_.actuated, gains);
  SolverOptions s = solver;
  s.max_iterations = options_.iterations_per_step;
  s.fixed_iterations = true;
  optimizer_ = std::make_unique<TrajectoryOptimizer>(model_, problem_, s);
  const int N = problem_.num_steps;
  q_shift_.assign(N + 1, problem_.q_init);
  q_nom_ = problem_.q_nom;
  knot_times_.resize(N + 1);
}

Controller::~Controller() = default;

void Controller::Publish(double t, const Trajectory& solution) {
  const int N = problem_.num_steps;
  const double dt = problem_.time_step;
  plan_.start_time = t;
  plan_.time_step = dt;
  plan_.q = solution.q;
  plan_.v = solution.v;
  plan_.tau = solution.tau;
  plan_.tau[N] = plan_.tau[N - 1];  // hold the last force over the final interval
  for (int k = 0; k <= N; ++k) knot_times_[k] = t + k * dt;
  plan_.q_spline.Fit(knot_times_, plan_.q);
  plan_.v_spline.Fit(knot_times_, plan_.v);
  plan_.tau_spline.Fit(knot_times_, plan_.tau);
}

SolverSummary Controller::Initialize(const std::vector<Eigen::VectorXd>& q_guess,
                                     int initial_iterations) {
  if (initial_iterations < 0) {
    ThrowInvalidArgument("Controller::Initialize", "initial_iterations",
                         std::to_string(initial_iterations), "an integer >= 0");
  }
  SolverOptions& o = optimizer_->mutable_options();
  const int per_step = o.max_iterations;
  o.max_iterations = initial_iterations;  // 0: the first plan is the guess itself
  const SolverSummary summary = optimizer_->Solve(q_guess, &solution_);
  o.max_iterations = per_step;
  Publish(0.0, solution_);
  return summary;
}

SolverSummary Controller::Replan(double t, const Eigen::VectorXd& q_hat,
                                 const Eigen::VectorXd& v_hat) {
  const int N = problem_.num_steps;
  const double dt = problem_.time_step;
  // Warm start: the previous plan resampled at the new knot times.
  for (int k = 0; k <= N; ++k) {
    plan_.q_spline.Evaluate(t + k * dt, &q_shift_[k]);
    NormalizeQuaternions(model_, &q_shift_[k]);
  }
  q_shift_[0] = q_hat;
  optimizer_->ResetInitialConditions(q_hat, v_hat);
  if (!options_.relative_positions.empty() || !options_.orientation_leads.empty()) {
    for (int k = 0; k <= N; ++k) {
      q_nom_[k] = problem_.q_nom[k];
      for (int j : options_.relative_positions) {
        q_nom_[k](j) = q_hat(j) + (problem_.q_nom[k](j) - problem_.q_init(j));
      }
      for (const MpcOptions::RelativeGoal& g : options_.relative_goals) {
        const int j = g.position;
        const bool above = g.goal >= problem_.q_init(j);  // the goal's side, seen from the start
        q_nom_[k](j) = above ? std::min(q_nom_[k](j), g.goal) : std::max(q_nom_[k](j), g.goal);
      }
    }
    for (const MpcOptions::OrientationLead& lead : options_.orientation_leads) {
      const int s = lead.position_start;
      const Eigen::Quaterniond measured = QuaternionAt(q_hat, s);
      Eigen::Quaterniond previous = measured;
      for (int k = 0; k <= N; ++k) {
        Eigen::Quaterniond Q =
            LeadOrientation(measured, QuaternionAt(problem_.q_nom[k], s), lead.max_angle);
        if (Q.dot(previous) < 0.0) Q.coeffs() = -Q.coeffs();
        SetQuaternionAt(Q, s, &q_nom_[k]);
        previous = Q;
      }
    }
    optimizer_->UpdateNominalTrajectory(q_nom_, problem_.v_nom);
  }
  optimizer_->SetIterate(q_shift_);
  q_warm_ = q_shift_;
  SolverSummary summary = optimizer_->SolveWarmStart(&solution_);
  bool finite = summary.termination != TerminationType::kFailure;
  for (int k = 0; finite && k <= N; ++k) {
    finite =
        solution_.q[k].allFinite() && solution_.v[k].allFinite() && solution_.tau[k].allFinite();
  }
  if (!finite) {
    ++num_rejected_;
    summary.termination = TerminationType::kFailure;
    summary.message =
        "plan rejected (" +
        (summary.message.empty() ? std::string("non-finite values") : summary.message) +
        "); the previous plan is kept";
    return summary;
  }
  Publish(t, solution_);
  return summary;
}

void Controller::Control(double t, const Eigen::VectorXd& q_hat, const Eigen::VectorXd& v_hat,
                         Eigen::VectorXd* u) {
  plan_.Sample(model_, t, &q_d_, &v_d_, &u_ff_);
  pd_->Compute(q_hat, v_hat, q_d_, v_d_, u_ff_, u);
}

}  // namespace idto::mpc
