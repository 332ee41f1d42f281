#include "idto/solver/solver_summary.hpp"

#include <cstdio>
#include <sstream>

namespace idto {

std::string TerminationTypeName(TerminationType type) {
  switch (type) {
    case TerminationType::kConverged:
      return "converged";
    case TerminationType::kMaxIterations:
      return "max_iterations";
    case TerminationType::kFailure:
      return "failure";
    case TerminationType::kUserTermination:
      return "user";
    case TerminationType::kUserAbort:
      return "user_abort";
  }
  return "unknown";
}

namespace {

const char* StepName(DoglegStep s) {
  switch (s) {
    case DoglegStep::kNewton:
      return "newton";
    case DoglegStep::kCauchy:
      return "cauchy";
    case DoglegStep::kDogleg:
      return "dogleg";
    case DoglegStep::kNone:
      return "none";
  }
  return "none";
}

}  // namespace

double SolverSummary::mean_iteration_time() const {
  if (log.empty()) return 0.0;
  double t = 0.0;
  for (const IterationSummary& s : log) t += s.time_total;
  return t / static_cast<double>(log.size());
}

std::string SolverSummary::BriefReport() const {
  char line[512];
  std::snprintf(line, sizeof(line),
                "idto: %s after %d iterations, cost %.6e -> %.6e, constraint violation %.3e, "
                "%.3f s (%.3f ms/iteration)%s%s",
                TerminationTypeName(termination).c_str(), iterations, initial_cost, final_cost,
                constraint_violation, solve_time, 1e3 * mean_iteration_time(),
                message.empty() ? "" : ": ", message.c_str());
  return line;
}

std::string SolverSummary::FullReport() const {
  std::ostringstream out;
  out << " iter        cost       merit      |g|       |p|    radius       rho  acc  step    "
         "violation     ms\n";
  IterationSummary total;
  for (const IterationSummary& s : log) {
    char line[256];
    std::snprintf(line, sizeof(line),
                  "%5d %11.4e %11.4e %9.2e %9.2e %9.2e %9.2e  %3s  %-6s %10.3e %7.3f\n",
                  s.iteration, s.cost, s.merit, s.gradient_norm, s.step_norm, s.trust_radius,
                  s.ratio, s.accepted ? "yes" : (s.growth_guard ? "grd" : "no"),
                  StepName(s.step_type), s.constraint_violation, 1e3 * s.time_total);
    out << line;
    total.time_derivatives += s.time_derivatives;
    total.time_cost += s.time_cost;
    total.time_hessian += s.time_hessian;
    total.time_factorization += s.time_factorization;
    total.time_multipliers += s.time_multipliers;
    total.time_total += s.time_total;
    total.time_contact += s.time_contact;
  }
  char line[512];
  std::snprintf(line, sizeof(line),
                "time: derivatives %.4f s, cost %.4f s, hessian %.4f s, factorization %.4f s, "
                "multipliers %.4f s, total %.4f s\n"
                "      contact evaluation %.4f s (within derivatives and cost; CPU time summed "
                "over threads)\n",
                total.time_derivatives, total.time_cost, total.time_hessian,
                total.time_factorization, total.time_multipliers, total.time_total,
                total.time_contact);
  out << line << BriefReport() << "\n";
  return out.str();
}

std::string SolverSummary::ToCsv() const {
  std::ostringstream out;
  out.precision(17);
  out << "iteration,cost,merit,gradient_norm,step_norm,scaled_step_norm,trust_radius,ratio,"
         "accepted,step_type,constraint_violation,trial_cost,regularization,time_derivatives,time_"
         "cost,"
         "time_hessian,time_factorization,time_multipliers,time_total,time_contact,correction_"
         "norm,growth_guard\n";
  for (const IterationSummary& s : log) {
    out << s.iteration << ',' << s.cost << ',' << s.merit << ',' << s.gradient_norm << ','
        << s.step_norm << ',' << s.scaled_step_norm << ',' << s.trust_radius << ',' << s.ratio
        << ',' << (s.accepted ? 1 : 0) << ',' << StepName(s.step_type) << ','
        << s.constraint_violation << ',' << s.trial_cost << ',' << s.regularization << ','
        << s.time_derivatives << ',' << s.time_cost << ',' << s.time_hessian << ','
        << s.time_factorization << ',' << s.time_multipliers << ',' << s.time_total << ','
        << s.time_contact << ',' << s.correction_norm << ',' << (s.growth_guard ? 1 : 0) << '\n';
  }
  return out.str();
}

}  // namespace idto
