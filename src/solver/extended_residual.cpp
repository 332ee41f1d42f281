#include "solver/extended_residual.hpp"

#include <algorithm>

#include "idto/core/errors.hpp"
#include "math/small_dense.hpp"

namespace idto::internal {

namespace {

// The arguments of the kernels below.
struct KernelInput {
  const PentaDiagonalMatrix& H;
  const BlockConstraintJacobian& A;
  const Eigen::VectorXd& g;
  const Eigen::VectorXd& h;
  const Eigen::VectorXd& p;
  const Eigen::VectorXd& lambda;
};

// Each entry is accumulated in double-double arithmetic (exact products, TwoSum) and rounded
// once: the refinement then corrects the error that the conditioning of K (up to ~1e10 on the
// examples) puts into the double solve, not only the factorization's round-off (docs/solver.md,
// "Accuracy"). An entry is one chain of dependent TwoSums, so the rows go in chunks of up to
// 4 V entries (V = 2 or 1 vectors of 4 lanes) whose accumulators stay in registers for the whole
// row: the lanes are independent, and each entry still takes its terms in the same order, so
// the result does not depend on the chunking. Lanes past a chunk's `count` rows read zeros and
// are not stored. Everything here is inlined into the two variants of Kernel, so that the fma
// variant's products compile to vector fma instructions.
using internal::Lanes4;

// *x = (a[0], a[stride], a[2 stride], a[3 stride]) for the first `count` lanes, 0 for the others.
template <bool kContiguous>
__attribute__((always_inline)) inline void LoadLanes(const double* a, long stride, int count,
                                                     Lanes4* x) {
  const long s = kContiguous ? 1 : stride;
  if (count >= 4) {
    *x = Lanes4{a[0], a[s], a[2 * s], a[3 * s]};  // one vector load when contiguous
  } else {
    *x = Lanes4{a[0], count > 1 ? a[s] : 0.0, count > 2 ? a[2 * s] : 0.0, 0.0};  // count >= 1
  }
}

// (hi, lo)[v] −= a b for the chunk's V vectors of lanes, a from `column` as LoadLanes reads it.
template <bool kFma, int V, bool kContiguous>
__attribute__((always_inline)) inline void Accumulate(const double* column, long stride, int count,
                                                      double b, Lanes4* hi, Lanes4* lo) {
  const Lanes4 bb = {b, b, b, b};
  for (int v = 0; v < V; ++v) {
    Lanes4 a;
    LoadLanes<kContiguous>(column + 4 * v * stride, stride, count - 4 * v, &a);
    internal::SubtractProductExactlyWith<kFma>(a, bb, &hi[v], &lo[v]);
  }
}

// hi = −b's lanes, lo = 0.
template <int V>
__attribute__((always_inline)) inline void StartLanes(const double* b, int count, Lanes4* hi,
                                                      Lanes4* lo) {
  for (int v = 0; v < V; ++v) {
    LoadLanes<true>(b + 4 * v, 1, count - 4 * v, &hi[v]);
    hi[v] = -hi[v];
    lo[v] = Lanes4{0.0, 0.0, 0.0, 0.0};
  }
}

// out[i] = hi + lo, rounded once, for the chunk's lanes.
template <int V>
__attribute__((always_inline)) inline void StoreLanes(const Lanes4* hi, const Lanes4* lo, int count,
                                                      double* out) {
  for (int i = 0; i < count; ++i) out[i] = hi[i / 4][i % 4] + lo[i / 4][i % 4];
}

// Rows [i0, i0 + count) of step r's part of rp: −g_r − Σ_c H(r, c) p_c − Σ_j J(j, r + 1)ᵀ λ_j.
struct PositionRows {
  template <bool kFma, int V>
  __attribute__((always_inline)) static void Run(const KernelInput& in, int r, int i0, int count,
                                                 Eigen::VectorXd* rp) {
    const int N = in.A.num_steps(), n = in.A.num_positions(), nu = in.A.num_constraints();
    Lanes4 hi[V], lo[V];
    StartLanes<V>(in.g.data() + r * n + i0, count, hi, lo);
    // Left of the diagonal and the diagonal block, H(r, c) = A(r), B(r), C(r): along columns.
    for (int c = std::max(0, r - 2); c <= r; ++c) {
      const Eigen::MatrixXd& M = c == r ? in.H.C(r) : (c == r - 1 ? in.H.B(r) : in.H.A(r));
      const double* pc = in.p.data() + c * n;
      for (int j = 0; j < n; ++j) {
        Accumulate<kFma, V, true>(M.col(j).data() + i0, 1, count, pc[j], hi, lo);
      }
    }
    // Right of the diagonal, H(r, c)(i, j) = M(c)(j, i): along M(c)'s rows.
    for (int c = r + 1; c <= std::min(N - 1, r + 2); ++c) {
      const Eigen::MatrixXd& M = c == r + 1 ? in.H.B(c) : in.H.A(c);
      const double* pc = in.p.data() + c * n;
      const long ld = M.outerStride();
      for (int j = 0; j < n; ++j) {
        Accumulate<kFma, V, false>(M.data() + j + i0 * ld, ld, count, pc[j], hi, lo);
      }
    }
    // Aᵀλ over the constraints h_j that involve q_{r+1}: (J(j, r+1)ᵀ)(i, u) = J(u, i).
    for (int j = r; j <= std::min(N - 1, r + 2); ++j) {
      const Eigen::MatrixXd& J = in.A.Block(j, r + 1);
      const double* l = in.lambda.data() + j * nu;
      const long ld = J.outerStride();
      for (int u = 0; u < nu; ++u) {
        Accumulate<kFma, V, false>(J.data() + u + i0 * ld, ld, count, l[u], hi, lo);
      }
    }
    StoreLanes<V>(hi, lo, count, rp->data() + r * n + i0);
  }
};

// Rows [u0, u0 + count) of step j's part of rl: −h_j − Σ_s J(j, s) p_{s−1}.
struct ConstraintRows {
  template <bool kFma, int V>
  __attribute__((always_inline)) static void Run(const KernelInput& in, int j, int u0, int count,
                                                 Eigen::VectorXd* rl) {
    const int N = in.A.num_steps(), n = in.A.num_positions(), nu = in.A.num_constraints();
    Lanes4 hi[V], lo[V];
    StartLanes<V>(in.h.data() + j * nu + u0, count, hi, lo);
    for (int s = std::max(1, j - 1); s <= std::min(N, j + 1); ++s) {
      const Eigen::MatrixXd& J = in.A.Block(j, s);
      const double* ps = in.p.data() + (s - 1) * n;
      for (int i = 0; i < n; ++i) {
        Accumulate<kFma, V, true>(J.col(i).data() + u0, 1, count, ps[i], hi, lo);
      }
    }
    StoreLanes<V>(hi, lo, count, rl->data() + j * nu + u0);
  }
};

// Rows::Run over the chunks of [0, size): 8 rows (two vectors) at a time while more than 4 are
// left, then the last 1..4 in one vector.
template <class Rows, bool kFma>
__attribute__((always_inline)) inline void ForChunks(const KernelInput& in, int step, int size,
                                                     Eigen::VectorXd* out) {
  int i = 0;
  for (; size - i > 4; i += 8) Rows::template Run<kFma, 2>(in, step, i, std::min(8, size - i), out);
  if (i < size) Rows::template Run<kFma, 1>(in, step, i, size - i, out);
}

template <bool kFma>
__attribute__((always_inline)) inline void Kernel(const KernelInput& in, int begin, int end,
                                                  Eigen::VectorXd* rp, Eigen::VectorXd* rl) {
  for (int r = begin; r < end; ++r) {
    ForChunks<PositionRows, kFma>(in, r, in.A.num_positions(), rp);
  }
  for (int j = begin; j < end; ++j) {
    ForChunks<ConstraintRows, kFma>(in, j, in.A.num_constraints(), rl);
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
#define IDTO_FMA_DISPATCH 1
// Compiled for CPUs with fma whatever the build's flags; called only when CpuHasFma().
__attribute__((target("fma"))) void KernelFma(const KernelInput& in, int begin, int end,
                                              Eigen::VectorXd* rp, Eigen::VectorXd* rl) {
  Kernel<true>(in, begin, end, rp, rl);
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
                         int end, Eigen::VectorXd* rp, Eigen::VectorXd* rl, ProductSplit split) {
  const KernelInput in{H, A, g, h, p, lambda};
  if (split == ProductSplit::kAuto) {
    split = CpuHasFma() ? ProductSplit::kFmaInstruction : ProductSplit::kDekker;
  }
#if IDTO_FMA_DISPATCH
  if (split == ProductSplit::kFmaInstruction) {
    if (!CpuHasFma()) {
      ThrowInvalidArgument("ExtendedKktResidual", "split", "kFmaInstruction",
                           "kAuto or kDekker on a CPU without fma");
    }
    KernelFma(in, begin, end, rp, rl);
    return;
  }
#else
  if (split == ProductSplit::kFmaInstruction) {
    ThrowInvalidArgument("ExtendedKktResidual", "split", "kFmaInstruction",
                         "kAuto or kDekker on a CPU without fma");
  }
#endif
  Kernel<false>(in, begin, end, rp, rl);
}

}  // namespace idto::internal
