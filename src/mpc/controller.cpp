#include "idto/mpc/controller.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/algorithms/jacobians.hpp"
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
  CheckNonNegative(kWhere, "estimator.position_time_constant", estimator.position_time_constant);
  if (hold.position_start >= 0) ValidateHold(model);
}

void MpcOptions::ValidateHold(const Model& model) const {
  static constexpr const char* kWhere = "MpcOptions";
  bool is_quaternion = false;
  for (const JointIndex j : model.floating_joints()) {
    is_quaternion = is_quaternion || model.position_start(j) == hold.position_start;
  }
  if (!is_quaternion) {
    ThrowInvalidArgument(kWhere, "hold.position_start", std::to_string(hold.position_start),
                         "the first position index of a floating joint's quaternion");
  }
  CheckPositive(kWhere, "hold.enter_angle", hold.enter_angle);
  CheckPositive(kWhere, "hold.distance", hold.distance);
  if (!(std::isfinite(hold.exit_angle) && hold.exit_angle > hold.enter_angle)) {
    ThrowInvalidArgument(
        kWhere, "hold.exit_angle", FormatValue(hold.exit_angle),
        "a finite angle above hold.enter_angle = " + FormatValue(hold.enter_angle));
  }
  const std::pair<const char*, double> non_negative[] = {
      {"hold.predict", hold.predict},     {"hold.rest_exit_angle", hold.rest_exit_angle},
      {"hold.refresh", hold.refresh},     {"hold.seek_rate", hold.seek_rate},
      {"hold.seek_step", hold.seek_step}, {"hold.seek_max", hold.seek_max}};
  for (const auto& [name, value] : non_negative) {
    if (!(std::isfinite(value) && value >= 0.0)) {
      ThrowInvalidArgument(kWhere, name, FormatValue(value), "a finite number >= 0");
    }
  }
  if (hold.tips.empty() || hold.tips.size() != hold.squeeze.size()) {
    ThrowInvalidArgument(
        kWhere, "hold.tips", std::to_string(hold.tips.size()) + " bodies",
        "one or more, as many as hold.squeeze (" + std::to_string(hold.squeeze.size()) + ")");
  }
  for (size_t k = 0; k < hold.tips.size(); ++k) {
    if (hold.tips[k] < 1 || hold.tips[k] >= model.num_bodies()) {
      ThrowInvalidArgument(kWhere, "hold.tips[" + std::to_string(k) + "]",
                           std::to_string(hold.tips[k]),
                           "a body index in [1, " + std::to_string(model.num_bodies()) + ")");
    }
    if (!(std::isfinite(hold.squeeze[k]) && std::abs(hold.squeeze[k]) < hold.distance)) {
      ThrowInvalidArgument(kWhere, "hold.squeeze[" + std::to_string(k) + "]",
                           FormatValue(hold.squeeze[k]),
                           "a finite length smaller than hold.distance in magnitude");
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
  if (options_.hold.position_start >= 0) SetUpHold();
}

void Controller::SetUpHold() {
  const MpcOptions::Hold& h = options_.hold;
  const int N = problem_.num_steps;
  for (const JointIndex j : model_.floating_joints()) {
    if (model_.position_start(j) == h.position_start) {
      hold_velocity_start_ = model_.velocity_start(j);
    }
  }
  q_index_of_v_.assign(model_.nv(), -1);
  for (int i : options_.actuated) {
    q_index_of_v_[i] = model_.position_start(model_.GetJointIndex(model_.velocity_name(i)));
  }
  hold_data_ = std::make_unique<Data>(model_);
  ForwardKinematics(model_, problem_.q_init, hold_data_.get());
  for (size_t f = 0; f < h.tips.size(); ++f) {
    hold_tips0_.push_back(hold_data_->X_WB(h.tips[f]).translation());
    CalcPointJacobian(model_, *hold_data_, h.tips[f], Eigen::Vector3d::Zero(), &hold_J_);
    std::vector<int> dofs;
    for (int i : options_.actuated) {
      if (hold_J_.col(i).norm() > 1e-9) dofs.push_back(i);
    }
    if (dofs.empty() || dofs.size() > static_cast<size_t>(MpcOptions::kMaxHoldTipDofs)) {
      ThrowInvalidArgument("Controller", "options.hold.tips[" + std::to_string(f) + "]",
                           "body " + model_.body_name(h.tips[f]) + " moved by " +
                               std::to_string(dofs.size()) + " actuated DoFs",
                           "a body moved by 1 to " + std::to_string(MpcOptions::kMaxHoldTipDofs));
    }
    hold_dofs_.push_back(dofs);
  }
  hold_traj_.q.assign(N + 1, problem_.q_init);
  hold_traj_.v.assign(N + 1, Eigen::VectorXd::Zero(model_.nv()));
  hold_traj_.tau.assign(N + 1, Eigen::VectorXd::Zero(model_.nv()));
}

bool Controller::UpdateHold(const Eigen::VectorXd& q_hat, const Eigen::VectorXd& v_hat) {
  const MpcOptions::Hold& h = options_.hold;
  const int s = h.position_start;
  // The rotation that takes the measured orientation to the target, and its angle theta.
  Eigen::Quaterniond E =
      QuaternionAt(problem_.q_nom.back(), s) * QuaternionAt(q_hat, s).conjugate();
  if (E.w() < 0.0) E.coeffs() = -E.coeffs();
  const double sn = E.vec().norm();
  const double theta = 2.0 * std::atan2(sn, E.w());
  const Eigen::Vector3d w = v_hat.segment<3>(hold_velocity_start_);  // world
  const double approach = sn > 0.0 ? w.dot(E.vec() / sn) : 0.0;      // d(-theta)/dt
  const double predicted = theta - std::max(0.0, approach) * h.predict;
  const Eigen::Vector3d centre = q_hat.segment<3>(s + 4);
  const bool spinning = std::abs(w.z()) > h.seek_rate;
  if (!holding_ && std::min(theta, predicted) < h.enter_angle) {
    holding_ = true;
    hold_centre_ = centre;
    hold_extra_ = 0.0;
  } else if (holding_ && (theta > h.exit_angle ||
                          (h.rest_exit_angle > 0.0 && theta > h.rest_exit_angle && !spinning))) {
    holding_ = false;
  }
  if (!holding_) return false;
  if ((centre - hold_centre_).norm() > h.refresh) hold_centre_ = centre;
  if (h.seek_step > 0.0) {
    hold_extra_ = spinning ? std::min(hold_extra_ + h.seek_step, h.seek_max)
                           : std::max(hold_extra_ - 0.25 * h.seek_step, 0.0);
  }
  return true;
}

void Controller::PlaceTip(size_t f, const Eigen::Vector3d& goal, Eigen::VectorXd* q) {
  const int tip = options_.hold.tips[f];
  const std::vector<int>& dofs = hold_dofs_[f];
  const int n = static_cast<int>(dofs.size());
  using TipJacobian = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, MpcOptions::kMaxHoldTipDofs>;
  using TipVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, MpcOptions::kMaxHoldTipDofs, 1>;
  using TipMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0,
                                  MpcOptions::kMaxHoldTipDofs, MpcOptions::kMaxHoldTipDofs>;
  TipJacobian J(3, n);
  TipVector r(n);
  // Gauss-Newton on |J dq - e|^2 + mu |q + dq - q_init|^2: the solution stays near q_init, so the
  // grasp does not jump between inverse-kinematics branches as the ball's estimate moves.
  constexpr double kMu = 1e-5;  // m^2 / rad^2
  for (int it = 0; it < 30; ++it) {
    ForwardKinematics(model_, *q, hold_data_.get());
    const Eigen::Vector3d e = goal - hold_data_->X_WB(tip).translation();
    CalcPointJacobian(model_, *hold_data_, tip, Eigen::Vector3d::Zero(), &hold_J_);
    for (int k = 0; k < n; ++k) {
      J.col(k) = hold_J_.col(dofs[k]);
      const int j = q_index_of_v_[dofs[k]];
      r(k) = (*q)(j)-problem_.q_init(j);
    }
    TipMatrix H = J.transpose() * J;
    H.diagonal().array() += kMu;
    const TipVector dq = H.ldlt().solve(J.transpose() * e - kMu * r);
    for (int k = 0; k < n; ++k) {
      const int j = q_index_of_v_[dofs[k]];
      (*q)(j) = std::clamp((*q)(j) + dq(k), model_.position_lower_limits()(j),
                           model_.position_upper_limits()(j));
    }
  }
}

void Controller::BuildHoldPlan(const Eigen::VectorXd& q_hat) {
  const MpcOptions::Hold& h = options_.hold;
  Eigen::VectorXd& q = hold_traj_.q[0];
  q = problem_.q_init;
  q.segment<7>(h.position_start) = q_hat.segment<7>(h.position_start);
  for (size_t f = 0; f < h.tips.size(); ++f) {
    // Radially: towards the centre along the horizontal direction of the tip at q_init.
    Eigen::Vector3d d = hold_tips0_[f] - hold_centre_;
    d.z() = 0.0;
    d.normalize();
    PlaceTip(f, hold_centre_ + (h.distance - (h.squeeze[f] + hold_extra_)) * d, &q);
  }
  const Eigen::VectorXd& zero = hold_traj_.v[0];
  const Eigen::VectorXd& g = InverseDynamics(model_, q, zero, zero, hold_data_.get());
  Eigen::VectorXd& tau = hold_traj_.tau[0];
  tau.setZero();
  for (int i : options_.actuated) tau(i) = g(i);
  for (size_t k = 1; k < hold_traj_.q.size(); ++k) {
    hold_traj_.q[k] = q;
    hold_traj_.tau[k] = tau;
  }
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
  if (options_.hold.position_start >= 0 && UpdateHold(q_hat, v_hat)) {
    // The grasp replaces the solver's plan (MpcOptions::Hold) and warm-starts the next solve. A
    // failed solve is still a failed re-plan: counted, and the closed loop keeps its plan.
    BuildHoldPlan(q_hat);
    Publish(t, hold_traj_);
    if (summary.termination == TerminationType::kFailure) ++num_rejected_;
    return summary;
  }
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
