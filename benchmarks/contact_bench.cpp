// Contact evaluation on a model: the quadruped standing on the ground, the same with 100 extra
// geometries that never touch anything (filtered out, or far away and pruned), and the pruning
// trade: time per evaluation vs the largest force error against no pruning.
//
// Names: "contact/quadruped/<variant>/tol:<force_tolerance>". The counters "force_error_N"
// (largest |F_ext| difference on any body, over a set of random standing states, against
// force_tolerance = 0) and "pairs_evaluated" make the trade table of docs/contact.md.

#include <cmath>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Core>

#include "idto/idto.hpp"

namespace {

struct Scene {
  std::string error;
  idto::Model model;
  std::vector<Eigen::VectorXd> q, v;  // random standing states
};

// variant: "plain", "filtered100" (100 spheres welded to the body, excluded by
// excluded_pairs), "far100" (100 world spheres 5-10 m away, evaluated unless pruned).
Scene MakeScene(const std::string& variant) {
  Scene s;
  try {
    idto::ModelBuilder b("quadruped_scene");
    idto::UrdfOptions o;
    o.base = idto::BaseType::kFloating;
    idto::AddUrdfFile(std::string(IDTO_SOURCE_DIR) + "/models/quadruped.urdf", o, &b);
    b.AddGeometry("ground", idto::kWorldBody, Eigen::Isometry3d::Identity(), idto::HalfSpace{});
    for (int i = 0; i < 100 && variant != "plain"; ++i) {
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      if (variant == "filtered100") {
        X.translation() << 0.01 * (i % 10) - 0.05, 0.01 * (i / 10) - 0.05, 0.02;
        b.AddGeometry("extra" + std::to_string(i), b.GetBodyIndex("body"), X, idto::Sphere{0.01});
      } else {
        const double angle = 2.0 * M_PI * i / 100.0;
        X.translation() << (5.0 + 0.05 * i) * std::cos(angle), (5.0 + 0.05 * i) * std::sin(angle),
            1.0;
        b.AddGeometry("extra" + std::to_string(i), idto::kWorldBody, X, idto::Sphere{0.1});
      }
    }
    s.model = b.Build();
    std::srand(7);
    for (int i = 0; i < 16; ++i) {
      Eigen::VectorXd q = s.model.NeutralConfiguration();
      q(6) = 0.30 + 0.05 * (std::rand() / static_cast<double>(RAND_MAX));  // base height
      for (int j = 7; j < s.model.nq(); ++j) {
        q(j) = 0.4 * (std::rand() / static_cast<double>(RAND_MAX) - 0.5);
      }
      Eigen::VectorXd v = Eigen::VectorXd::Zero(s.model.nv());
      for (int j = 0; j < s.model.nv(); ++j) {
        v(j) = 0.2 * (std::rand() / static_cast<double>(RAND_MAX) - 0.5);
      }
      s.q.push_back(q);
      s.v.push_back(v);
    }
  } catch (const std::exception& e) {
    s.error = e.what();
  }
  return s;
}

idto::ContactOptions Options(const idto::Model& model, const std::string& variant,
                             double tolerance) {
  idto::ContactOptions o;
  o.parameters.stiffness = 2000.0;
  o.parameters.smoothing = 0.01;
  o.force_tolerance = tolerance;
  if (variant == "filtered100") {
    // (A collision group of "body" alone would exclude nothing: ContactEngine refuses it.)
    (void)model;
    for (int i = 0; i < 100; ++i) o.excluded_pairs.emplace_back("extra" + std::to_string(i), "*");
  }
  return o;
}

void BM_Contact(benchmark::State& state, const std::string& variant, double tolerance) {
  const Scene scene = MakeScene(variant);
  if (!scene.error.empty()) {
    state.SkipWithError(scene.error.c_str());
    return;
  }
  const idto::Model& model = scene.model;
  const idto::ContactEngine engine(model, Options(model, variant, tolerance));
  const idto::ContactEngine reference(model, Options(model, variant, 0.0));
  idto::ContactData cd = engine.MakeData(model), rd = reference.MakeData(model);
  std::vector<idto::Data> datas;
  for (size_t i = 0; i < scene.q.size(); ++i) {
    datas.emplace_back(model);
    idto::ForwardKinematics(model, scene.q[i], scene.v[i], &datas.back());
  }
  double error = 0.0;
  int evaluated = 0;
  for (const idto::Data& d : datas) {
    engine.Evaluate(model, d, &cd);
    reference.Evaluate(model, d, &rd);
    error = std::max(error, (cd.F_ext - rd.F_ext).cwiseAbs().maxCoeff());
    evaluated += cd.num_active;
  }
  size_t i = 0;
  for (auto _ : state) {
    engine.Evaluate(model, datas[i], &cd);
    benchmark::DoNotOptimize(cd.F_ext.data());
    i = (i + 1) % datas.size();
  }
  state.counters["force_error_N"] = error;
  state.counters["pairs"] = engine.num_pairs();
  state.counters["pairs_evaluated"] = static_cast<double>(evaluated) / datas.size();
}

void Register() {
  for (const std::string variant : {"plain", "filtered100", "far100"}) {
    for (double tol : {0.0, 1e-8, 1e-4, 1e-2, 1.0}) {
      if (variant == "filtered100" && tol != 1e-8) continue;
      const std::string name = "contact/quadruped/" + variant +
                               "/tol:" + (tol == 0.0 ? std::string("off") : std::to_string(tol));
      benchmark::RegisterBenchmark(name.c_str(), [variant, tol](benchmark::State& s) {
        BM_Contact(s, variant, tol);
      })->Unit(benchmark::kNanosecond);
    }
  }
}

const bool kRegistered = (Register(), true);

}  // namespace
