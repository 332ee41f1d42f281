#pragma once

/// @file
/// Plants for closed-loop simulation: what plays the real robot against the MPC controller.
/// The planner's contact model is smooth and soft; a plant's is stiff (built-in) or rigid
/// (MuJoCo), so closed-loop results show what the plan achieves on a more realistic model.

#include <memory>
#include <string>

#include <Eigen/Core>

#include "idto/contact/contact_engine.hpp"
#include "idto/multibody/model.hpp"

namespace idto::sim {

/// A simulated system with idto's state convention (q: nq, v: nv; design.md §3).
///
/// A plant starts at the model's neutral configuration, at rest, at time 0. After construction
/// Reset and Advance allocate nothing. Not thread-safe: one plant per thread.
class Plant {
 public:
  virtual ~Plant() = default;
  /// Sets the state (quaternions are normalized) and the clock to 0. Throws InvalidArgument on
  /// wrong sizes or non-finite entries.
  virtual void Reset(const Eigen::VectorXd& q, const Eigen::VectorXd& v) = 0;
  /// Advances by `duration` seconds (>= 0) in the plant's own whole time steps with generalized
  /// forces u (nv) held constant and an external force `f_ext_W` (world frame, N) applied at the
  /// origin of body `disturbed_body` (use -1 for none; 0, the world, is ignored) for this call
  /// only. The number of steps is chosen so that time() stays within half a step of the sum of
  /// the durations requested since Reset (e.g. a 1/60 s period on 1 ms steps takes 17, 17, 16,
  /// ... steps). Throws InvalidArgument on bad arguments and std::runtime_error when the
  /// simulation becomes unstable (the message names the time).
  virtual void Advance(double duration, const Eigen::VectorXd& u, int disturbed_body = -1,
                       const Eigen::Vector3d& f_ext_W = Eigen::Vector3d::Zero()) = 0;
  /// Extra viscous damping d (nv, >= 0; only on DoFs of 1-DoF joints) added to the model's
  /// joint damping and integrated implicitly: each step applies -d .* v at the step's end
  /// velocity. The closed loop puts a PD controller's -Kd v here, which stays stable at 1 ms
  /// even on light links where the explicit term would diverge (Kd h / I > 2). Throws
  /// InvalidArgument on a wrong size, a negative or non-finite entry, or a non-zero entry on a
  /// multi-DoF joint.
  virtual void SetExtraDamping(const Eigen::VectorXd& d) = 0;
  /// Current configuration (nq) and velocity (nv).
  virtual const Eigen::VectorXd& q() const = 0;
  virtual const Eigen::VectorXd& v() const = 0;
  /// Simulated time since Reset, s (a whole number of time steps).
  virtual double time() const = 0;
  /// Sum of the contact force magnitudes on each body in the last step (num_bodies; N; entry 0
  /// is the world), for contact timing plots. Each contact adds |f| to both of its bodies.
  virtual const Eigen::VectorXd& contact_force_per_body() const = 0;
  /// "builtin" or "mujoco".
  virtual std::string name() const = 0;
};

/// The built-in plant's options.
struct BuiltinPlantOptions {
  double time_step{1e-3};  ///< s
  /// A stiff, barely smoothed contact law (not the planner's).
  ContactParameters contact{2e4, 1e-4, 0.1, 1.0, 1e-3};
  /// Pair selection: the scene's filters (the parameters above replace the law's).
  ContactOptions pairs;
  /// Contact forces and joint damping at the new velocity (see MakeBuiltinPlant); false: every
  /// force at the old velocity (plain semi-implicit Euler, unstable at the defaults for light
  /// links such as the quadruped's shanks).
  bool implicit_contact{true};
};

/// Semi-implicit Euler on idto's own dynamics (CRBA + Cholesky) with a stiff compliant contact
/// law: for machines without MuJoCo and for tests.
///
/// Contact pairs are those of ContactEngine(model, options.pairs) with options.contact as the
/// law; of options.pairs.overrides only friction coefficients are kept (stiffness, smoothing,
/// dissipation and stiction velocities are the planner's modelling choices, friction is the
/// surfaces'). Each step of size h from (q, v), with the contact geometry (phi, normal, contact
/// point, Jacobian J_c of the relative contact velocity) evaluated once at q:
///  - implicit_contact (default): the new velocity v+ solves
///      (M + h D)(v+ - v) = h (u + tau_disturbance - bias(q, v)) + h sum_c J_c^T f_c(J_c v+)
///    with the law's normal force at the distance predicted for the end of the step,
///    f_n = c(phi + h v_n) d(v_n), and friction -mu f_n0 v_t / sqrt(v_s^2 + |v_t|^2) bounded by
///    the normal force f_n0 at the start of the step. f_n is non-increasing in v_n and friction
///    is the gradient of a convex function, so v+ is the unique minimizer of a convex function:
///    Newton's method with a line search, warm-started at v (about 2.5 iterations per
///    step on the standing quadruped; 18 us per step against MuJoCo's 16 us on this machine).
///    At rest the contact holds exactly the law's equilibrium (c(phi) = weight).
///  - implicit_contact = false: a = ForwardDynamics(q, v, u + J^T F_ext(q, v)), v+ = v + h a.
///  - then q+ = Integrate(q, v+, h) (quaternions stay normalized).
///
/// Stability at h = 1 ms with the default law (k = 2e4 N/m, sigma = 0.1 mm, v_d = 0.1 m/s,
/// v_s = 1 mm/s): a 1 kg ball dropped from 0.5 m settles at the law's equilibrium in both
/// modes. The quadruped's feet have an apparent mass of 9 g (light shanks): explicitly, its
/// contact damping (c / v_d) and stiction (mu f_n / v_s) give h b / m of 10 and more (stable
/// needs < 2) and the simulation diverges within 40 ms of touchdown; implicitly it stands. Even
/// for the ball, explicit stiction (h mu g / v_s = 10) chatters: a rolling ball reports 40%
/// more contact force than its weight. So the law's defaults are kept and the implicit scheme
/// is the default.
///
/// Throws InvalidArgument on a non-positive time step, invalid contact parameters or unknown
/// names in options.pairs.
std::unique_ptr<Plant> MakeBuiltinPlant(const Model& model, const BuiltinPlantOptions& options);

/// The MuJoCo plant's options.
struct MujocoPlantOptions {
  double time_step{1e-3};  ///< s
  /// Sliding friction of every pair (unless a per-pair override in `pairs` sets one).
  double friction_coefficient{1.0};
  /// Torsional friction of every pair, m (>= 0): the largest torque about the contact normal is
  /// this length times the normal force (MuJoCo's condim 4). 0 (default): none.
  double torsional_friction{0.0};
  /// Rolling friction of every pair, m (>= 0): the largest torque about a tangent axis is this
  /// length times the normal force (MuJoCo's condim 6, with torsional_friction about the
  /// normal). 0 (default): none. A point contact resists no spin or roll; torsional and rolling
  /// friction stand in for the torque of a contact patch (e.g. a soft ball on a palm).
  double rolling_friction{0.0};
  /// MuJoCo's friction cone: "elliptic" (default: Coulomb's cone; MuJoCo's documentation calls
  /// it the better model of physical reality) or "pyramidal" (MuJoCo's own default, its linear
  /// approximation; the plant before session 28). docs/mpc.md, session 28, measures both.
  std::string friction_cone{"elliptic"};
  /// Pair selection as in the planner: every pair a ContactEngine(model, pairs) evaluates
  /// becomes an explicit MuJoCo `<pair>`, and no other pair collides (MakeMujocoPlantMjcf).
  /// The law's other parameters are not used: MuJoCo's contact is its own.
  ContactOptions pairs;
};

/// The MJCF text MakeMujocoPlant loads: MakeMjcf(model) with geometry, contact, the time step,
/// Euler integration, and one explicit `<pair>` per pair that a ContactEngine(model,
/// options.pairs) evaluates (every other collision disabled through contype = conaffinity = 0),
/// so the scene's filters hold exactly. Friction: options.friction_coefficient, or a per-pair
/// override's friction_coefficient from options.pairs, in options.friction_cone; torsional and
/// rolling friction: options.torsional_friction and options.rolling_friction on every pair
/// (condim 3 when both are 0, 4 with torsional friction only, 6 with rolling friction;
/// MjcfContactPair). Throws InvalidArgument on a non-positive time step, a negative or
/// non-finite coefficient, or a friction_cone other than "elliptic" or "pyramidal". Needs no
/// MuJoCo (for inspection and tests).
std::string MakeMujocoPlantMjcf(const Model& model, const MujocoPlantOptions& options);

/// True when idto was built with MuJoCo.
bool HaveMujoco();

/// MuJoCo (rigid contact, MuJoCo's default soft-constraint parameters, options.friction_cone
/// friction cones, Euler integration with implicit joint damping) loaded from
/// MakeMujocoPlantMjcf(model, options) through MuJoCo's virtual file system and stepped at
/// time_step; states mapped between conventions with MujocoMap, u applied as qfrc_applied = T(q) u
/// (so that the generalized force in idto's coordinates is u; idto/sim/mjcf.hpp), the disturbance
/// as xfrc_applied on the MuJoCo body carrying `disturbed_body`, moved from the body origin to that
/// body's centre of mass. contact_force_per_body sums |f| of mj_contactForce over the contacts of
/// the last step. Throws std::runtime_error when idto was built without MuJoCo, when MuJoCo rejects
/// the model, and from Advance when MuJoCo reports bad qpos/qvel/qacc (after which MuJoCo has reset
/// its state).
std::unique_ptr<Plant> MakeMujocoPlant(const Model& model, const MujocoPlantOptions& options);

}  // namespace idto::sim
