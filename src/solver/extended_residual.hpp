#pragma once

// The KKT residual in double-double arithmetic (BandedKktSolver's extended refinement step),
// with the exact product split by an fma instruction where the CPU has one and by Dekker's
// product otherwise. Both splits are exact, so the result is bitwise the same either way.

#include <Eigen/Core>

#include "idto/math/penta_diagonal_matrix.hpp"
#include "idto/solver/banded_kkt.hpp"

namespace idto::internal {

/// How ExtendedKktResidual splits each product exactly.
enum class ProductSplit {
  kAuto,            ///< an fma instruction if the CPU has one (checked once), else Dekker's
  kFmaInstruction,  ///< requires CpuHasFma()
  kDekker,          ///< Dekker's product with Veltkamp's splitting (any IEEE double machine)
};

/// Whether the CPU running this process executes fma instructions (x86-64: cpuid; false on
/// other targets, where the kernel is compiled for the build's own instruction set).
bool CpuHasFma();

/// Steps [begin, end) of rp = −g − H p − Aᵀλ (N n) and rl = −h − A p (N nu), each entry
/// accumulated in double-double (exact products, TwoSum) and rounded once: rp's and rl's
/// segments of those steps, which depend on no other step's output (disjoint ranges may run on
/// separate threads). Outputs must be sized. No allocation.
void ExtendedKktResidual(const PentaDiagonalMatrix& H, const BlockConstraintJacobian& A,
                         const Eigen::VectorXd& g, const Eigen::VectorXd& h,
                         const Eigen::VectorXd& p, const Eigen::VectorXd& lambda, int begin,
                         int end, Eigen::VectorXd* rp, Eigen::VectorXd* rl,
                         ProductSplit split = ProductSplit::kAuto);

}  // namespace idto::internal
