#pragma once

// The oracle of the whole gradient: the transcription's cost L(q) written out once more on
// Eigen's AutoDiffScalar and differentiated with respect to q_1..q_N by forward-mode AD.
// Discrete velocities go through the templated N+ (v_k = N+(q_k) (q_k - q_{k-1}) / dt),
// accelerations are a_k = (v_{k+1} - v_k) / dt, torques tau_k = ID(q_{k+1}, v_{k+1}, a_k) with
// every contact pair (TauWithContactAD), and the cost is
//   sum_{k<N} dt/2 [Qq (q_k - q_nom)^2 + Qv (v_k - v_nom)^2 + R tau_k^2]
//   + 1/2 [Qfq (q_N - q_nom)^2 + Qfv (v_N - v_nom)^2].
// None of the solver's derivatives or chain rules is used. Step k's terms depend on q_{k-1},
// q_k and q_{k+1} only, so each is differentiated with 3 nq directions.

#include <numeric>
#include <optional>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>

#include "idto/problem/problem_definition.hpp"
#include "support/contact_oracle.hpp"

namespace idto {
namespace test {

/// dL/dq_1..q_N (N nq). `penalty_weight` > 0 replaces R on the unactuated DoFs (the penalty
/// method's cost). Needs an example without limit penalties; every contact pair is evaluated
/// (the library's result matches when its pruning is off, force_tolerance = 0).
inline Eigen::VectorXd AutoDiffCostGradient(const Model& model, const ProblemDefinition& problem,
                                            double penalty_weight,
                                            const std::vector<Eigen::VectorXd>& q) {
  if (problem.limits.any()) throw std::invalid_argument("cost oracle: limit penalties");
  const int N = problem.num_steps, nq = model.nq(), nv = model.nv(), n = 3 * nq;
  const double dt = problem.time_step;
  std::vector<int> pairs;
  std::optional<ContactEngine> engine;
  if (problem.enable_contact && model.geometries().size() >= 2) {
    engine.emplace(model, problem.contact);
    pairs.resize(engine->num_pairs());
    std::iota(pairs.begin(), pairs.end(), 0);
  }
  Eigen::VectorXd R = problem.R;
  if (penalty_weight > 0.0) {
    for (int d : problem.UnactuatedDofs(model)) R(d) = penalty_weight;
  }
  const auto constant = [&](const Eigen::VectorXd& x) {
    VectorX<ADX> y(x.size());
    for (int i = 0; i < x.size(); ++i) y(i) = ADX(x(i), Eigen::VectorXd::Zero(n));
    return y;
  };
  // q_j as an AD vector in slot s (0, 1, 2) of the 3 nq directions; q_0 is fixed.
  const auto seeded = [&](int j, int slot) {
    if (j <= 0) return constant(q[std::max(j, 0)]);
    VectorX<ADX> y(nq);
    for (int i = 0; i < nq; ++i) y(i) = ADX(q[j](i), n, slot * nq + i);
    return y;
  };
  const auto velocity = [&](const VectorX<ADX>& qk, const VectorX<ADX>& q_prev) {
    MatrixX<ADX> Nplus;
    CalcNplusMatrix<ADX>(model, qk, &Nplus);
    const VectorX<ADX> dq = (qk - q_prev) / ADX(dt);
    VectorX<ADX> v(nv);
    for (int r = 0; r < nv; ++r) {
      v(r) = ADX(0.0, Eigen::VectorXd::Zero(n));
      for (int c = 0; c < nq; ++c) v(r) += Nplus(r, c) * dq(c);
    }
    return v;
  };
  const auto weighted = [&](const Eigen::VectorXd& w, const VectorX<ADX>& x,
                            const Eigen::VectorXd& x_nom) {
    ADX sum(0.0, Eigen::VectorXd::Zero(n));
    for (int i = 0; i < x.size(); ++i) {
      const ADX e = x(i) - x_nom(i);
      sum += w(i) * e * e;
    }
    return sum;
  };
  Eigen::VectorXd g = Eigen::VectorXd::Zero(N * nq);
  // Adds d term / d q_j for the slots' configurations j = first .. first + 2 (j >= 1).
  const auto accumulate = [&](const ADX& term, int first) {
    for (int slot = 0; slot < 3; ++slot) {
      const int j = first + slot;
      if (j < 1 || j > N || term.derivatives().size() != n) continue;
      g.segment((j - 1) * nq, nq) += term.derivatives().segment(slot * nq, nq);
    }
  };
  for (int k = 0; k < N; ++k) {
    const VectorX<ADX> q_prev = seeded(k - 1, 0), q_k = seeded(k, 1), q_next = seeded(k + 1, 2);
    const VectorX<ADX> v_k = k == 0 ? constant(problem.v_init) : velocity(q_k, q_prev);
    const VectorX<ADX> v_next = velocity(q_next, q_k);
    const VectorX<ADX> a_k = (v_next - v_k) / ADX(dt);
    const VectorX<ADX> tau =
        TauWithContactAD(model, engine ? &*engine : nullptr, pairs, q_next, v_next, a_k, n);
    const ADX running = ADX(0.5 * dt) * (weighted(problem.Qq, q_k, problem.q_nom[k]) +
                                         weighted(problem.Qv, v_k, problem.v_nom[k]) +
                                         weighted(R, tau, Eigen::VectorXd::Zero(nv)));
    accumulate(running, k - 1);
  }
  const VectorX<ADX> q_prev = seeded(N - 1, 0), q_N = seeded(N, 1);
  const ADX terminal = ADX(0.5) * (weighted(problem.Qfq, q_N, problem.q_nom[N]) +
                                   weighted(problem.Qfv, velocity(q_N, q_prev), problem.v_nom[N]));
  accumulate(terminal, N - 1);
  return g;
}

}  // namespace test
}  // namespace idto
