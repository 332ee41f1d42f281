// Cost of one signed distance query per pair type: analytic pairs, the FCL fallback, and FCL's
// answer on the analytic pairs (SignedDistanceFcl) for comparison. Each benchmark cycles through
// 64 seeded random poses of one class (separated or penetrating) so that branches are not
// perfectly predicted.
#include <algorithm>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Geometry>

#include "idto/geometry/signed_distance.hpp"

namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;

struct PoseSet {
  idto::Shape A, B;
  std::vector<Isometry3d> X_WA, X_WB;
};

idto::Shape MakeShape(const std::string& name) {
  if (name == "sphere") return idto::Sphere{0.2};
  if (name == "capsule") return idto::Capsule{0.1, 0.4};
  if (name == "cylinder") return idto::Cylinder{0.15, 0.4};
  if (name == "box") return idto::Box{Vector3d(0.3, 0.2, 0.5)};
  return idto::HalfSpace{};
}

// 64 poses with φ > 0 (separated) or φ < 0 (penetrating).
PoseSet MakePoses(const std::string& a, const std::string& b, bool separated) {
  PoseSet set{MakeShape(a), MakeShape(b), {}, {}};
  std::mt19937 engine(42);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(-0.5, 0.5);
  auto pose = [&]() {
    Isometry3d X = Isometry3d::Identity();
    Eigen::Quaterniond q(normal(engine), normal(engine), normal(engine), normal(engine));
    X.linear() = q.normalized().toRotationMatrix();
    X.translation() = Vector3d(uniform(engine), uniform(engine), uniform(engine));
    return X;
  };
  while (set.X_WA.size() < 64) {
    const Isometry3d X_WA = pose();
    const Isometry3d X_WB = pose();
    const double phi = idto::SignedDistance(set.A, X_WA, set.B, X_WB).distance;
    if ((phi > 0.0) == separated) {
      set.X_WA.push_back(X_WA);
      set.X_WB.push_back(X_WB);
    }
  }
  return set;
}

template <bool kFcl>
void BM_SignedDistance(benchmark::State& state, const std::string& a, const std::string& b,
                       bool separated) {
  const PoseSet set = MakePoses(a, b, separated);
  std::size_t i = 0;
  for (auto _ : state) {
    const idto::SignedDistanceResult r =
        kFcl ? idto::SignedDistanceFcl(set.A, set.X_WA[i], set.B, set.X_WB[i])
             : idto::SignedDistance(set.A, set.X_WA[i], set.B, set.X_WB[i]);
    benchmark::DoNotOptimize(r.distance);
    i = (i + 1) & 63;
  }
  state.SetLabel(idto::SignedDistanceIsExact(set.A, set.B) && !kFcl ? "exact" : "FCL");
}

// A box on the ground as one box–half-space query versus its 9 inscribed spheres.
void BM_InscribedSpheresHalfSpace(benchmark::State& state) {
  const idto::Box box{Vector3d::Constant(0.15)};
  const std::vector<idto::InscribedSphere> spheres = idto::InscribedSpheres(box);
  Isometry3d X_WBox = Isometry3d::Identity();
  X_WBox.linear() = Eigen::AngleAxisd(0.3, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  X_WBox.translation() = Vector3d(0.1, 0.2, 0.08);
  const Isometry3d I = Isometry3d::Identity();
  for (auto _ : state) {
    double phi = 1e9;
    for (const auto& s : spheres) {
      phi = std::min(
          phi,
          idto::SignedDistance(s.sphere, X_WBox * s.X_BoxSphere, idto::HalfSpace{}, I).distance);
    }
    benchmark::DoNotOptimize(phi);
  }
}
BENCHMARK(BM_InscribedSpheresHalfSpace)->Name("geometry/SignedDistance/box9spheres-half_space");

int RegisterAll() {
  const std::vector<std::pair<std::string, std::string>> analytic = {
      {"sphere", "sphere"},   {"sphere", "half_space"},   {"sphere", "capsule"},
      {"sphere", "cylinder"}, {"sphere", "box"},          {"capsule", "half_space"},
      {"capsule", "capsule"}, {"cylinder", "half_space"}, {"box", "half_space"}};
  const std::vector<std::pair<std::string, std::string>> fcl = {{"capsule", "cylinder"},
                                                                {"capsule", "box"},
                                                                {"cylinder", "cylinder"},
                                                                {"cylinder", "box"},
                                                                {"box", "box"}};
  for (const bool separated : {true, false}) {
    const std::string kind = separated ? "/separated" : "/penetrating";
    for (const auto& pairs : {analytic, fcl}) {
      for (const auto& [a, b] : pairs) {
        benchmark::RegisterBenchmark(("geometry/SignedDistance/" + a + "-" + b + kind).c_str(),
                                     [a = a, b = b, separated](benchmark::State& state) {
                                       BM_SignedDistance<false>(state, a, b, separated);
                                     });
      }
    }
    // FCL on the analytic pairs it can take (no half-spaces), for comparison.
    for (const auto& [a, b] : analytic) {
      if (b == "half_space") continue;
      benchmark::RegisterBenchmark(("geometry/SignedDistanceFcl/" + a + "-" + b + kind).c_str(),
                                   [a = a, b = b, separated](benchmark::State& state) {
                                     BM_SignedDistance<true>(state, a, b, separated);
                                   });
    }
  }
  return 0;
}
const int kRegistered = RegisterAll();

}  // namespace
