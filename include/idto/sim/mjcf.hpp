#pragma once

/// @file
/// MuJoCo interoperability without MuJoCo: MJCF text for an idto Model, and the maps between
/// idto's generalized coordinates and those of the MuJoCo model that text describes.
///
/// Nothing here includes or links MuJoCo; a program that has MuJoCo loads the text with
/// `mj_loadXML` (from a file or the virtual file system) and uses MujocoMap to move states,
/// accelerations, forces, mass matrices and Jacobians between the two conventions.
///
/// **The MuJoCo model.** Every moving body (joint type != kFixed) becomes a `<body>` named like
/// the idto body, nested under the MuJoCo body of its moving ancestor (bodies welded by fixed
/// joints are merged into their moving ancestor, as idto does for dynamics; bodies welded to the
/// world go into `<worldbody>`). The MuJoCo body frame is the idto body frame B (= the joint
/// frame J at q = 0), placed at X_MJ relative to its MuJoCo parent. `<inertial>` holds the
/// merged mass, centre of mass and rotational inertia (welded descendants included). Joints:
///  - revolute / continuous -> `hinge` about the joint axis; prismatic -> `slide`;
///  - planar -> `slide` (e1), `slide` (e2), `hinge` (normal), named `<joint>_x`, `_y`, `_theta`;
///  - floating on a body whose moving ancestor is the world -> `free`; floating below a moving
///    body (MuJoCo allows free joints only at the top level) -> three `slide`s along J's axes
///    (`<joint>_x`, `_y`, `_z`) followed by a `ball` (`<joint>_ball`);
///  - damping of every MuJoCo joint = the idto joint's damping (per velocity coordinate).
/// MuJoCo adds no armature, friction loss, stiffness or springs, so with contact (and limits)
/// disabled `mj_inverse` returns M qacc + bias + D qvel, which is idto's InverseDynamics in
/// MuJoCo coordinates.
///
/// **Coordinates.** MuJoCo orders joints depth-first through its body tree; idto orders them by
/// body index. The two orders agree for parsed models (depth-first) and may differ for models
/// built in code; MujocoMap handles the permutation. Both have nq and nv equal. Per joint:
///  - 1-DoF joints and planar joints: identical coordinates (q_mj = q, v_mj = v).
///  - floating joint, idto: q = [qw qx qy qz x y z] (pose of B in J), v = [w_J; v_J] (angular
///    velocity and velocity of the body origin Bo, both expressed in J);
///    MuJoCo free joint: qpos = [p_WB; quat_WB] (world pose, J is folded in through X_WJ),
///    qvel = [v_WBo expressed in W; w expressed in B];
///    MuJoCo slides + ball: qpos = [p_JB; quat_JB], qvel = [v_J; w expressed in B].
///
/// **Velocity map.** v_mj = T(q) v with T(q) (nv x nv) a signed permutation with 3x3 rotation
/// blocks (per floating joint: v_mj_lin = R_WJ v_J (free) or v_J (slides), w_mj = R_JB^T w_J),
/// so T is orthogonal: v = T^T v_mj. Consequences used to compare dynamics quantities:
///  - accelerations map with the same T: a_mj = T a, because dT/dt v = 0 (the only
///    time-varying block is R_JB^T acting on w_J, and d/dt(R_JB^T) w_J = -R_JB^T [w_J]x w_J = 0);
///  - generalized forces map by power balance, tau^T v = tau_mj^T v_mj: tau = T^T tau_mj
///    (so idto's InverseDynamics(q, v, a) = T^T qfrc_inverse for qacc = T a);
///  - mass matrix: M = T^T M_mj T; Jacobians: J = J_mj T (J_mj from mj_jac, world-aligned);
///  - a joint's damping is the same scalar on every DoF, so D = T^T D_mj T (T orthogonal).

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/core/types.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// An explicit MuJoCo contact pair in `<contact>`. MuJoCo collides explicit pairs whatever the
/// geoms' contype/conaffinity. With no torsional and no rolling friction (the default) it is
/// `<pair geom1=... geom2=... condim="3" friction="mu mu 0.005 0.0001 0.0001"/>` (sliding
/// friction only; the last three numbers are MuJoCo's defaults and unused at condim 3). With
/// torsional friction only it is condim 4 (`friction="mu mu torsional 0.0001 0.0001"`), with
/// rolling friction condim 6 (`friction="mu mu torsional rolling rolling"`). MuJoCo's torsional
/// and rolling coefficients are lengths (m): the largest torque about the contact normal,
/// respectively about the two tangent axes, is that length times the normal force.
struct MjcfContactPair {
  GeometryIndex geometry_a{0};  ///< index into Model::geometries()
  GeometryIndex geometry_b{0};
  double friction_coefficient{1.0};  ///< sliding friction (>= 0)
  double torsional_friction{0.0};    ///< m (>= 0); > 0 selects condim 4 (or 6)
  double rolling_friction{0.0};      ///< m (>= 0); > 0 selects condim 6
  /// MuJoCo's condim for these coefficients: 3, 4 or 6.
  int condim() const {
    if (rolling_friction > 0.0) return 6;
    return torsional_friction > 0.0 ? 4 : 3;
  }
};

/// Options of MakeMjcf. The defaults describe the same dynamics as idto (no contact solver
/// quirks added): geometry included, contacts enabled, no limits and no actuators.
struct MjcfOptions {
  /// Emit the model's collision geometry as `<geom>`s (sphere, capsule, cylinder, box; a
  /// HalfSpace becomes a `plane`, allowed only on the world or bodies welded to it).
  bool include_geometry{true};
  /// contype / conaffinity of every generated geom.
  int contype{1};
  int conaffinity{1};
  /// Emit `<site>`s for bodies welded by fixed joints and for frames added to bodies (named like
  /// the body or frame), so that they can be looked up with mj_name2id(mjOBJ_SITE, ...).
  bool include_sites{true};
  /// Integration time step, s (> 0).
  double timestep{0.001};
  /// MuJoCo integrator: "Euler", "RK4" or "implicit".
  std::string integrator{"Euler"};
  /// MuJoCo's friction cone (`<option cone>`): "pyramidal" (MuJoCo's default) or "elliptic"
  /// (MuJoCo's documentation: the better model of physical reality; docs/mpc.md, session 28).
  std::string cone{"pyramidal"};
  /// Adds `<flag contact="disable"/>` to `<option>`.
  bool disable_contact{false};
  /// Emits `range` and `limited="true"` for 1-DoF joints with finite position limits (MuJoCo then
  /// adds limit constraint forces, also in mj_inverse; off by default).
  bool include_joint_limits{false};
  /// Adds a `<motor>` (gear 1, named like the joint) for every revolute, continuous and
  /// prismatic joint, with ctrlrange = +-effort limit where finite.
  bool include_actuators{false};
  /// Give MuJoCo each body's inertia already diagonalized (`quat` + `diaginertia`, computed by
  /// Eigen's self-adjoint eigensolver, exact to round-off) instead of `fullinertia`. MuJoCo
  /// diagonalizes a `fullinertia` itself by an iterative method whose accuracy limits agreement
  /// with idto to ~1e-9 relative (up to 2e-8 measured on random full inertias); with this flag
  /// (the default) the two agree to round-off (~1e-15). Inertias that are diagonal already are
  /// always written as `diaginertia`.
  bool diagonalize_inertia{true};
  /// `model` attribute of `<mujoco>`; empty: the Model's name.
  std::string model_name;
  /// Explicit contact pairs (needs include_geometry). To collide exactly these pairs and no
  /// others, set contype = conaffinity = 0. Empty by default.
  std::vector<MjcfContactPair> contact_pairs;

  /// True when the options are usable; otherwise writes the reason to `why` (if not null).
  bool IsValid(std::string* why = nullptr) const;
};

/// MJCF text (MuJoCo 2.2 XML) describing `model`: bodies, inertias, joints, damping, gravity,
/// and optionally geometry, sites, limits and motors (see the file comment for the mapping).
/// Uses `<compiler angle="radian" inertiafromgeom="false"/>`; numbers are written with 17
/// significant digits so that the MuJoCo model carries exactly idto's values.
/// Throws InvalidArgument on invalid options or a HalfSpace attached to a moving body.
std::string MakeMjcf(const Model& model, const MjcfOptions& options = {});

/// The correspondence between an idto Model and the MuJoCo model of MakeMjcf(model): body
/// names and ids, and the coordinate maps of the file comment. Construct once per model; the
/// maps do not allocate (except where an Eigen output is resized).
class MujocoMap {
 public:
  explicit MujocoMap(const Model& model);

  /// MuJoCo's nq and nv (equal to the idto model's).
  int nq() const { return nq_; }
  int nv() const { return nv_; }
  /// Number of MuJoCo bodies, world included (= idto moving bodies + 1).
  int num_mujoco_bodies() const { return static_cast<int>(mj_body_to_idto_.size()); }

  /// MuJoCo body id of idto body b: the id of the body carrying b (its moving ancestor; 0 for
  /// bodies welded to the world). Ids follow the depth-first order of the generated MJCF.
  int MujocoBodyId(BodyIndex b) const { return mj_body_id_[b]; }
  /// idto body index of MuJoCo body `id` (0 for the world).
  BodyIndex IdtoBodyOfMujocoBody(int id) const { return mj_body_to_idto_[id]; }
  /// Pose of idto body b in the frame of its MuJoCo body (identity for moving bodies).
  const Eigen::Isometry3d& X_MB(BodyIndex b) const { return X_MB_[b]; }

  /// First MuJoCo qpos / qvel index of idto joint j (a moving body).
  int mujoco_qpos_start(JointIndex j) const { return mj_q_start_[j]; }
  int mujoco_dof_start(JointIndex j) const { return mj_v_start_[j]; }

  /// q (nq), v (nv) -> MuJoCo qpos (nq), qvel (nv). Quaternions are written as given (normalize
  /// q first if MuJoCo should see unit quaternions).
  void IdtoToMujocoState(const Eigen::Ref<const Eigen::VectorXd>& q,
                         const Eigen::Ref<const Eigen::VectorXd>& v, double* mj_qpos,
                         double* mj_qvel) const;
  /// MuJoCo qpos (nq), qvel (nv) -> q (nq), v (nv) (resized).
  void MujocoToIdtoState(const double* mj_qpos, const double* mj_qvel, Eigen::VectorXd* q,
                         Eigen::VectorXd* v) const;
  /// q (nq) only -> qpos (nq), and back.
  void IdtoToMujocoPositions(const Eigen::Ref<const Eigen::VectorXd>& q, double* mj_qpos) const;
  void MujocoToIdtoPositions(const double* mj_qpos, Eigen::VectorXd* q) const;

  /// x_mj = T(q) x for a velocity or acceleration x (nv) -> x_mj (nv).
  void IdtoToMujocoVelocity(const Eigen::Ref<const Eigen::VectorXd>& q,
                            const Eigen::Ref<const Eigen::VectorXd>& x, double* x_mj) const;
  /// x = T(q)^T x_mj for a velocity or acceleration (nv, resized). q is idto's configuration.
  void MujocoToIdtoVelocity(const Eigen::Ref<const Eigen::VectorXd>& q, const double* x_mj,
                            Eigen::VectorXd* x) const;
  /// tau = T(q)^T tau_mj for a generalized force (e.g. qfrc_inverse; nv, resized).
  void MujocoToIdtoForce(const Eigen::Ref<const Eigen::VectorXd>& q, const double* tau_mj,
                         Eigen::VectorXd* tau) const;
  /// tau_mj = T(q) tau (nv), e.g. for qfrc_applied.
  void IdtoToMujocoForce(const Eigen::Ref<const Eigen::VectorXd>& q,
                         const Eigen::Ref<const Eigen::VectorXd>& tau, double* tau_mj) const;
  /// T(q) (nv x nv, resized) with v_mj = T v.
  void VelocityMap(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::MatrixXd* T) const;

 private:
  // Per joint (index = idto body index; entry 0 unused).
  enum class Kind { kNone, kScalar, kPlanar, kFree, kNestedFloating };
  void CheckSizes(const char* where, const Eigen::Ref<const Eigen::VectorXd>& q) const;
  // R_JB^T for the floating joint of body b at configuration q.
  Eigen::Matrix3d R_BJ(int b, const Eigen::Ref<const Eigen::VectorXd>& q) const;

  int nq_{0};
  int nv_{0};
  std::vector<BodyIndex> joints_;  // moving bodies in idto order
  std::vector<Kind> kind_;
  std::vector<int> q_start_;
  std::vector<int> v_start_;
  std::vector<int> mj_q_start_;
  std::vector<int> mj_v_start_;
  std::vector<Eigen::Isometry3d> X_WJ_;  // free joints: pose of J in the world
  std::vector<Eigen::Isometry3d> X_MB_;
  std::vector<int> mj_body_id_;
  std::vector<BodyIndex> mj_body_to_idto_;
};

/// Convenience forms of MujocoMap (each builds a MujocoMap, which allocates; keep a MujocoMap
/// in loops). q (nq), v (nv) <-> qpos (nq), qvel (nv).
void IdtoToMujocoState(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                       const Eigen::Ref<const Eigen::VectorXd>& v, double* mj_qpos,
                       double* mj_qvel);
void MujocoToIdtoState(const Model& model, const double* mj_qpos, const double* mj_qvel,
                       Eigen::VectorXd* q, Eigen::VectorXd* v);
/// T(q) (nv x nv) with v_mj = T v, a_mj = T a, tau = T^T tau_mj, M = T^T M_mj T, J = J_mj T.
void IdtoToMujocoVelocityMap(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                             Eigen::MatrixXd* T);

}  // namespace idto
