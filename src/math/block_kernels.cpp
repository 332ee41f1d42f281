#include "math/block_kernels.hpp"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <string>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define IDTO_X86_KERNELS 1
#endif

namespace idto::internal {

namespace {

bool CpuHasAvx2Fma() {
#ifdef IDTO_X86_KERNELS
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}

// IDTO_PORTABLE_KERNELS set and not "0": the baseline kernels everywhere, for results that are
// the same bit for bit on CPUs with and without AVX2/FMA.
bool PortableRequested() {
  const char* value = std::getenv("IDTO_PORTABLE_KERNELS");
  return value != nullptr && value[0] != '\0' && std::string(value) != "0";
}

bool Avx2Allowed() {
#ifdef IDTO_X86_KERNELS
  return CpuHasAvx2Fma() && !PortableRequested();
#else
  return false;
#endif
}

std::atomic<bool>& Avx2Enabled() {
  static std::atomic<bool> enabled{Avx2Allowed()};
  return enabled;
}

}  // namespace

bool Avx2KernelsAvailable() { return CpuHasAvx2Fma(); }

bool UseAvx2Kernels() { return Avx2Enabled().load(std::memory_order_relaxed); }

void SetAvx2KernelsEnabledForTesting(bool enabled) {
  Avx2Enabled().store(enabled && CpuHasAvx2Fma(), std::memory_order_relaxed);
}

namespace avx2 {

#ifdef IDTO_X86_KERNELS

#define IDTO_TARGET_AVX2 __attribute__((target("avx2,fma")))

namespace {

// Lanes [0, count) of a 4-lane mask (count may be <= 0 or >= 4).
IDTO_TARGET_AVX2 inline __m256i LaneMask(int count) {
  return _mm256_cmpgt_epi64(_mm256_set1_epi64x(count), _mm256_set_epi64x(3, 2, 1, 0));
}

// Rows of a tile: 12 rows by 4 columns take 12 of the 16 vector registers as accumulators
// (measured faster than 8 x 4 on the quadruped's blocks of 19: fewer tiles, more independent
// fmas in flight).
constexpr int kTileRows = 12;

// One tile of C += alpha A B^T: rows [0, mr) (mr <= 4 RV) of A and C, columns [0, NC) of B^T
// and C. The accumulators stay in registers over the whole inner dimension: per p, RV loads of
// A's column, NC broadcasts of B's, RV NC fmas. kFull: mr == 4 RV (plain loads and stores).
// keep_from_row >= 0 (a tile on C's diagonal, lower_only): entry (i, j) is written only where
// i + keep_from_row >= j, i.e. on or below the diagonal of C.
template <int RV, int NC, bool kFull>
IDTO_TARGET_AVX2 void Tile(int mr, int k, double alpha, const double* A, long lda, const double* B,
                           long b_col, long b_inner, int keep_from_row, double* C, long ldc) {
  __m256d acc[RV][NC];
#pragma GCC unroll 4
  for (int r = 0; r < RV; ++r) {
#pragma GCC unroll 4
    for (int j = 0; j < NC; ++j) acc[r][j] = _mm256_setzero_pd();
  }
  __m256i mask[RV];
#pragma GCC unroll 4
  for (int r = 0; r < RV; ++r) mask[r] = LaneMask(mr - 4 * r);
  for (int p = 0; p < k; ++p) {
    const double* a = A + p * lda;
    const double* b = B + p * b_inner;
    __m256d av[RV];
#pragma GCC unroll 4
    for (int r = 0; r < RV; ++r) {
      av[r] = kFull ? _mm256_loadu_pd(a + 4 * r) : _mm256_maskload_pd(a + 4 * r, mask[r]);
    }
#pragma GCC unroll 4
    for (int j = 0; j < NC; ++j) {
      const __m256d bj = _mm256_broadcast_sd(b + j * b_col);
#pragma GCC unroll 4
      for (int r = 0; r < RV; ++r) acc[r][j] = _mm256_fmadd_pd(av[r], bj, acc[r][j]);
    }
  }
  const __m256d alpha_v = _mm256_set1_pd(alpha);
  if (keep_from_row >= 0) {
    // A diagonal tile: through memory, entry by entry (at most one per column block).
    alignas(32) double t[RV * 4];
#pragma GCC unroll 4
    for (int j = 0; j < NC; ++j) {
#pragma GCC unroll 4
      for (int r = 0; r < RV; ++r) _mm256_store_pd(t + 4 * r, acc[r][j]);
      double* c = C + j * ldc;
      for (int i = 0; i < mr; ++i) {
        if (i + keep_from_row >= j) c[i] += alpha * t[i];
      }
    }
    return;
  }
#pragma GCC unroll 4
  for (int j = 0; j < NC; ++j) {
    double* c = C + j * ldc;
#pragma GCC unroll 4
    for (int r = 0; r < RV; ++r) {
      if (kFull) {
        _mm256_storeu_pd(c + 4 * r,
                         _mm256_fmadd_pd(alpha_v, acc[r][j], _mm256_loadu_pd(c + 4 * r)));
      } else {
        const __m256d old = _mm256_maskload_pd(c + 4 * r, mask[r]);
        _mm256_maskstore_pd(c + 4 * r, mask[r], _mm256_fmadd_pd(alpha_v, acc[r][j], old));
      }
    }
  }
}

template <int NC>
IDTO_TARGET_AVX2 void TileRows(int mr, int k, double alpha, const double* A, long lda,
                               const double* B, long b_col, long b_inner, int keep_from_row,
                               double* C, long ldc) {
  if (mr == 12) {
    Tile<3, NC, true>(mr, k, alpha, A, lda, B, b_col, b_inner, keep_from_row, C, ldc);
  } else if (mr > 8) {
    Tile<3, NC, false>(mr, k, alpha, A, lda, B, b_col, b_inner, keep_from_row, C, ldc);
  } else if (mr == 8) {
    Tile<2, NC, true>(mr, k, alpha, A, lda, B, b_col, b_inner, keep_from_row, C, ldc);
  } else if (mr > 4) {
    Tile<2, NC, false>(mr, k, alpha, A, lda, B, b_col, b_inner, keep_from_row, C, ldc);
  } else if (mr == 4) {
    Tile<1, NC, true>(mr, k, alpha, A, lda, B, b_col, b_inner, keep_from_row, C, ldc);
  } else {
    Tile<1, NC, false>(mr, k, alpha, A, lda, B, b_col, b_inner, keep_from_row, C, ldc);
  }
}

// C (m x n) += alpha A Bop with Bop(p, j) = B[j b_col + p b_inner] (k x n): A B^T for
// (b_col, b_inner) = (1, ldb), A B for (ldb, 1).
IDTO_TARGET_AVX2 void AddProductImpl(int m, int n, int k, double alpha, const double* A, long lda,
                                     const double* B, long b_col, long b_inner, bool lower_only,
                                     double* C, long ldc) {
  for (int j0 = 0; j0 < n; j0 += 4) {
    const int nc = n - j0 < 4 ? n - j0 : 4;
    // With lower_only, the rows above j0 hold no entry on or below the diagonal of this block.
    for (int i0 = lower_only ? j0 : 0; i0 < m; i0 += kTileRows) {
      const int mr = m - i0 < kTileRows ? m - i0 : kTileRows;
      const int keep = lower_only && i0 < j0 + nc ? i0 - j0 : -1;
      const double* a = A + i0;
      const double* b = B + j0 * b_col;
      double* c = C + i0 + j0 * ldc;
      switch (nc) {
        case 4:
          TileRows<4>(mr, k, alpha, a, lda, b, b_col, b_inner, keep, c, ldc);
          break;
        case 3:
          TileRows<3>(mr, k, alpha, a, lda, b, b_col, b_inner, keep, c, ldc);
          break;
        case 2:
          TileRows<2>(mr, k, alpha, a, lda, b, b_col, b_inner, keep, c, ldc);
          break;
        default:
          TileRows<1>(mr, k, alpha, a, lda, b, b_col, b_inner, keep, c, ldc);
          break;
      }
    }
  }
}

IDTO_TARGET_AVX2 inline void AddProductNTImpl(int m, int n, int k, double alpha, const double* A,
                                              long lda, const double* B, long ldb, bool lower_only,
                                              double* C, long ldc) {
  AddProductImpl(m, n, k, alpha, A, lda, B, 1, ldb, lower_only, C, ldc);
}

// Column j of X (m rows) -= column p of X times l, then the next such update: the diagonal
// blocks' updates of the solve and the factorization (short, vectorized by the compiler).
IDTO_TARGET_AVX2 inline void SubtractScaledColumn(int begin, int end, const double* x_p, double l,
                                                  double* x_j) {
  for (int i = begin; i < end; ++i) x_j[i] -= x_p[i] * l;
}

}  // namespace

IDTO_TARGET_AVX2 void AddProductNT(int m, int n, int k, double alpha, const double* A, int lda,
                                   const double* B, int ldb, bool lower_only, double* C, int ldc) {
  if (m <= 0 || n <= 0 || k <= 0) return;
  AddProductNTImpl(m, n, k, alpha, A, lda, B, ldb, lower_only, C, ldc);
}

IDTO_TARGET_AVX2 void SolveRightLowerTransposed(int m, int n, const double* L, int ldl, double* X,
                                                int ldx);

IDTO_TARGET_AVX2 void AddProductNN(int m, int n, int k, double alpha, const double* A, int lda,
                                   const double* B, int ldb, bool lower_only, double* C, int ldc) {
  if (m <= 0 || n <= 0 || k <= 0) return;
  AddProductImpl(m, n, k, alpha, A, lda, B, ldb, 1, lower_only, C, ldc);
}

IDTO_TARGET_AVX2 void LowerSolve(int size, const double* L, int ldl, const double* inverse_diagonal,
                                 double* X, int ldx, int cols) {
  // L^-1 X = (X^T L^-T)^T: transposed, the substitution runs down contiguous columns of X^T, one
  // vector operation for four of X's columns, instead of a chain of scalar updates per column
  // (measured: the latter took 15 % of an Allegro Lagrange iteration). The transpose lives on
  // the stack (no allocation); larger blocks take the blocked loop below.
  constexpr int kMaxTransposed = 1024;  // 8 KB: blocks up to 32 x 32, small beside any thread stack
  if (size * cols <= kMaxTransposed) {
    alignas(32) double T[kMaxTransposed];
    for (int j = 0; j < cols; ++j) {
      const double* x = X + static_cast<long>(j) * ldx;
      for (int i = 0; i < size; ++i) T[j + static_cast<long>(i) * cols] = x[i];
    }
    SolveRightLowerTransposed(cols, size, L, ldl, T, cols);
    for (int j = 0; j < cols; ++j) {
      double* x = X + static_cast<long>(j) * ldx;
      for (int i = 0; i < size; ++i) x[i] = T[j + static_cast<long>(i) * cols];
    }
    return;
  }
  // Right-looking by blocks of four rows: the block's rows of X by substitution, then the rows
  // below it updated by one tiled product (inner dimension 4).
  for (int k0 = 0; k0 < size; k0 += 4) {
    const int kc = size - k0 < 4 ? size - k0 : 4;
    for (int j = 0; j < cols; ++j) {
      double* x = X + static_cast<long>(j) * ldx;
      for (int k = k0; k < k0 + kc; ++k) {
        const double a = x[k] * inverse_diagonal[k];
        x[k] = a;
        const double* l = L + static_cast<long>(k) * ldl;
        for (int i = k + 1; i < k0 + kc; ++i) x[i] -= a * l[i];
      }
    }
    const int below = size - k0 - kc;
    if (below > 0) {
      AddProductImpl(below, cols, kc, -1.0, L + k0 + kc + static_cast<long>(k0) * ldl, ldl, X + k0,
                     ldx, 1, false, X + k0 + kc, ldx);
    }
  }
}

IDTO_TARGET_AVX2 void SolveRightLowerTransposed(int m, int n, const double* L, int ldl, double* X,
                                                int ldx) {
  // Column j of X L^T = X_old gives x_j = (x_old_j - sum_{p<j} x_p L(j, p)) / L(j, j); four
  // columns at a time, their updates from the solved columns as one tiled product.
  for (int j0 = 0; j0 < n; j0 += 4) {
    const int nc = n - j0 < 4 ? n - j0 : 4;
    if (j0 > 0) {
      AddProductNTImpl(m, nc, j0, -1.0, X, ldx, L + j0, ldl, false, X + static_cast<long>(j0) * ldx,
                       ldx);
    }
    for (int j = j0; j < j0 + nc; ++j) {
      double* x_j = X + static_cast<long>(j) * ldx;
      for (int p = j0; p < j; ++p) {
        SubtractScaledColumn(0, m, X + static_cast<long>(p) * ldx,
                             L[j + static_cast<long>(p) * ldl], x_j);
      }
      // One division per column, not per entry (a vector division costs ~10 fmas).
      const double inverse = 1.0 / L[j + static_cast<long>(j) * ldl];
      for (int i = 0; i < m; ++i) x_j[i] *= inverse;
    }
  }
}

IDTO_TARGET_AVX2 int CholeskyColumns(double tolerance, const double* diagonal, int size, int begin,
                                     int end, double* M, int ld, double* inverse_diagonal,
                                     double* relative_pivot) {
  // Left-looking by panels of four columns: the panel's update from the panel's earlier columns
  // as one tiled product (its entries above the diagonal inside the panel are updated too; they
  // are not part of the result), then the panel column by column; then the trailing block.
  for (int k0 = begin; k0 < end; k0 += 4) {
    const int kc = end - k0 < 4 ? end - k0 : 4;
    const double* left = M + k0 + static_cast<long>(begin) * ld;
    AddProductNTImpl(size - k0, kc, k0 - begin, -1.0, left, ld, left, ld, false,
                     M + k0 + static_cast<long>(k0) * ld, ld);
    for (int k = k0; k < k0 + kc; ++k) {
      double* m_k = M + static_cast<long>(k) * ld;
      for (int p = k0; p < k; ++p) {
        SubtractScaledColumn(k, size, M + static_cast<long>(p) * ld,
                             M[k + static_cast<long>(p) * ld], m_k);
      }
      const double d = m_k[k];
      const double original = diagonal != nullptr ? diagonal[k] : 0.0;
      if (!AcceptPivot(d, tolerance, original, relative_pivot)) return k;
      const double l = std::sqrt(d);
      // One division per column, not per entry (a vector division costs ~10 fmas).
      const double inverse = 1.0 / l;
      if (inverse_diagonal != nullptr) inverse_diagonal[k] = inverse;
      m_k[k] = l;
      for (int i = k + 1; i < size; ++i) m_k[i] *= inverse;
    }
  }
  const int rest = size - end;
  if (rest > 0 && end > begin) {
    const double* panel = M + end + static_cast<long>(begin) * ld;
    AddProductNTImpl(rest, rest, end - begin, -1.0, panel, ld, panel, ld, true,
                     M + end + static_cast<long>(end) * ld, ld);
  }
  return -1;
}

IDTO_TARGET_AVX2 bool CholeskyInPlace(int n, double* S, int lds) {
  // Tolerance 0 without scales: any positive finite pivot is accepted.
  double relative = 0.0;
  if (CholeskyColumns(0.0, nullptr, n, 0, n, S, lds, nullptr, &relative) >= 0) return false;
  for (int j = 1; j < n; ++j) {
    for (int i = 0; i < j; ++i) S[i + static_cast<long>(j) * lds] = 0.0;
  }
  return true;
}

#else  // !IDTO_X86_KERNELS: UseAvx2Kernels() is false, so none of these is ever called.

void AddProductNN(int, int, int, double, const double*, int, const double*, int, bool, double*,
                  int) {
  std::abort();
}
void LowerSolve(int, const double*, int, const double*, double*, int, int) { std::abort(); }

void AddProductNT(int, int, int, double, const double*, int, const double*, int, bool, double*,
                  int) {
  std::abort();
}
void SolveRightLowerTransposed(int, int, const double*, int, double*, int) { std::abort(); }
bool CholeskyInPlace(int, double*, int) { std::abort(); }
int CholeskyColumns(double, const double*, int, int, int, double*, int, double*, double*) {
  std::abort();
}

#endif

}  // namespace avx2

}  // namespace idto::internal
