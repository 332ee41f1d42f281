#pragma once

/// @file
/// The equality-constrained Newton step of IDTO (paper §5.2.2) in time and memory linear in the
/// horizon N: the KKT system
///
///     [H  Aᵀ] [p]   [−g]
///     [A  0 ] [λ] = [−h]
///
/// with H block-pentadiagonal (PentaDiagonalMatrix, positive definite) and A the Jacobian of
/// the constraints h_j (the unactuated rows of τ_j, j = 0..N−1), whose block row j only involves
/// q_{j−1}, q_j, q_{j+1}. Interleaving the unknowns per step, x_r = (p_r, λ_r) with p_r the
/// step of q_{r+1}, makes the KKT matrix block-pentadiagonal with blocks of size n + nu; it is
/// factored by a block LDLᵀ whose pivot blocks are factored by a nested Schur complement (two
/// Cholesky factorizations). From blocks of 8 (kTwoHalfMinBlock) and 8 steps the elimination
/// runs from both ends of the horizon towards two separator steps in the middle (one thread per
/// half, in the factorization and in each solve). docs/solver.md
/// ("Lagrange multipliers in O(N)", "Two halves") explains why this never breaks down when H is
/// positive definite and A has full row rank, and what the status says when it does not.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "idto/math/penta_diagonal_matrix.hpp"

namespace idto {

/// The constraint Jacobian A = ∂h/∂q of IDTO, stored by blocks: block row j (constraint h_j,
/// nu rows, j = 0..N−1) has the nonzero blocks J(j, s) = ∂h_j/∂q_s (nu × n) for
/// s ∈ {j−1, j, j+1} ∩ [1, N]. The decision variable q_s occupies the columns (s−1)·n .. s·n−1
/// and h_j the rows j·nu .. (j+1)·nu−1 (the layout of TrajectoryOptimizer's dense route).
class BlockConstraintJacobian {
 public:
  BlockConstraintJacobian() = default;
  /// N block rows, n positions per step, nu constraints per step; all blocks zero.
  BlockConstraintJacobian(int num_steps, int num_positions, int num_constraints);

  /// Changes the sizes (allocates); all blocks zero. Throws InvalidArgument on negative sizes.
  void Resize(int num_steps, int num_positions, int num_constraints);

  int num_steps() const { return num_steps_; }
  int num_positions() const { return num_positions_; }
  int num_constraints() const { return num_constraints_; }
  /// N nu.
  int rows() const { return num_steps_ * num_constraints_; }
  /// N n.
  int cols() const { return num_steps_ * num_positions_; }

  /// True when J(j, s) is a stored block: 0 <= j < N and s ∈ {j−1, j, j+1} ∩ [1, N].
  bool HasBlock(int j, int s) const {
    return j >= 0 && j < num_steps_ && s >= 1 && s <= num_steps_ && s >= j - 1 && s <= j + 1;
  }
  /// J(j, s) = ∂h_j/∂q_s (nu × n). Throws InvalidArgument when !HasBlock(j, s).
  Eigen::MatrixXd& Block(int j, int s) {
    if (!HasBlock(j, s)) ThrowNoBlock(j, s);
    return blocks_[Index(j, s)];
  }
  const Eigen::MatrixXd& Block(int j, int s) const {
    if (!HasBlock(j, s)) ThrowNoBlock(j, s);
    return blocks_[Index(j, s)];
  }

  void SetZero();
  /// Ap = A p. p: N n; Ap: N nu (resized; no allocation when already sized).
  void Multiply(const Eigen::VectorXd& p, Eigen::VectorXd* Ap) const;
  /// Atl = Aᵀ λ. lambda: N nu; Atl: N n (resized; no allocation when already sized).
  void MultiplyTranspose(const Eigen::VectorXd& lambda, Eigen::VectorXd* Atl) const;
  /// y += Aᵀ λ. lambda: N nu; y: N n (e.g. g_merit = g + Aᵀλ). Never allocates.
  void AddMultiplyTranspose(const Eigen::VectorXd& lambda, Eigen::VectorXd* y) const;
  /// The dense N nu × N n matrix (tests, the dense oracle).
  Eigen::MatrixXd MakeDense() const;

 private:
  int Index(int j, int s) const { return 3 * j + (s - j + 1); }
  [[noreturn]] void ThrowNoBlock(int j, int s) const;
  // Throws InvalidArgument naming `function` when a block is not nu x n.
  void CheckBlockShapes(const char* function) const;

  int num_steps_{0};
  int num_positions_{0};
  int num_constraints_{0};
  // Three blocks per row j, for s = j−1, j, j+1 (out-of-range ones stay zero and unused).
  std::vector<Eigen::MatrixXd> blocks_;
};

/// Outcome of BandedKktSolver::Factor. Building the message allocates; the status does not.
struct KktStatus {
  enum class Code {
    kSuccess,
    /// The Hessian part of pivot block `step` is not numerically positive definite: H itself is
    /// not (the block names the decision variable q_{step+1}, row `row` of it).
    kHessianNotPositiveDefinite,
    /// The constraints h_0..h_step are linearly dependent (to the rank tolerance): row `row` of
    /// h_step depends on the rows before it, e.g. an unactuated DoF that no q_s can influence.
    kConstraintsRankDeficient,
    kNotFactored,
  };
  Code code{Code::kNotFactored};
  /// The time step j of the failing pivot block (h_j and the decision variable q_{j+1}); −1 on
  /// success.
  int step{-1};
  /// The row within that block's Hessian part (0..n−1) or constraint part (0..nu−1); −1 on
  /// success.
  int row{-1};
  /// The pivot found, relative to its scale (≤ 0 or tiny, or NaN): for the Hessian part its
  /// diagonal entry before elimination; for the constraint part the row's squared norm (see
  /// BandedKktSolver::rank_tolerance).
  double relative_pivot{0.0};

  bool ok() const { return code == Code::kSuccess; }
  /// A sentence naming the step and the block, e.g. "KKT factorization: the constraints are
  /// rank-deficient at step j = 3 (row 1 of h_3 depends on the rows before it, relative pivot
  /// 0); an unactuated DoF that no configuration can influence?".
  std::string Message() const;
};

/// Factors and solves the IDTO KKT system in O(N (n + nu)³) time and O(N (n + nu)²) memory,
/// with no heap allocation after construction (for a fixed size; the process-wide thread pool
/// starts its worker, once, on the first two-thread Factor).
///
/// Usage: `BandedKktSolver kkt(N, n, nu); KktStatus s = kkt.Factor(H, A);
/// if (s.ok()) kkt.Solve(g, h, &p, &lambda);` H and A must stay alive and unchanged until the
/// last Solve when refinement_steps() > 0 (the residual of each refinement step reads them).
class BandedKktSolver {
 public:
  BandedKktSolver() = default;
  /// N steps, n positions per step (H's block size), nu constraints per step (nu may be 0).
  BandedKktSolver(int num_steps, int num_positions, int num_constraints);

  /// Changes the sizes (allocates). Throws InvalidArgument on negative sizes.
  void Resize(int num_steps, int num_positions, int num_constraints);

  int num_steps() const { return num_steps_; }
  int num_positions() const { return n_; }
  int num_constraints() const { return nu_; }

  /// Steps of iterative refinement against the unfactored system in Solve (default 1: on
  /// problems with entries spanning 1e-6..1e6 it takes the error from ~1e-9 to ~1e-12 for
  /// banded products and one more forward/backward sweep; a second step gains nothing,
  /// docs/solver.md).
  int refinement_steps() const { return refinement_steps_; }
  void set_refinement_steps(int steps) { refinement_steps_ = steps; }
  /// Whether the refinement's residual is accumulated in double-double arithmetic (exact
  /// products by fma, compensated sums) instead of double, with at least two refinement steps.
  /// Off (the default), the refined step is as accurate as the conditioning κ of K allows in
  /// double (κ · 1e-16: up to ~1e-6 relative on the bimanual examples); on, the refinement also
  /// removes that error: below 1e-15 relative on every example (docs/solver.md, "Accuracy"), at
  /// about 1.5–2× the KKT time.
  bool extended_residual() const { return extended_residual_; }
  void set_extended_residual(bool extended) { extended_residual_ = extended; }
  /// Without extended_residual(): when the first refinement step corrects the step by more than
  /// this (relative, max(|dp|∞ / |p|∞, |dλ|∞ / |λ|∞), or NaN), Solve adds refinement steps with
  /// the residual in double-double (see kMaxExtendedSteps). A first correction c signals a
  /// conditioning that a residual in double cannot resolve: the step then keeps an error of
  /// order c or more (up to 70 c measured on the examples). The default 1e-11 brings every
  /// example within 2e-12 of the exact step (docs/solver.md, "Accuracy"); well conditioned
  /// systems (c ~ 1e-13 or below) pay nothing. Infinity: never; 0: whenever c is not exactly 0.
  /// Throws InvalidArgument on NaN or a negative value.
  double extended_threshold() const { return extended_threshold_; }
  void set_extended_threshold(double threshold);
  /// Whether the last Solve refined with the residual in double-double (always with
  /// extended_residual() or extended_first(); otherwise when the first correction exceeded
  /// extended_threshold()).
  bool last_solve_extended() const { return last_solve_extended_; }
  /// Whether the last Solve's first refinement correction exceeded extended_threshold(), in
  /// whichever precision it was computed: the system needed the double-double residual.
  bool last_solve_needed_extended() const { return last_solve_needed_extended_; }
  /// A hint for a sequence of related systems (the minimizer's iterations, which keep their
  /// conditioning): the first refinement step takes the residual in double-double directly
  /// (then more such steps as kMaxExtendedSteps says), instead of a
  /// step in double followed by one in double-double. Saves a solve and a residual where the
  /// extended step is needed, costs the difference of the residuals where it is not. The
  /// minimizer sets it to the previous iteration's last_solve_needed_extended(), from false at
  /// the start of each cold solve (warm starts continue it, as they continue the trust radius).
  /// Default false.
  bool extended_first() const { return extended_first_; }
  void set_extended_first(bool extended_first) { extended_first_ = extended_first; }
  /// Most refinement steps with the double-double residual in one Solve (without
  /// extended_residual()): after the first, another follows while its correction c exceeds
  /// √extended_threshold(); after two or more, while c times the contraction estimated from the
  /// last two corrections exceeds extended_threshold().
  static constexpr int kMaxExtendedSteps = 5;
  /// A constraint pivot d (the squared diagonal of the Cholesky factor of −S_j, S_j the Schur
  /// complement of the constraint part of pivot block j) with d <= tolerance · s is rank
  /// deficiency, s the sum of the positive contributions to (−S_j)_ii: about the row's squared
  /// norm in the metric of H⁻¹ (default 1e-14: the row makes an angle below ~1e-7 with the span
  /// of the rows before it, in about that metric). (−S_j)_ii itself is no scale: for a dependent
  /// row it is round-off.
  double rank_tolerance() const { return rank_tolerance_; }
  void set_rank_tolerance(double tolerance) { rank_tolerance_ = tolerance; }

  /// Smallest block size n + nu factored in two halves (with N >= 8).
  static constexpr int kTwoHalfMinBlock = 8;
  /// Threads of Factor and Solve (default 1; 2 is the most they use). From a block size n + nu
  /// of kTwoHalfMinBlock and N >= 8 steps, the factorization runs from both ends of the horizon
  /// towards the middle (docs/solver.md, "Two halves"); with 2 threads the two halves are
  /// factored, and each solve's sweeps over them run, at once. The
  /// arithmetic does not depend on the thread count: results are bitwise equal for any value.
  /// A second thread that starts late costs nothing (the calling thread then factors both
  /// halves).
  int num_threads() const { return num_threads_; }
  /// Throws InvalidArgument unless 1 <= threads <= 256.
  void set_num_threads(int threads);

  /// Whether Factor and Solve run the code compiled for the block size m = n + nu (blocks of up
  /// to 8 rows; larger ones always take kernels with m at run time). Default true; false runs
  /// every size through the run-time kernels, with bit for bit the same results and status (a
  /// peer for benchmarks and tests). Takes effect at the next Factor.
  bool compiled_block_sizes() const { return compiled_block_sizes_; }
  void set_compiled_block_sizes(bool compiled) { compiled_block_sizes_ = compiled; }

  /// Factors [H Aᵀ; A 0]. H: N blocks of n × n, positive definite; A: N × N blocks of nu × n.
  /// Throws InvalidArgument on sizes that differ from the solver's, H's or A's own or any of
  /// their blocks'. Returns the status: success,
  /// or the failing step and block and why; the factors are then unusable (never NaN results:
  /// Solve on a failed factorization sets p and λ to zero). When the two-half order fails, the
  /// system is factored again in the forward order, whose status is returned.
  KktStatus Factor(const PentaDiagonalMatrix& H, const BlockConstraintJacobian& A);
  const KktStatus& status() const { return status_; }
  /// Whether the last Factor used the two-half order (false: the forward order, for small blocks,
  /// short horizons, or because the two halves failed or met a weak pivot).
  bool factored_in_two_halves() const { return split_ < num_steps_; }

  /// The solution of H p + Aᵀ λ = −g, A p = −h. g: N n; h: N nu; p: N n; lambda: N nu (outputs
  /// resized, no allocation when already sized). Requires status().ok(), else p = λ = 0.
  void Solve(const Eigen::VectorXd& g, const Eigen::VectorXd& h, Eigen::VectorXd* p,
             Eigen::VectorXd* lambda);

  /// Solve without iterative refinement: one forward and one backward sweep (relative error
  /// about κ ε, κ the system's condition number), for right-hand sides that need no more than
  /// that (the solver's constraint correction). Same sizes and status rule as Solve; leaves
  /// last_solve_needed_extended() as it was.
  void SolveUnrefined(const Eigen::VectorXd& g, const Eigen::VectorXd& h, Eigen::VectorXd* p,
                      Eigen::VectorXd* lambda);

  /// The residual of the unfactored system for a candidate (p, λ): rp = −g − H p − Aᵀλ (N n),
  /// rl = −h − A p (N nu); with extended_residual() in double-double, rounded once. Uses the H and
  /// A of the last Factor. Outputs resized.
  void Residual(const Eigen::VectorXd& g, const Eigen::VectorXd& h, const Eigen::VectorXd& p,
                const Eigen::VectorXd& lambda, Eigen::VectorXd* rp, Eigen::VectorXd* rl);

 private:
  // Scratch of one half of the factorization (each half runs on its own thread): T1 = V(r, c1)
  // of the step last eliminated, T2 = V(r, c2) (m × m); scales (m): the pivot test's scales,
  // the Hessian part's diagonal before elimination and the constraint rows' squared norms in
  // the metric of H⁻¹; the half's status.
  struct Half {
    Eigen::MatrixXd T1, T2;
    Eigen::VectorXd scales;
    KktStatus status;
    bool weak_pivot{false};  // backward half: a constraint pivot failed BackwardPivotsWellScaled
  };
  // The member templates below take the block size m = n + nu as M (M > 0: m at compile time,
  // for blocks up to 8 rows; M = 0: m_ at run time); the .cpp dispatches once per Factor and per
  // sweep pair.
  // Throws InvalidArgument when a block of H or A that Factor reads is not n x n (H) or nu x n
  // (A), naming it.
  void CheckBlockShapes(const PentaDiagonalMatrix& H, const BlockConstraintJacobian& A) const;
  // The factorization in the order of split_ (two halves when split_ < N, else forward).
  template <int M>
  KktStatus FactorInOrder();
  // Pivot block r: D_r = [P Qᵀ; Q R] (n + nu) = F_r Σ F_rᵀ with F_r = [Lp 0; Y Ls] lower
  // triangular, Σ = diag(I_n, −I_nu): P = Lp Lpᵀ, Y = Q Lp⁻ᵀ, Y Yᵀ − R = Ls Lsᵀ. In place in
  // F_[r], which holds D_r's lower triangle on entry; scales (m) as in Half. On failure, sets
  // *status and returns false.
  template <int M>
  bool FactorPivot(int r, double* scales, KktStatus* status);
  // Adds the p-part's squared column norms of Vt's constraint columns to the rank test's scales
  // (the last nu entries of scales).
  template <int M>
  void AddConstraintScale(const Eigen::MatrixXd& Vt, double* scales) const;
  // The block K(c, r) (m × m) for a neighbour c of r (|c − r| = 1 or 2): K(r, c)ᵀ.
  template <int M>
  void AssembleCoupling(int r, int c, Eigen::MatrixXd* Kt) const;
  // The elimination of step r against its second-previous step c2 (< 0: none) in the half's
  // order: *D = K(r, r)'s lower triangle (zero when !diagonal), the constraint scales zeroed;
  // *Vt2 = F_c2⁻¹ K(c2, r); *D −= Vt2ᵀ Σ Vt2. scales (m): step r's, as in Half.
  template <int M>
  void EliminateSecond(int r, int c2, bool diagonal, Eigen::MatrixXd* D, Eigen::MatrixXd* Vt2,
                       double* scales, Half* half) const;
  // Then against its previous step c1 (< 0: none): *Vt1 = F_c1⁻¹ (K(c1, r) − T1 Σ Vt2) with T1
  // = V(c1, c2) (Vt2 == nullptr: no c2); *D −= Vt1ᵀ Σ Vt1; T1 = Vt1ᵀ.
  template <int M>
  void EliminateFirst(int r, int c1, const Eigen::MatrixXd* Vt2, Eigen::MatrixXd* D,
                      Eigen::MatrixXd* Vt1, double* scales, Half* half) const;
  // Steps [0, split_) forward and their part of the separator steps split_, split_ + 1.
  template <int M>
  void FactorForwardHalf();
  // Steps [split_ + 2, N) backward (from N − 1) and their part of the separator.
  template <int M>
  void FactorBackwardHalf();
  // In the backward order step r's constraint pivots see only ∂h_r/∂q_{r+1}. True when every
  // pivot d_u (the squared diagonal of Ls) is at least kBackwardPivotRatio times row u's squared
  // norm over all three blocks of h_r in the metric of diag(H)⁻¹; a smaller one passes the rank
  // test (its scale is as small) but brings growth of order 1 / d_u (docs/solver.md).
  bool BackwardPivotsWellScaled(int r) const;
  // The separator's two pivots, from both halves' parts.
  template <int M>
  bool FactorSeparator();
  // V(r, c)ᵀ for a step c eliminated before its neighbour r.
  const Eigen::MatrixXd& Coupling(int r, int c) const;
  // Elimination order: the position of step r, and the step at position e.
  int Position(int r) const;
  int StepAt(int e) const;
  // Solves the interleaved system in place in z_ (N (n + nu)); in the two-half order each
  // sweep's halves run on one thread each.
  template <int M>
  void SolveInterleavedInPlace();
  // The steps before and after r (at most 4) into c, in the order their terms are added.
  int Neighbours(int r, int* c) const;
  // The forward substitution of the steps at elimination positions [e_begin, e_end), in order;
  // the backward one in reverse order, w (m) its scratch.
  template <int M>
  void ForwardSweep(int e_begin, int e_end);
  template <int M>
  void BackwardSweep(int e_begin, int e_end, double* w);
  void SolveOnce(const Eigen::VectorXd& g, const Eigen::VectorXd& h, Eigen::VectorXd* p,
                 Eigen::VectorXd* lambda);
  // One step of iterative refinement of (p, λ), the residual in double-double when extended.
  // Returns the relative size of the correction, max(|dp| / |p|, |dλ| / |λ|).
  double RefineOnce(const Eigen::VectorXd& g, const Eigen::VectorXd& h, bool extended,
                    Eigen::VectorXd* p, Eigen::VectorXd* lambda);
  // After `steps` double-double steps whose last correction was `correction`: more as
  // kMaxExtendedSteps says.
  void FinishExtendedRefinement(const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                                double correction, int steps, Eigen::VectorXd* p,
                                Eigen::VectorXd* lambda);
  void CalcResidual(const Eigen::VectorXd& g, const Eigen::VectorXd& h, const Eigen::VectorXd& p,
                    const Eigen::VectorXd& lambda, bool extended, Eigen::VectorXd* rp,
                    Eigen::VectorXd* rl);

  int num_steps_{0};
  int n_{0};
  int nu_{0};
  int m_{0};  // n + nu
  int refinement_steps_{1};
  int num_threads_{1};
  // Steps [0, split_) are eliminated forward, [split_ + 2, N) backward, split_ and split_ + 1
  // last; split_ = N: all forward. The last Factor's order: two_half_split_ (N for small blocks
  // or short horizons), or N when the two halves failed.
  int split_{0};
  int two_half_split_{0};
  bool compiled_block_sizes_{true};
  // The block size the last Factor dispatched on (m_, or 0: the run-time kernels), which the
  // solves use too.
  int dispatch_size_{0};
  bool extended_residual_{false};
  double extended_threshold_{1e-11};
  bool last_solve_extended_{false};
  bool last_solve_needed_extended_{false};
  bool extended_first_{false};
  double rank_tolerance_{1e-14};
  KktStatus status_;
  const PentaDiagonalMatrix* H_{nullptr};
  const BlockConstraintJacobian* A_{nullptr};

  // K = G Σ̂ Gᵀ (Σ̂ = diag(Σ, ..., Σ)) with G block lower triangular: G(r, r) = F_r and
  // G(r, c) = V(r, c) Σ for c = r−1, r−2. Vt1_[r] = V(r, r−1)ᵀ, Vt2_[r] = V(r, r−2)ᵀ (m × m).
  std::vector<Eigen::MatrixXd> Vt1_, Vt2_;
  // F_[r] (m × m lower triangular; after a successful FactorPivot its strictly upper triangle
  // mirrors the lower one, for the backward sweep's F⁻ᵀ by columns; nothing else reads it).
  std::vector<Eigen::MatrixXd> F_;
  // The separator's parts from the backward half: E_[i] (m × m) its update of D_{split_ + i},
  // Wt_[0] = V(split_, split_ + 2)ᵀ, Wt_[1] = V(split_ + 1, split_ + 3)ᵀ, Wt1_ = V(split_ + 1,
  // split_ + 2)ᵀ, C_ = −V(split_, split_ + 2) Σ V(split_ + 1, split_ + 2)ᵀ (its part of U(k + 1,
  // k)ᵀ); separator_scales_[h][i] (m): half h's part of the rank-test scales of step
  // split_ + i.
  Eigen::MatrixXd E_[2], Wt_[2], Wt1_, C_;
  Eigen::VectorXd separator_scales_[2][2];
  Half half_[2];  // forward, backward
  // 1 / F_r(i, i) for every step (N m), written by FactorPivot.
  Eigen::VectorXd inverse_diagonal_;
  const double* InverseDiagonal(int r) const {
    return inverse_diagonal_.data() + static_cast<Eigen::Index>(r) * m_;
  }
  Eigen::VectorXd z_, rp_, rl_, dp_, dl_;
  Eigen::VectorXd work_m_[2];  // m each: the backward sweep's scratch, one per half
};

}  // namespace idto
