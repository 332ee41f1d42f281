#pragma once

/// @file
/// How the transcription differentiates tau_k with respect to q_s.

namespace idto {

/// The derivative method of d tau / d q (TauDerivativeEvaluator).
enum class DerivativeMethod {
  kForwardDifferences,  ///< one perturbed evaluation per coordinate, step sqrt(eps) relative
  kCentralDifferences,  ///< two per coordinate, step sqrt(eps) relative with contact, else
                        ///< cbrt(eps)
  /// Exact: analytic RNEA derivatives plus the analytic derivative of every contact pair's
  /// forces (docs/solver.md, "Derivatives"), one evaluation per time step.
  kAnalytic
};

}  // namespace idto
