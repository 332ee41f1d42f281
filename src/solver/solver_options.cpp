#include "idto/solver/solver_options.hpp"

#include "idto/solver/solver_summary.hpp"

#include <cmath>
#include <sstream>

#include "core/parallel.hpp"

namespace idto {

static_assert(SolverOptions::kMaxNumThreads == kMaxParallelThreads,
              "SolverOptions::kMaxNumThreads is ParallelFor's limit");

std::string ConstraintMethodName(ConstraintMethod method) {
  switch (method) {
    case ConstraintMethod::kNone:
      return "none";
    case ConstraintMethod::kPenalty:
      return "penalty";
    case ConstraintMethod::kLagrangeMultipliers:
      return "lagrange";
  }
  return "unknown";
}

namespace {
// 4 GiB of iteration log.
constexpr double kMaxLogBytes = 4.0 * (1 << 30);
}  // namespace

bool SolverOptions::IsValid(std::string* why) const {
  std::ostringstream out;
  auto fail = [&](const char* field, double value, const char* expected) {
    out << "SolverOptions: " << field << " is " << value << "; expected " << expected;
    if (why != nullptr) *why = out.str();
    return false;
  };
  if (max_iterations < 0) return fail("max_iterations", max_iterations, "a number >= 0");
  // Every iteration adds an IterationSummary to SolverSummary::log: refuse counts whose log alone
  // could not fit in memory (instead of a bare std::bad_alloc hours into a run).
  if (static_cast<double>(max_iterations) * sizeof(IterationSummary) > kMaxLogBytes) {
    out << "SolverOptions: max_iterations is " << max_iterations << "; expected at most "
        << static_cast<long long>(kMaxLogBytes / sizeof(IterationSummary))
        << " (the iteration log would need "
        << static_cast<double>(max_iterations) * sizeof(IterationSummary) / (1 << 30) << " GiB)";
    if (why != nullptr) *why = out.str();
    return false;
  }
  if (num_threads < 1 || num_threads > kMaxNumThreads) {
    return fail("num_threads", num_threads, "in [1, 256] (SolverOptions::kMaxNumThreads)");
  }
  if (!(std::isfinite(penalty_weight) && penalty_weight >= 0)) {
    return fail("penalty_weight", penalty_weight, "a finite number >= 0");
  }
  if (!(std::isfinite(finite_difference_step) && finite_difference_step >= 0 &&
        finite_difference_step < 1)) {
    return fail("finite_difference_step", finite_difference_step, "in [0, 1) (0: automatic)");
  }
  if (!(std::isfinite(initial_trust_radius) && initial_trust_radius > 0)) {
    return fail("initial_trust_radius", initial_trust_radius, "a finite number > 0");
  }
  if (!(std::isfinite(max_trust_radius) && max_trust_radius >= initial_trust_radius)) {
    return fail("max_trust_radius", max_trust_radius, "a finite number >= initial_trust_radius");
  }
  if (!(acceptance_ratio >= 0 && acceptance_ratio < 0.25)) {
    return fail("acceptance_ratio", acceptance_ratio, "in [0, 0.25)");
  }
  if (!(constraint_correction >= 0 && constraint_correction <= 10)) {
    return fail("constraint_correction", constraint_correction, "in [0, 10] (0: none)");
  }
  if (!(kkt_extended_threshold >= 0)) {
    return fail("kkt_extended_threshold", kkt_extended_threshold, ">= 0 (infinity: never)");
  }
  if (!(cost_tolerance >= 0)) return fail("cost_tolerance", cost_tolerance, ">= 0");
  if (!(gradient_tolerance >= 0)) return fail("gradient_tolerance", gradient_tolerance, ">= 0");
  if (!(step_tolerance >= 0)) return fail("step_tolerance", step_tolerance, ">= 0");
  if (why != nullptr) why->clear();
  return true;
}

}  // namespace idto
