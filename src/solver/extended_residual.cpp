#include "solver/extended_residual.hpp"

#include <algorithm>

#include "idto/core/errors.hpp"
#include "math/small_dense.hpp"

namespace idto::internal {

namespace {

// Accumulated exactly enough in double-double arithmetic and rounded once: the refinement then
// corrects the error that the conditioning of K (up to ~1e10 on the examples) puts into the
// double solve, not only the factorization's round-off (docs/solver.md, "Accuracy"). Every loop
// runs along a stored column. Inlined into each caller, so that the fma variant's products
// compile to fma instructions.
template <bool kFma>
__attribute__((always_inline)) inline void Kernel(
    const PentaDiagonalMatrix& H, const BlockConstraintJacobian& A, const Eigen::VectorXd& g,
    const Eigen::VectorXd& h, const Eigen::VectorXd& p, const Eigen::VectorXd& lambda, int begin,
    int end, double* hi, double* lo, Eigen::VectorXd* rp, Eigen::VectorXd* rl) {
  const int N = A.num_steps(), n = A.num_positions(), nu = A.num_constraints();
  for (int r = begin; r < end; ++r) {
    for (int i = 0; i < n; ++i) {
      hi[i] = -g(r * n + i);
      lo[i] = 0.0;
    }
    // Blocks left of the diagonal and the diagonal one, H(r, c) = A(r), B(r), C(r): by columns.
    for (int c = std::max(0, r - 2); c <= r; ++c) {
      const Eigen::MatrixXd& M = c == r ? H.C(r) : (c == r - 1 ? H.B(r) : H.A(r));
      for (int j = 0; j < n; ++j) {
        const double pj = p(c * n + j);
        const double* column = M.col(j).data();
        for (int i = 0; i < n; ++i) SubtractProductExactlyWith<kFma>(column[i], pj, &hi[i], &lo[i]);
      }
    }
    // Right of the diagonal, H(r, c) = M(c)ᵀ: H(r, c)(i, j) = M(c)(j, i). The inner loop runs
    // over i, so that its n accumulations are independent (TwoSum is a chain of dependent
    // operations: accumulating one entry in the inner loop would serialize them).
    for (int c = r + 1; c <= std::min(N - 1, r + 2); ++c) {
      const Eigen::MatrixXd& M = c == r + 1 ? H.B(c) : H.A(c);
      const double* pc = p.data() + c * n;
      const double* m = M.data();
      const long ld = M.outerStride();
      for (int j = 0; j < n; ++j) {
        const double pj = pc[j];
        for (int i = 0; i < n; ++i)
          SubtractProductExactlyWith<kFma>(m[j + i * ld], pj, &hi[i], &lo[i]);
      }
    }
    // Aᵀλ: the constraints h_j that involve q_{r+1}; (J(j, r+1)ᵀ)(i, u) = J(u, i), inner loop
    // over i as above.
    for (int j = r; j <= std::min(N - 1, r + 2); ++j) {
      const Eigen::MatrixXd& J = A.Block(j, r + 1);
      const double* l = lambda.data() + j * nu;
      const double* a = J.data();
      const long ld = J.outerStride();
      for (int u = 0; u < nu; ++u) {
        const double lu = l[u];
        for (int i = 0; i < n; ++i)
          SubtractProductExactlyWith<kFma>(a[u + i * ld], lu, &hi[i], &lo[i]);
      }
    }
    for (int i = 0; i < n; ++i) (*rp)(r * n + i) = hi[i] + lo[i];
  }
  for (int j = begin; j < end; ++j) {
    for (int u = 0; u < nu; ++u) {
      hi[u] = -h(j * nu + u);
      lo[u] = 0.0;
    }
    for (int s = std::max(1, j - 1); s <= std::min(N, j + 1); ++s) {
      const Eigen::MatrixXd& J = A.Block(j, s);
      for (int i = 0; i < n; ++i) {
        const double pi = p((s - 1) * n + i);
        const double* column = J.col(i).data();
        for (int u = 0; u < nu; ++u)
          SubtractProductExactlyWith<kFma>(column[u], pi, &hi[u], &lo[u]);
      }
    }
    for (int u = 0; u < nu; ++u) (*rl)(j * nu + u) = hi[u] + lo[u];
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
#define IDTO_FMA_DISPATCH 1
// Compiled for CPUs with fma whatever the build's flags; called only when CpuHasFma().
__attribute__((target("fma"))) void KernelFma(
    const PentaDiagonalMatrix& H, const BlockConstraintJacobian& A, const Eigen::VectorXd& g,
    const Eigen::VectorXd& h, const Eigen::VectorXd& p, const Eigen::VectorXd& lambda, int begin,
    int end, double* hi, double* lo, Eigen::VectorXd* rp, Eigen::VectorXd* rl) {
  Kernel<true>(H, A, g, h, p, lambda, begin, end, hi, lo, rp, rl);
}
#else
#define IDTO_FMA_DISPATCH 0
#endif

}  // namespace

bool CpuHasFma() {
#if IDTO_FMA_DISPATCH
  static const bool has_fma = __builtin_cpu_supports("fma");
  return has_fma;
#else
  return false;
#endif
}

void ExtendedKktResidual(const PentaDiagonalMatrix& H, const BlockConstraintJacobian& A,
                         const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                         const Eigen::VectorXd& p, const Eigen::VectorXd& lambda, int begin,
                         int end, double* hi, double* lo, Eigen::VectorXd* rp, Eigen::VectorXd* rl,
                         ProductSplit split) {
  if (split == ProductSplit::kAuto) {
    split = CpuHasFma() ? ProductSplit::kFmaInstruction : ProductSplit::kDekker;
  }
#if IDTO_FMA_DISPATCH
  if (split == ProductSplit::kFmaInstruction) {
    if (!CpuHasFma()) {
      ThrowInvalidArgument("ExtendedKktResidual", "split", "kFmaInstruction",
                           "kAuto or kDekker on a CPU without fma");
    }
    KernelFma(H, A, g, h, p, lambda, begin, end, hi, lo, rp, rl);
    return;
  }
#else
  if (split == ProductSplit::kFmaInstruction) {
    ThrowInvalidArgument("ExtendedKktResidual", "split", "kFmaInstruction",
                         "kAuto or kDekker on a CPU without fma");
  }
#endif
  Kernel<false>(H, A, g, h, p, lambda, begin, end, hi, lo, rp, rl);
}

}  // namespace idto::internal
