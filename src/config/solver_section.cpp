// The `solver` section (SolverOptions fields) and `mpc.solver` (the controller's options).

#include <string>
#include <vector>

#include "config_loader.hpp"

namespace idto::config_internal {

namespace {

const std::vector<std::string> kSolverKeys = {"max_iterations",
                                              "num_threads",
                                              "constraint_method",
                                              "penalty_weight",
                                              "derivative_method",
                                              "finite_difference_step",
                                              "scaling",
                                              "initial_trust_radius",
                                              "max_trust_radius",
                                              "acceptance_ratio",
                                              "cost_tolerance",
                                              "gradient_tolerance",
                                              "step_tolerance",
                                              "fixed_iterations",
                                              "trial_derivatives",
                                              "verbosity",
                                              "kkt_extended_residual",
                                              "kkt_extended_threshold",
                                              "constraint_correction"};

static_assert(static_cast<int>(ConstraintMethod::kNone) == 0 &&
                  static_cast<int>(ConstraintMethod::kPenalty) == 1 &&
                  static_cast<int>(ConstraintMethod::kLagrangeMultipliers) == 2,
              "ConstraintMethod order");
static_assert(static_cast<int>(DerivativeMethod::kForwardDifferences) == 0 &&
                  static_cast<int>(DerivativeMethod::kCentralDifferences) == 1 &&
                  static_cast<int>(DerivativeMethod::kAnalytic) == 2,
              "DerivativeMethod order");
static_assert(static_cast<int>(ScalingMethod::kNone) == 0 &&
                  static_cast<int>(ScalingMethod::kSqrt) == 1 &&
                  static_cast<int>(ScalingMethod::kDoubleSqrt) == 2,
              "ScalingMethod order");

}  // namespace

// The keys present, over the values already in config_.solver (the defaults, or for
// mpc.solver the open loop's).
void ConfigLoader::LoadSolver(const YAML::Node& node, const std::string& path) {
  const MapReader s(reader_, node, path, kSolverKeys);
  SolverOptions& o = config_.solver;
  o.max_iterations = s.Int("max_iterations", o.max_iterations, 0);
  o.num_threads = s.Int("num_threads", o.num_threads, 1);
  o.constraint_method = static_cast<ConstraintMethod>(s.Enum(
      "constraint_method", {"none", "penalty", "lagrange"}, static_cast<int>(o.constraint_method)));
  o.penalty_weight = s.NonNegative("penalty_weight", o.penalty_weight);
  o.derivative_method =
      static_cast<DerivativeMethod>(s.Enum("derivative_method", {"forward", "central", "analytic"},
                                           static_cast<int>(o.derivative_method)));
  o.finite_difference_step = s.NonNegative("finite_difference_step", o.finite_difference_step);
  o.scaling = static_cast<ScalingMethod>(
      s.Enum("scaling", {"none", "sqrt", "double_sqrt"}, static_cast<int>(o.scaling)));
  o.initial_trust_radius = s.Positive("initial_trust_radius", o.initial_trust_radius);
  o.max_trust_radius = s.Positive("max_trust_radius", o.max_trust_radius);
  o.acceptance_ratio = s.NonNegative("acceptance_ratio", o.acceptance_ratio);
  o.constraint_correction = s.NonNegative("constraint_correction", o.constraint_correction);
  o.cost_tolerance = s.NonNegative("cost_tolerance", o.cost_tolerance);
  o.gradient_tolerance = s.NonNegative("gradient_tolerance", o.gradient_tolerance);
  o.step_tolerance = s.NonNegative("step_tolerance", o.step_tolerance);
  o.fixed_iterations = s.Bool("fixed_iterations", o.fixed_iterations);
  o.trial_derivatives = s.Bool("trial_derivatives", o.trial_derivatives);
  o.kkt_extended_residual = s.Bool("kkt_extended_residual", o.kkt_extended_residual);
  o.kkt_extended_threshold = s.NonNegative("kkt_extended_threshold", o.kkt_extended_threshold);
  o.verbosity = s.Int("verbosity", o.verbosity, 0);
  std::string why;
  if (!o.IsValid(&why)) reader_.Fail(s.node(), s.path(), "invalid options: " + why);
}

}  // namespace idto::config_internal
