// The MuJoCo plant: the idto model exported by MakeMujocoPlantMjcf, loaded through MuJoCo's
// virtual file system and stepped with mj_step1 / mj_step2 (Euler), states and forces mapped
// with MujocoMap (idto/sim/mjcf.hpp). Compiled only when MuJoCo was found (IDTO_HAVE_MUJOCO);
// src/sim/plant.cpp has the stand-in of a build without it.

#ifdef IDTO_HAVE_MUJOCO

#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>
#include <Eigen/Core>

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/sim/mjcf.hpp"
#include "idto/sim/plant.hpp"
#include "plant_internal.hpp"

namespace idto::sim {
namespace {

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
struct MjVfsDeleter {
  void operator()(mjVFS* vfs) const {
    mj_deleteVFS(vfs);
    delete vfs;
  }
};

// Compiles MJCF text through the virtual file system (no temporary file).
std::unique_ptr<mjModel, MjModelDeleter> LoadMjcf(const std::string& xml) {
  std::unique_ptr<mjVFS, MjVfsDeleter> vfs(new mjVFS);  // large: keep it off the stack
  mj_defaultVFS(vfs.get());
  static constexpr const char* kFile = "idto_plant.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), kFile, static_cast<int>(xml.size())) != 0) {
    throw std::runtime_error("MakeMujocoPlant: cannot create a file in MuJoCo's VFS");
  }
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), kFile)], xml.data(), xml.size());
  char error[1024] = "";
  mjModel* m = mj_loadXML(kFile, vfs.get(), error, sizeof(error));
  if (m == nullptr) {
    throw std::runtime_error(std::string("MakeMujocoPlant: MuJoCo rejected the generated MJCF: ") +
                             error);
  }
  return std::unique_ptr<mjModel, MjModelDeleter>(m);
}

// Sum of MuJoCo's instability warnings (bad qpos / qvel / qacc), after which MuJoCo resets the
// data.
int InstabilityWarnings(const mjData* d) {
  return d->warning[mjWARN_BADQPOS].number + d->warning[mjWARN_BADQVEL].number +
         d->warning[mjWARN_BADQACC].number;
}

class MujocoPlant final : public Plant {
 public:
  MujocoPlant(const Model& model, const MujocoPlantOptions& options)
      : model_(model),
        options_(options),
        map_(model_),
        m_(LoadMjcf(MakeMujocoPlantMjcf(model_, options_))),
        d_(mj_makeData(m_.get())),
        clock_(options_.time_step) {
    if (d_ == nullptr) throw std::runtime_error("MakeMujocoPlant: mj_makeData failed");
    if (m_->nq != model_.nq() || m_->nv != model_.nv() || m_->nbody != map_.num_mujoco_bodies()) {
      throw std::runtime_error("MakeMujocoPlant: the MuJoCo model's sizes (nq " +
                               std::to_string(m_->nq) + ", nv " + std::to_string(m_->nv) +
                               ") differ from the idto model's (nq " + std::to_string(model_.nq()) +
                               ", nv " + std::to_string(model_.nv()) + ")");
    }
    // MuJoCo geom id -> idto body carrying the geometry (by name; the world for others).
    geom_body_.assign(m_->ngeom, kWorldBody);
    for (const GeometryInstance& g : model_.geometries()) {
      const int id = mj_name2id(m_.get(), mjOBJ_GEOM, g.name.c_str());
      if (id >= 0) geom_body_[id] = g.body;
    }
    extra_damping_.assign(m_->nv, 0.0);
    extra_damping_dof_.assign(model_.nv(), -1);
    u_ = Eigen::VectorXd::Zero(model_.nv());
    contact_force_per_body_ = Eigen::VectorXd::Zero(model_.num_bodies());
    Reset(model_.NeutralConfiguration(), Eigen::VectorXd::Zero(model_.nv()));
  }

  void Reset(const Eigen::VectorXd& q, const Eigen::VectorXd& v) override {
    internal::CheckResetState("MujocoPlant::Reset", model_, q, v, &q_);
    mj_resetData(m_.get(), d_.get());
    map_.IdtoToMujocoState(q_, v, d_->qpos, d_->qvel);
    map_.MujocoToIdtoState(d_->qpos, d_->qvel, &q_, &v_);
    clock_.Reset();
    contact_force_per_body_.setZero();
  }

  void SetExtraDamping(const Eigen::VectorXd& d) override {
    static constexpr const char* kWhere = "MujocoPlant::SetExtraDamping";
    internal::CheckExtraDamping(kWhere, model_, d);
    // Implicit damping as added inertia: with h d added to the DoF's diagonal of M (Advance) and
    // the damping force -d v applied explicitly, Euler's (M + h d)(v+ - v) = h (f - d v) is
    // exactly M (v+ - v) = h (f - d v+). Unlike MuJoCo's own implicit dof_damping, which its
    // Euler step applies only after the constraint solver has computed the contact forces with
    // M alone, the contact forces are then computed with the mass the step really uses: with a
    // stiff ankle damper (h d / I = 12 on the hopper's 0.1 kg foot) the former made the foot
    // chatter on the ground. A 1-DoF joint's velocity maps to one MuJoCo DoF (T(q) e_i has one
    // non-zero, +1 or -1, there).
    Eigen::VectorXd e = Eigen::VectorXd::Zero(model_.nv());
    std::vector<double> column(model_.nv());
    for (int i = 0; i < model_.nv(); ++i) {
      if (d(i) == 0.0 && extra_damping_dof_[i] < 0) continue;
      e.setZero();
      e(i) = 1.0;
      map_.IdtoToMujocoForce(q_, e, column.data());
      int dof = -1;
      for (int k = 0; k < model_.nv(); ++k) {
        if (column[k] != 0.0) dof = k;
      }
      if (dof < 0) continue;
      extra_damping_[dof] = d(i);
      extra_damping_dof_[i] = dof;
    }
    has_extra_damping_ = false;
    for (double x : extra_damping_) has_extra_damping_ = has_extra_damping_ || x != 0.0;
  }

  void Advance(double duration, const Eigen::VectorXd& u, int disturbed_body,
               const Eigen::Vector3d& f_ext_W) override {
    static constexpr const char* kWhere = "MujocoPlant::Advance";
    internal::CheckAdvanceArguments(kWhere, model_, u, disturbed_body, f_ext_W);
    const long steps = clock_.Advance(kWhere, duration);
    u_ = u;
    mjModel* m = m_.get();
    mjData* d = d_.get();
    const int mj_body = disturbed_body > 0 ? map_.MujocoBodyId(disturbed_body) : 0;
    mju_zero(d->xfrc_applied, 6 * m->nbody);
    for (long i = 0; i < steps; ++i) {
      const int warnings = InstabilityWarnings(d);
      mj_step1(m, d);  // kinematics and collision at the current state
      if (has_extra_damping_) {
        // M + h d (SetExtraDamping), then the constraint projection J (M + h d)^-1 J^T again.
        // (Runtime changes of dof_armature do not reach qM in MuJoCo 2.2.)
        for (int k = 0; k < m->nv; ++k) {
          d->qM[m->dof_Madr[k]] += options_.time_step * extra_damping_[k];
        }
        mj_factorM(m, d);
        mj_projectConstraint(m, d);
      }
      map_.IdtoToMujocoForce(q_, u_, d->qfrc_applied);
      for (int k = 0; k < m->nv; ++k) d->qfrc_applied[k] -= extra_damping_[k] * d->qvel[k];
      if (mj_body > 0) {
        // xfrc_applied = [force; torque] at the body's centre of mass (xipos): move the force
        // from the idto body's origin.
        const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R_WM(d->xmat +
                                                                                  9 * mj_body);
        const Eigen::Map<const Eigen::Vector3d> p_WM(d->xpos + 3 * mj_body);
        const Eigen::Map<const Eigen::Vector3d> p_WMcm(d->xipos + 3 * mj_body);
        const Eigen::Vector3d p_WBo = p_WM + R_WM * map_.X_MB(disturbed_body).translation();
        Eigen::Map<Eigen::Matrix<double, 6, 1>> F(d->xfrc_applied + 6 * mj_body);
        F.head<3>() = f_ext_W;
        F.tail<3>() = (p_WBo - p_WMcm).cross(f_ext_W);
      }
      mj_step2(m, d);  // forces, constraints, Euler integration
      if (InstabilityWarnings(d) != warnings) {
        throw std::runtime_error(
            "MujocoPlant::Advance: MuJoCo reported an unstable simulation (bad qpos, qvel or "
            "qacc) at t = " +
            FormatValue(clock_.time()) + " s with time_step = " + FormatValue(options_.time_step) +
            " s and reset its state");
      }
      map_.MujocoToIdtoState(d->qpos, d->qvel, &q_, &v_);
      clock_.CountStep();
    }
    if (steps > 0) AccumulateContactForces();
  }

  const Eigen::VectorXd& q() const override { return q_; }
  const Eigen::VectorXd& v() const override { return v_; }
  double time() const override { return clock_.time(); }
  const Eigen::VectorXd& contact_force_per_body() const override { return contact_force_per_body_; }
  std::string name() const override { return "mujoco"; }

 private:
  // |f| of every contact of the last step, summed on the idto bodies of its two geoms.
  void AccumulateContactForces() {
    contact_force_per_body_.setZero();
    const mjData* d = d_.get();
    for (int i = 0; i < d->ncon; ++i) {
      const mjContact& contact = d->contact[i];
      if (contact.efc_address < 0) continue;
      mjtNum result[6];
      mj_contactForce(m_.get(), d, i, result);
      const double f = Eigen::Map<const Eigen::Vector3d>(result).norm();
      contact_force_per_body_(geom_body_[contact.geom1]) += f;
      contact_force_per_body_(geom_body_[contact.geom2]) += f;
    }
  }

  Model model_;
  MujocoPlantOptions options_;
  MujocoMap map_;
  std::unique_ptr<mjModel, MjModelDeleter> m_;
  std::unique_ptr<mjData, MjDataDeleter> d_;
  internal::StepClock clock_;
  std::vector<double> extra_damping_;  // per MuJoCo DoF (SetExtraDamping)
  bool has_extra_damping_{false};
  std::vector<int> extra_damping_dof_;  // MuJoCo DoF of each idto DoF given extra damping
  std::vector<BodyIndex> geom_body_;
  Eigen::VectorXd q_, v_, u_;
  Eigen::VectorXd contact_force_per_body_;
};

}  // namespace

std::unique_ptr<Plant> MakeMujocoPlant(const Model& model, const MujocoPlantOptions& options) {
  return std::make_unique<MujocoPlant>(model, options);
}

}  // namespace idto::sim

#endif  // IDTO_HAVE_MUJOCO
