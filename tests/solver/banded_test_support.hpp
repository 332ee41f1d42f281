#pragma once

// A random banded KKT problem and the dense long-double oracle of its solve, shared by the
// banded KKT tests (banded_kkt_test.cpp, kkt_unrefined_test.cpp), and the random banded SPD
// matrices of penta_diagonal_test.cpp.

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "idto/math/penta_diagonal_matrix.hpp"
#include "idto/solver/banded_kkt.hpp"
#include "support/random.hpp"

namespace idto::test {

using MatrixXl = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
using VectorXl = Eigen::Matrix<long double, Eigen::Dynamic, 1>;

struct KktProblem {
  PentaDiagonalMatrix H;
  BlockConstraintJacobian A;
  Eigen::VectorXd g, h;
};

/// A dense (N n) × (N n) symmetric positive definite matrix with two block off-diagonals:
/// L diag(d) Lᵀ, L block-banded (bandwidth 2 blocks) with a dominant diagonal, d log-uniform in
/// [1, condition].
inline Eigen::MatrixXd RandomBandedSpd(int N, int n, double condition, Random* rng) {
  const int size = N * n;
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(size, size);
  for (int k = 0; k < N; ++k) {
    for (int j = std::max(0, k - 2); j <= k; ++j) {
      L.block(k * n, j * n, n, n) = rng->Matrix(n, n, -0.3, 0.3);
    }
    L.block(k * n, k * n, n, n).diagonal().array() += 2.0;
  }
  Eigen::VectorXd d(size);
  for (int i = 0; i < size; ++i) d(i) = std::pow(condition, rng->Uniform(0.0, 1.0));
  return L * d.asDiagonal() * L.transpose();
}

// A random problem. H = L diag(d) Lᵀ (L block-banded, d log-uniform in [1, condition]) is
// positive definite and pentadiagonal; A has random blocks. With spread > 1 the variables and
// the constraints are rescaled by log-uniform factors in [1/spread, spread]: entries of H and
// A then span spread² up and down (1e-6..1e6 for spread = 1e3).
inline KktProblem RandomProblem(int N, int n, int nu, double condition, double spread,
                                test::Random* rng) {
  const int size = N * n;
  const Eigen::MatrixXd LDLt = RandomBandedSpd(N, n, condition, rng);
  Eigen::VectorXd sq(size), sl(N * nu);
  for (int i = 0; i < size; ++i) sq(i) = std::pow(spread, rng->Uniform(-1.0, 1.0));
  for (int i = 0; i < N * nu; ++i) sl(i) = std::pow(spread, rng->Uniform(-1.0, 1.0));
  Eigen::MatrixXd Hd = sq.asDiagonal() * LDLt * sq.asDiagonal();
  KktProblem P{PentaDiagonalMatrix(N, n), BlockConstraintJacobian(N, n, nu), {}, {}};
  for (int k = 0; k < N; ++k) {
    P.H.C(k) = 0.5 * (Hd.block(k * n, k * n, n, n) + Hd.block(k * n, k * n, n, n).transpose());
    if (k >= 1) P.H.B(k) = Hd.block(k * n, (k - 1) * n, n, n);
    if (k >= 2) P.H.A(k) = Hd.block(k * n, (k - 2) * n, n, n);
  }
  for (int j = 0; j < N; ++j) {
    for (int s = j - 1; s <= j + 1; ++s) {
      if (!P.A.HasBlock(j, s)) continue;
      P.A.Block(j, s) = sl.segment(j * nu, nu).asDiagonal() * rng->Matrix(nu, n) *
                        sq.segment((s - 1) * n, n).asDiagonal();
    }
  }
  P.g = sq.asDiagonal() * rng->Vector(size);
  P.h = sl.asDiagonal() * rng->Vector(N * nu);
  return P;
}

// The dense formula λ = (A H⁻¹ Aᵀ)⁻¹ (h − A H⁻¹ g), p = −H⁻¹ (g + Aᵀ λ) in long double.
inline void DenseOracle(const KktProblem& P, Eigen::VectorXd* p, Eigen::VectorXd* lambda) {
  const MatrixXl H = P.H.MakeDense().cast<long double>();
  const MatrixXl A = P.A.MakeDense().cast<long double>();
  const VectorXl g = P.g.cast<long double>();
  const VectorXl h = P.h.cast<long double>();
  const Eigen::LLT<MatrixXl> H_llt(H);
  VectorXl l = VectorXl::Zero(A.rows());
  if (A.rows() > 0) {
    const MatrixXl HinvAt = H_llt.solve(A.transpose());
    const MatrixXl S = A * HinvAt;
    l = Eigen::LLT<MatrixXl>(S).solve(VectorXl(h - HinvAt.transpose() * g));
  }
  *p = (-H_llt.solve(VectorXl(g + A.transpose() * l))).cast<double>();
  *lambda = l.cast<double>();
}

}  // namespace idto::test
