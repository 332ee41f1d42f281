#pragma once

/// @file
/// Contact-implicit MPC by real-time iteration (paper §6.4): at each control step, shift the
/// previous plan to the current time, reset the initial condition to the measured state,
/// optionally shift the nominal trajectory, run a few solver iterations from the warm start,
/// and publish the new plan; a PD+ controller tracks it between re-plans.

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/mpc/pd_controller.hpp"
#include "idto/mpc/spline.hpp"
#include "idto/multibody/data.hpp"
#include "idto/multibody/model.hpp"
#include "idto/problem/problem_definition.hpp"
#include "idto/solver/solver_options.hpp"
#include "idto/solver/solver_summary.hpp"
#include "idto/solver/trajectory_optimizer.hpp"

namespace idto::mpc {

/// Options of the real-time-iteration controller.
struct MpcOptions {
  double control_rate{100.0};  ///< Hz: a new plan every 1 / control_rate seconds
  int iterations_per_step{1};  ///< solver iterations per re-plan (paper: 1)
  /// Position coordinates whose nominal moves with the robot: at each re-plan,
  /// qbar_k(j) = q_measured(j) + (qbar0_k(j) - q_init0(j)), i.e. the original offsets from the
  /// initial condition are kept (the spinner's target stays 2 rad ahead; a walking robot's
  /// target stays ahead of its base).
  std::vector<int> relative_positions;
  /// Where a relative coordinate's target stops: for each entry, the nominal of position index
  /// `position` (one of relative_positions) never lies beyond `goal` (absolute, in q's units),
  /// seen from the problem's q_init0(j). At each re-plan and knot k, with d_k = qbar0_k(j) -
  /// q_init0(j): qbar_k(j) = min(q_measured(j) + d_k, goal) when goal >= q_init0(j), and
  /// max(q_measured(j) + d_k, goal) otherwise. So the target moves with the robot until it
  /// reaches the goal and then stays there, also when the robot has passed it (the hopper hops
  /// to a goal 0.7 m from its start and stands, instead of chasing a target that never stops).
  struct RelativeGoal {
    int position{0};   ///< a position index listed in relative_positions
    double goal{0.0};  ///< finite
  };
  std::vector<RelativeGoal> relative_goals;
  /// Orientation targets approached at a bounded lead: for each entry, the nominal orientation
  /// of the floating joint whose quaternion starts at position index `position_start` is, at
  /// each re-plan and knot k, the measured orientation turned towards the problem's nominal
  /// Qbar0_k by at most `max_angle` (rad, > 0) about the axis of the shortest rotation between
  /// them (in the joint's frame J): Qbar_k = exp(min(theta_k, max_angle) a_k / 2) Q_measured,
  /// where Qbar0_k Q_measured^-1 turns by theta_k in [0, pi] about a_k. The target thus moves
  /// with the object, a bounded angle ahead of it, and stops at the problem's nominal (paper
  /// §6.4's Allegro ball turned 180 degrees; a far target held over the whole horizon asks for
  /// more rotation than one real-time iteration can plan). Knot signs are kept continuous.
  struct OrientationLead {
    int position_start{0};  ///< index of the quaternion's w in q
    double max_angle{0.5};  ///< rad
  };
  std::vector<OrientationLead> orientation_leads;
  /// A hold law outside the optimizer (off while position_start < 0; docs/mpc.md, session 38).
  /// At each re-plan the orientation error theta of the floating body whose quaternion starts at
  /// position_start is measured against the problem's final nominal orientation. The hold starts
  /// when theta < enter_angle, or when the body's measured rotation towards the target will bring
  /// theta below it within `predict` seconds; while it lasts, the published plan is a grasp
  /// instead of the solver's plan (the solver still runs at every step): each fingertip body in
  /// `tips` is placed by inverse kinematics on its own joints (least squares, pulled towards
  /// q_init, within the position limits; so within about 2 mm) at `distance - squeeze[i]` from
  /// the body's centre,
  /// along the horizontal direction in which it lies from the centre at q_init; v = 0 and the
  /// feed-forward torque is the grasp's gravity compensation. The PD turns a squeeze of a
  /// fraction of a millimetre into a light touch. The centre is the body's measured one, taken
  /// again when the body moves more than `refresh` from it. Contact seeking: while the body
  /// spins about the world's z faster than seek_rate, every squeeze grows by seek_step per
  /// re-plan (up to seek_max more), else it shrinks by seek_step / 4. The hold ends when theta
  /// exceeds exit_angle, or rest_exit_angle (0: off) with the body spinning slower than
  /// seek_rate (it came to rest short of or past the target and the solver turns it again).
  struct Hold {
    int position_start{-1};
    double enter_angle{0.06};     ///< rad, > 0
    double predict{0.0};          ///< s, >= 0
    double exit_angle{0.5};       ///< rad, > enter_angle
    double rest_exit_angle{0.0};  ///< rad, >= 0 (0: off)
    double distance{0.072};       ///< m, > 0: body radius + fingertip radius
    double refresh{0.02};         ///< m, >= 0
    std::vector<int> tips;        ///< body indices, one or more, each moved by <= 8 joints
    std::vector<double> squeeze;  ///< m, one per tip (negative: a gap)
    double seek_rate{0.005};      ///< rad/s, >= 0
    double seek_step{0.0};        ///< m, >= 0 (0: off)
    double seek_max{0.0015};      ///< m, >= 0
  };
  Hold hold;
  /// The state estimate the closed loop gives the controller (docs/mpc.md, session 39). With
  /// position_time_constant T > 0, RunClosedLoop passes every measurement through a
  /// PositionFilter with this T (a complementary filter: predicted with the measured velocity,
  /// corrected towards the measured positions at the rate 1 / T) and the re-plans and the PD+
  /// tracking use its estimate of q instead of the measured q; v stays the measured one. 0 (the
  /// default): the measurements as they are. A robot's loop uses PositionFilter the same way.
  struct Estimator {
    double position_time_constant{0.0};  ///< s, >= 0 (0: off)
  };
  Estimator estimator;
  /// Most joints that may move one hold tip (MpcOptions::Hold::tips).
  static constexpr int kMaxHoldTipDofs = 8;
  PdGains gains;  ///< nv each; zero gives pure feed-forward
  /// Actuated velocity indices for the PD+ controller (default: all but the problem's
  /// unactuated DoFs).
  std::vector<int> actuated;
  void Validate(const Model& model) const;
  /// The checks of `hold` (Validate calls it when the hold is on).
  void ValidateHold(const Model& model) const;
};

/// A plan: knots at times t_0 + k dt (k = 0..N) and C² splines through them.
struct Plan {
  double start_time{0.0};
  double time_step{0.0};
  std::vector<Eigen::VectorXd> q, v, tau;  ///< N + 1 knots each (tau_N = tau_{N-1})
  CubicSpline q_spline, v_spline, tau_spline;
  /// q_d, v_d, u_ff at time t (quaternions normalized). Outputs are resized.
  void Sample(const Model& model, double t, Eigen::VectorXd* q_d, Eigen::VectorXd* v_d,
              Eigen::VectorXd* u_ff) const;
};

/// The orientation `measured` turned towards `target` by at most `max_angle` (rad) about the
/// axis of the shortest rotation between them, composed on the left (in the frame both are
/// expressed in); `target` itself when it is within max_angle. (MpcOptions::orientation_leads.)
Eigen::Quaterniond LeadOrientation(const Eigen::Quaterniond& measured,
                                   const Eigen::Quaterniond& target, double max_angle);

/// The controller. Owns a TrajectoryOptimizer; not thread-safe itself.
class Controller {
 public:
  /// `problem` holds the horizon, weights and the nominal trajectory relative to its q_init
  /// (the controller's time 0). `solver` options are used as given except that every re-plan
  /// runs exactly options.iterations_per_step iterations.
  Controller(const Model& model, const ProblemDefinition& problem, const SolverOptions& solver,
             const MpcOptions& options);
  ~Controller();

  /// Plans from the initial state with `initial_iterations` (>= 0) iterations (a cold start) at
  /// t = 0; with 0 the first plan is q_guess itself (N + 1 configurations, nq each), evaluated.
  /// Throws InvalidArgument for a negative count.
  SolverSummary Initialize(const std::vector<Eigen::VectorXd>& q_guess, int initial_iterations);

  /// Re-plans at time t from the measured state (q_hat: nq, v_hat: nv). When the solve fails
  /// or produces a non-finite plan, the previous plan is kept and the summary says so
  /// (termination kFailure).
  SolverSummary Replan(double t, const Eigen::VectorXd& q_hat, const Eigen::VectorXd& v_hat);

  /// PD+ command at time t for the measured state, from the latest plan.
  void Control(double t, const Eigen::VectorXd& q_hat, const Eigen::VectorXd& v_hat,
               Eigen::VectorXd* u);

  const Plan& plan() const { return plan_; }
  const MpcOptions& options() const { return options_; }
  TrajectoryOptimizer& optimizer() { return *optimizer_; }
  /// The warm start of the last Replan (the previous plan resampled at the new knot times,
  /// first knot = the measured state), before the solver iterated on it.
  const std::vector<Eigen::VectorXd>& last_warm_start() const { return q_warm_; }
  /// Number of re-plans whose result was rejected (non-finite or failed) so far.
  int num_rejected_plans() const { return num_rejected_; }

 private:
  void Publish(double t, const Trajectory& solution);
  /// Hold law (MpcOptions::Hold): its scratch and per-tip joints (constructor).
  void SetUpHold();
  /// Hold law (MpcOptions::Hold): the orientation error from the measurement, whether to hold.
  bool UpdateHold(const Eigen::VectorXd& q_hat, const Eigen::VectorXd& v_hat);
  /// The grasp around hold_centre_ (inverse kinematics from q_init) into hold_traj_.
  void BuildHoldPlan(const Eigen::VectorXd& q_hat);
  /// Moves fingertip `f` of the hold towards `goal` (world) in *q, on its own joints.
  void PlaceTip(size_t f, const Eigen::Vector3d& goal, Eigen::VectorXd* q);

  Model model_;
  ProblemDefinition problem_;
  MpcOptions options_;
  std::unique_ptr<TrajectoryOptimizer> optimizer_;
  std::unique_ptr<PdController> pd_;
  Plan plan_;
  int num_rejected_{0};
  // Hold law state (MpcOptions::Hold), set up by the constructor when the hold is on.
  bool holding_{false};
  double hold_extra_{0.0};       // m: the contact seeking's added squeeze
  int hold_velocity_start_{-1};  // the held body's angular velocity (world), 3
  Eigen::Vector3d hold_centre_{Eigen::Vector3d::Zero()};  // world
  std::vector<Eigen::Vector3d> hold_tips0_;               // per tip: its position at q_init, world
  std::vector<std::vector<int>> hold_dofs_;               // per tip: velocity indices of its joints
  std::vector<int> q_index_of_v_;                         // actuated velocity i: its position index
  std::unique_ptr<Data> hold_data_;                       // kinematics scratch for the grasp
  Eigen::Matrix3Xd hold_J_;                               // 3 x nv point Jacobian scratch
  Trajectory hold_traj_;                                  // the published grasp: N + 1 copies
  // Scratch.
  std::vector<Eigen::VectorXd> q_shift_, q_warm_, q_nom_;
  std::vector<double> knot_times_;
  Eigen::VectorXd q_d_, v_d_, u_ff_;
  Trajectory solution_;
};

}  // namespace idto::mpc
