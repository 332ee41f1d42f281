// Rigid-body dynamics kernels, idto against MuJoCo in the same binary (when MuJoCo is found).
//
// Models (read from IDTO_SOURCE_DIR/models; a missing or broken file skips its benchmarks with
// the reason): "spinner" (3 DoF, fixed base: the smallest example, whose per-step derivative
// cost bounds its solver iteration), "arm7" (7 DoF, fixed base), "quadruped" (18 DoF, floating
// base), "allegro_ball" (the hand, fixed, plus a free ball: 22 DoF; one scene built with
// AddUrdfFile twice). Each model is evaluated at one random but fixed state (seeded).
//
// Benchmarks come in pairs "dynamics/<kernel>/<model>/idto" and ".../mujoco"; main.cpp prints
// the ratio idto/MuJoCo of every pair at the end of the run. Kernels and what each side does
// per call (both start from q, v, a only):
//  - FKpos:  idto ForwardKinematics(q) | mj_kinematics
//  - FK:     idto ForwardKinematics(q, v) | mj_kinematics + mj_comPos + mj_comVel
//            (MuJoCo computes body velocities only through mj_comPos/mj_comVel)
//  - RNEA:   idto InverseDynamics(q, v, a) | mj_kinematics + mj_comPos + mj_comVel +
//            mj_rne(flg_acc = 1) with qacc = a (MuJoCo's rne has no damping; idto adds D v)
//  - CRBA:   idto MassMatrix(q) (dense, symmetric) | mj_kinematics + mj_comPos + mj_crb +
//            mj_fullM (dense)
//  - RNEAderivs: idto ComputeRneaDerivatives(q, v, a): tau, d tau/dq (nv x nq), d tau/dv and M
//            in one pass (no MuJoCo counterpart; compare with RNEA of the same run)
//  - RNEAderivsTangent: idto ComputeRneaDerivativesTangent(q, v, a): the same with d tau/dq in
//            the tangent space only (nv x nv; what the solver uses, and what Pinocchio's
//            computeRNEADerivatives computes)
//  - RNEAderivsFD: the same outputs by forward differences of idto InverseDynamics (1 + nq + 2 nv
//            calls, step sqrt(eps)), the method the analytic derivatives replace
//  - Jacobians4: idto ForwardKinematics(q) + 4 x CalcPointJacobian | mj_kinematics +
//            mj_comPos + 4 x mj_jac (quadruped: the feet; arm: the last links; hand: the
//            fingertips)
// The MuJoCo models come from idto::MakeMjcf without geometry and sites (mj_kinematics would
// otherwise also place every geom and site, work idto's kinematics does not do).

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/idto.hpp"
#include "idto/parsers/urdf.hpp"
#include "idto/sim/mjcf.hpp"

#ifdef IDTO_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace {

using idto::BodyIndex;

constexpr int kNumJacobianPoints = 4;

std::string ModelPath(const std::string& file) {
  return std::string(IDTO_SOURCE_DIR) + "/models/" + file;
}

// A model with its fixed state and the points whose Jacobians are timed.
struct BenchModel {
  std::string error;  // why the model is unavailable (empty when it is)
  idto::Model model;
  Eigen::VectorXd q, v, a;
  std::vector<BodyIndex> bodies;        // kNumJacobianPoints bodies
  std::vector<Eigen::Vector3d> points;  // p_BC per body
};

idto::Model LoadModel(const std::string& name) {
  if (name == "arm7") return idto::ParseUrdfFile(ModelPath("arm7.urdf"));
  if (name == "spinner") return idto::ParseUrdfFile(ModelPath("spinner.urdf"));
  if (name == "quadruped") {
    idto::UrdfOptions options;
    options.base = idto::BaseType::kFloating;
    options.X_WB.translation() = Eigen::Vector3d(0.0, 0.0, 0.3);
    return idto::ParseUrdfFile(ModelPath("quadruped.urdf"), options);
  }
  if (name == "allegro_ball") {
    idto::ModelBuilder builder("allegro_ball");
    idto::AddUrdfFile(ModelPath("allegro_hand.urdf"), idto::UrdfOptions{}, &builder);
    idto::UrdfOptions ball;
    ball.base = idto::BaseType::kFloating;
    ball.prefix = "ball_";
    ball.X_WB.translation() = Eigen::Vector3d(0.05, 0.0, 0.1);
    idto::AddUrdfFile(ModelPath("ball.urdf"), ball, &builder);
    return builder.Build();
  }
  throw std::invalid_argument("unknown benchmark model " + name);
}

// The first kNumJacobianPoints leaf bodies (feet, fingertips) in index order, completed with
// the last bodies of the model when there are fewer leaves (a serial arm).
std::vector<BodyIndex> JacobianBodies(const idto::Model& model) {
  std::vector<bool> has_child(model.num_bodies(), false);
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) has_child[model.parent(b)] = true;
  std::vector<BodyIndex> bodies;
  for (BodyIndex b = 1; b < model.num_bodies() && bodies.size() < kNumJacobianPoints; ++b) {
    if (!has_child[b]) bodies.push_back(b);
  }
  for (BodyIndex b = model.num_bodies() - 1; b >= 1 && bodies.size() < kNumJacobianPoints; --b) {
    if (has_child[b]) bodies.push_back(b);
  }
  return bodies;
}

BenchModel MakeBenchModel(const std::string& name) {
  BenchModel out;
  try {
    out.model = LoadModel(name);
  } catch (const std::exception& e) {
    out.error = e.what();
    return out;
  }
  const idto::Model& model = out.model;
  std::mt19937 engine(20240601u);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  auto random_vector = [&](int n, double scale) {
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) x(i) = scale * uniform(engine);
    return x;
  };
  out.q = model.NeutralConfiguration() + random_vector(model.nq(), 0.5);
  for (const idto::JointIndex j : model.floating_joints()) {
    const int i = model.position_start(j);
    out.q.segment<4>(i).normalize();
  }
  out.v = random_vector(model.nv(), 1.0);
  out.a = random_vector(model.nv(), 1.0);
  out.bodies = JacobianBodies(model);
  for (std::size_t k = 0; k < out.bodies.size(); ++k) {
    out.points.push_back(Eigen::Vector3d(0.01, -0.02, 0.03) * static_cast<double>(k + 1));
  }
  return out;
}

// Models are loaded on first use (listing benchmarks reads no file) and kept for the run.
const BenchModel& GetBenchModel(const std::string& name) {
  static std::map<std::string, std::unique_ptr<BenchModel>> cache;
  auto& entry = cache[name];
  if (!entry) entry = std::make_unique<BenchModel>(MakeBenchModel(name));
  return *entry;
}

// ------------------------------------------------------------------------------------------------
// idto

void IdtoFkPositions(benchmark::State& state, const std::string& name) {
  const BenchModel& bm = GetBenchModel(name);
  if (!bm.error.empty()) return state.SkipWithError(bm.error.c_str());
  idto::Data data(bm.model);
  for (auto _ : state) {
    idto::ForwardKinematics(bm.model, bm.q, &data);
    benchmark::ClobberMemory();
  }
}

void IdtoFk(benchmark::State& state, const std::string& name) {
  const BenchModel& bm = GetBenchModel(name);
  if (!bm.error.empty()) return state.SkipWithError(bm.error.c_str());
  idto::Data data(bm.model);
  for (auto _ : state) {
    idto::ForwardKinematics(bm.model, bm.q, bm.v, &data);
    benchmark::ClobberMemory();
  }
}

void IdtoRnea(benchmark::State& state, const std::string& name) {
  const BenchModel& bm = GetBenchModel(name);
  if (!bm.error.empty()) return state.SkipWithError(bm.error.c_str());
  idto::Data data(bm.model);
  for (auto _ : state) {
    benchmark::DoNotOptimize(idto::InverseDynamics(bm.model, bm.q, bm.v, bm.a, &data).data());
    benchmark::ClobberMemory();
  }
}

void IdtoCrba(benchmark::State& state, const std::string& name) {
  const BenchModel& bm = GetBenchModel(name);
  if (!bm.error.empty()) return state.SkipWithError(bm.error.c_str());
  idto::Data data(bm.model);
  for (auto _ : state) {
    benchmark::DoNotOptimize(idto::MassMatrix(bm.model, bm.q, &data).data());
    benchmark::ClobberMemory();
  }
}

void IdtoRneaDerivatives(benchmark::State& state, const std::string& name) {
  const BenchModel& bm = GetBenchModel(name);
  if (!bm.error.empty()) return state.SkipWithError(bm.error.c_str());
  idto::Data data(bm.model);
  for (auto _ : state) {
    idto::ComputeRneaDerivatives(bm.model, bm.q, bm.v, bm.a, &data);
    benchmark::DoNotOptimize(data.dtau_dq.data());
    benchmark::ClobberMemory();
  }
}

void IdtoRneaDerivativesTangent(benchmark::State& state, const std::string& name) {
  const BenchModel& bm = GetBenchModel(name);
  if (!bm.error.empty()) return state.SkipWithError(bm.error.c_str());
  idto::Data data(bm.model);
  for (auto _ : state) {
    idto::ComputeRneaDerivativesTangent(bm.model, bm.q, bm.v, bm.a, nullptr, &data);
    benchmark::DoNotOptimize(data.dtau_dq_tangent.data());
    benchmark::ClobberMemory();
  }
}

void IdtoRneaDerivativesFd(benchmark::State& state, const std::string& name) {
  const BenchModel& bm = GetBenchModel(name);
  if (!bm.error.empty()) return state.SkipWithError(bm.error.c_str());
  const idto::Model& model = bm.model;
  idto::Data data(model);
  const int nq = model.nq(), nv = model.nv();
  Eigen::MatrixXd dtau_dq(nv, nq), dtau_dv(nv, nv), M(nv, nv);
  Eigen::VectorXd q = bm.q, v = bm.v, a = bm.a, tau0(nv);
  const double h = std::sqrt(std::numeric_limits<double>::epsilon());
  auto column = [&](double* x, Eigen::MatrixXd* J, int col) {
    const double x0 = *x;
    *x = x0 + h;
    const double step = *x - x0;  // the step actually applied
    J->col(col) = (idto::InverseDynamics(model, q, v, a, &data) - tau0) / step;
    *x = x0;
  };
  for (auto _ : state) {
    tau0 = idto::InverseDynamics(model, q, v, a, &data);
    for (int i = 0; i < nq; ++i) column(&q(i), &dtau_dq, i);
    for (int i = 0; i < nv; ++i) column(&v(i), &dtau_dv, i);
    for (int i = 0; i < nv; ++i) column(&a(i), &M, i);
    benchmark::DoNotOptimize(dtau_dq.data());
    benchmark::ClobberMemory();
  }
}

void IdtoJacobians(benchmark::State& state, const std::string& name) {
  const BenchModel& bm = GetBenchModel(name);
  if (!bm.error.empty()) return state.SkipWithError(bm.error.c_str());
  idto::Data data(bm.model);
  std::vector<Eigen::Matrix3Xd> J(bm.bodies.size(), Eigen::Matrix3Xd(3, bm.model.nv()));
  std::string label;
  for (const BodyIndex b : bm.bodies) label += (label.empty() ? "" : ",") + bm.model.body_name(b);
  state.SetLabel(label);
  for (auto _ : state) {
    idto::ForwardKinematics(bm.model, bm.q, &data);
    for (std::size_t k = 0; k < bm.bodies.size(); ++k) {
      idto::CalcPointJacobian(bm.model, data, bm.bodies[k], bm.points[k], &J[k]);
    }
    benchmark::ClobberMemory();
  }
}

// ------------------------------------------------------------------------------------------------
// MuJoCo

#ifdef IDTO_HAVE_MUJOCO

struct MujocoBench {
  std::string error;
  mjModel* m{nullptr};
  mjData* d{nullptr};
  std::vector<int> body_ids;          // MuJoCo bodies of the Jacobian points
  std::vector<Eigen::Vector3d> p_MC;  // the points in those bodies' frames
  std::vector<std::vector<mjtNum>> jacp;
  MujocoBench() = default;
  MujocoBench(const MujocoBench&) = delete;
  MujocoBench& operator=(const MujocoBench&) = delete;
  ~MujocoBench() {
    if (d != nullptr) mj_deleteData(d);
    if (m != nullptr) mj_deleteModel(m);
  }
};

mjModel* LoadMjcf(const std::string& xml, std::string* error) {
  auto vfs = std::make_unique<mjVFS>();  // ~2 MB: not on the stack
  mj_defaultVFS(vfs.get());
  const char* kName = "idto_bench.xml";
  mj_makeEmptyFileVFS(vfs.get(), kName, static_cast<int>(xml.size()));
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), kName)], xml.data(), xml.size());
  char message[1000] = "";
  mjModel* m = mj_loadXML(kName, vfs.get(), message, sizeof(message));
  mj_deleteVFS(vfs.get());
  if (m == nullptr) *error = std::string("mj_loadXML: ") + message;
  return m;
}

const MujocoBench& GetMujocoBench(const std::string& name) {
  static std::map<std::string, std::unique_ptr<MujocoBench>> cache;
  auto& entry = cache[name];
  if (entry) return *entry;
  entry = std::make_unique<MujocoBench>();
  MujocoBench& mb = *entry;
  const BenchModel& bm = GetBenchModel(name);
  if (!bm.error.empty()) {
    mb.error = bm.error;
    return mb;
  }
  idto::MjcfOptions options;
  options.include_geometry = false;
  options.include_sites = false;
  options.disable_contact = true;
  mb.m = LoadMjcf(idto::MakeMjcf(bm.model, options), &mb.error);
  if (mb.m == nullptr) return mb;
  mb.d = mj_makeData(mb.m);
  const idto::MujocoMap map(bm.model);
  map.IdtoToMujocoState(bm.q, bm.v, mb.d->qpos, mb.d->qvel);
  map.IdtoToMujocoVelocity(bm.q, bm.a, mb.d->qacc);
  for (std::size_t k = 0; k < bm.bodies.size(); ++k) {
    mb.body_ids.push_back(map.MujocoBodyId(bm.bodies[k]));
    mb.p_MC.push_back(map.X_MB(bm.bodies[k]) * bm.points[k]);
    mb.jacp.emplace_back(3 * static_cast<std::size_t>(mb.m->nv), 0.0);
  }
  return mb;
}

#define IDTO_GET_MUJOCO(mb, name)               \
  const MujocoBench& mb = GetMujocoBench(name); \
  if (!(mb).error.empty()) return state.SkipWithError((mb).error.c_str())

void MujocoFkPositions(benchmark::State& state, const std::string& name) {
  IDTO_GET_MUJOCO(mb, name);
  for (auto _ : state) {
    mj_kinematics(mb.m, mb.d);
    benchmark::ClobberMemory();
  }
}

void MujocoFk(benchmark::State& state, const std::string& name) {
  IDTO_GET_MUJOCO(mb, name);
  for (auto _ : state) {
    mj_kinematics(mb.m, mb.d);
    mj_comPos(mb.m, mb.d);
    mj_comVel(mb.m, mb.d);
    benchmark::ClobberMemory();
  }
}

void MujocoRnea(benchmark::State& state, const std::string& name) {
  IDTO_GET_MUJOCO(mb, name);
  std::vector<mjtNum> tau(static_cast<std::size_t>(mb.m->nv));
  for (auto _ : state) {
    mj_kinematics(mb.m, mb.d);
    mj_comPos(mb.m, mb.d);
    mj_comVel(mb.m, mb.d);
    mj_rne(mb.m, mb.d, 1, tau.data());
    benchmark::DoNotOptimize(tau.data());
    benchmark::ClobberMemory();
  }
}

void MujocoCrba(benchmark::State& state, const std::string& name) {
  IDTO_GET_MUJOCO(mb, name);
  std::vector<mjtNum> M(static_cast<std::size_t>(mb.m->nv) * static_cast<std::size_t>(mb.m->nv));
  for (auto _ : state) {
    mj_kinematics(mb.m, mb.d);
    mj_comPos(mb.m, mb.d);
    mj_crb(mb.m, mb.d);
    mj_fullM(mb.m, M.data(), mb.d->qM);
    benchmark::DoNotOptimize(M.data());
    benchmark::ClobberMemory();
  }
}

void MujocoJacobians(benchmark::State& state, const std::string& name) {
  IDTO_GET_MUJOCO(mb, name);
  std::vector<std::vector<mjtNum>> jacp = mb.jacp;
  for (auto _ : state) {
    mj_kinematics(mb.m, mb.d);
    mj_comPos(mb.m, mb.d);
    for (std::size_t k = 0; k < mb.body_ids.size(); ++k) {
      const int id = mb.body_ids[k];
      const Eigen::Map<const Eigen::Matrix<mjtNum, 3, 3, Eigen::RowMajor>> R_WM(mb.d->xmat +
                                                                                9 * id);
      const Eigen::Map<const Eigen::Vector3d> p_WM(mb.d->xpos + 3 * id);
      const Eigen::Vector3d p_WC = p_WM + R_WM * mb.p_MC[k];
      mj_jac(mb.m, mb.d, jacp[k].data(), nullptr, p_WC.data(), id);
    }
    benchmark::ClobberMemory();
  }
}

#endif  // IDTO_HAVE_MUJOCO

// ------------------------------------------------------------------------------------------------

using BenchFunction = void (*)(benchmark::State&, const std::string&);

struct Kernel {
  const char* name;
  BenchFunction idto;
  BenchFunction mujoco;
};

bool RegisterDynamicsBenchmarks() {
  const Kernel kernels[] = {
#ifdef IDTO_HAVE_MUJOCO
      {"FKpos", IdtoFkPositions, MujocoFkPositions},
      {"FK", IdtoFk, MujocoFk},
      {"RNEA", IdtoRnea, MujocoRnea},
      {"CRBA", IdtoCrba, MujocoCrba},
      {"Jacobians4", IdtoJacobians, MujocoJacobians},
      {"RNEAderivs", IdtoRneaDerivatives, nullptr},
      {"RNEAderivsTangent", IdtoRneaDerivativesTangent, nullptr},
      {"RNEAderivsFD", IdtoRneaDerivativesFd, nullptr},
#else
      {"FKpos", IdtoFkPositions, nullptr},
      {"FK", IdtoFk, nullptr},
      {"RNEA", IdtoRnea, nullptr},
      {"CRBA", IdtoCrba, nullptr},
      {"Jacobians4", IdtoJacobians, nullptr},
      {"RNEAderivs", IdtoRneaDerivatives, nullptr},
      {"RNEAderivsTangent", IdtoRneaDerivativesTangent, nullptr},
      {"RNEAderivsFD", IdtoRneaDerivativesFd, nullptr},
#endif
  };
  for (const char* model : {"spinner", "arm7", "quadruped", "allegro_ball"}) {
    for (const Kernel& kernel : kernels) {
      const std::string base = std::string("dynamics/") + kernel.name + "/" + model;
      const std::string model_name = model;
      const BenchFunction idto_fn = kernel.idto;
      benchmark::RegisterBenchmark(
          (base + "/idto").c_str(),
          [idto_fn, model_name](benchmark::State& state) { idto_fn(state, model_name); });
      if (kernel.mujoco != nullptr) {
        const BenchFunction mujoco_fn = kernel.mujoco;
        benchmark::RegisterBenchmark(
            (base + "/mujoco").c_str(),
            [mujoco_fn, model_name](benchmark::State& state) { mujoco_fn(state, model_name); });
      }
    }
  }
  return true;
}

[[maybe_unused]] const bool registered = RegisterDynamicsBenchmarks();

}  // namespace
