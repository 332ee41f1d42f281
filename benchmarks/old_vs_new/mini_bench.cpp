// Mini benchmark (one TU) for old-vs-new comparison: CPU time per call, alternating kernels.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "idto/idto.hpp"

double CpuNow() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "/work/wt/derivs/models/";
  idto::UrdfOptions options;
  options.base = idto::BaseType::kFloating;
  options.X_WB.translation() = Eigen::Vector3d(0.0, 0.0, 0.3);
  const idto::Model model = idto::ParseUrdfFile(dir + "quadruped.urdf", options);
  std::mt19937 engine(20240601u);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd q = model.NeutralConfiguration(), v(model.nv()), a(model.nv());
  for (int i = 0; i < model.nq(); ++i) q(i) += 0.5 * uniform(engine);
  q.head<4>().normalize();
  for (int i = 0; i < model.nv(); ++i) v(i) = uniform(engine), a(i) = uniform(engine);
  idto::Data data(model);
  std::vector<std::pair<std::string, std::function<void()>>> kernels = {
      {"FK(q,v)", [&] { idto::ForwardKinematics(model, q, v, &data); }},
      {"RNEA", [&] { idto::InverseDynamics(model, q, v, a, &data); }},
      {"CRBA", [&] { idto::MassMatrix(model, q, &data); }},
#ifdef WITH_DERIVS
      {"RNEAderivs", [&] { idto::ComputeRneaDerivatives(model, q, v, a, &data); }},
#endif
  };
  const int kRounds = 15, kCalls = 20000;
  std::vector<std::vector<double>> t(kernels.size());
  for (int round = 0; round < kRounds; ++round) {
    for (std::size_t k = 0; k < kernels.size(); ++k) {
      const double t0 = CpuNow();
      for (int i = 0; i < kCalls; ++i) kernels[k].second();
      t[k].push_back((CpuNow() - t0) / kCalls * 1e6);
    }
  }
  for (std::size_t k = 0; k < kernels.size(); ++k) {
    std::sort(t[k].begin(), t[k].end());
    std::printf("%-12s median %.3f us  min %.3f us (CPU time, %d rounds x %d calls)\n",
                kernels[k].first.c_str(), t[k][kRounds / 2], t[k][0], kRounds, kCalls);
  }
  return 0;
}
