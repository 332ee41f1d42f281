#include "idto/problem/problem_definition.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <unistd.h>
#include <string>

#include "idto/core/errors.hpp"

namespace idto {

namespace {

constexpr const char* kWhere = "ProblemDefinition";

void CheckVector(const std::string& name, const Eigen::VectorXd& x, int size,
                 const char* size_name) {
  CheckSize(kWhere, name, x.size(), size, size_name);
  CheckFinite(kWhere, name, x);
}

void CheckWeights(const std::string& name, const Eigen::VectorXd& w, int size,
                  const char* size_name) {
  CheckSize(kWhere, name, w.size(), size, size_name);
  CheckNonNegative(kWhere, name, w);
}

}  // namespace

namespace {

void CheckLimitWeight(const char* name, double w) {
  if (!(std::isfinite(w) && w >= 0.0)) {
    ThrowInvalidArgument(kWhere, std::string("limits.") + name, FormatValue(w),
                         "a finite number >= 0");
  }
}

// Bounds may be infinite (no limit) but not NaN; sizes as the model's.
void CheckBounds(const std::string& name, const Eigen::VectorXd& x, int size, bool non_negative) {
  if (x.size() == 0) return;
  if (x.size() != size) {
    ThrowInvalidArgument(kWhere, "limits." + name, std::to_string(x.size()) + " entries",
                         std::to_string(size) + " entries (or none: the model's limits)");
  }
  for (int i = 0; i < size; ++i) {
    if (std::isnan(x(i)) || (non_negative && x(i) < 0.0)) {
      ThrowInvalidArgument(kWhere, "limits." + name + "[" + std::to_string(i) + "]",
                           FormatValue(x(i)),
                           non_negative ? "a number >= 0 (inf: no limit)" : "a number (or inf)");
    }
  }
}

// The solver keeps per step about a dozen nv x nq blocks (velocity partials, the three d tau
// blocks, mass matrix, Hessian and KKT blocks) and the trajectory: refuse horizons whose
// working set exceeds the machine's memory, naming num_steps and the estimate.
void CheckMemory(const Model& model, int num_steps) {
  const double nq = model.nq(), nv = model.nv();
  const double per_step = 8.0 * (12.0 * nv * nq + 4.0 * nq * nq + 20.0 * (nq + nv));
  const double estimate = per_step * (num_steps + 1.0);
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  const double physical =
      pages > 0 && page_size > 0 ? static_cast<double>(pages) * page_size : 64.0 * (1 << 30);
  if (estimate > physical) {
    std::ostringstream found, expected;
    found << num_steps << " (about " << estimate / (1 << 30) << " GiB of solver memory)";
    expected << "at most " << static_cast<long long>(physical / per_step) - 1
             << " for this model on this machine (" << physical / (1 << 30) << " GiB)";
    ThrowInvalidArgument(kWhere, "num_steps", found.str(), expected.str());
  }
}

void ValidateLimits(const Model& model, const LimitPenalties& l) {
  CheckLimitWeight("position_weight", l.position_weight);
  CheckLimitWeight("velocity_weight", l.velocity_weight);
  CheckLimitWeight("effort_weight", l.effort_weight);
  CheckBounds("q_lower", l.q_lower, model.nq(), false);
  CheckBounds("q_upper", l.q_upper, model.nq(), false);
  CheckBounds("v_max", l.v_max, model.nv(), true);
  CheckBounds("tau_max", l.tau_max, model.nv(), true);
  const Eigen::VectorXd& lo = l.q_lower.size() ? l.q_lower : model.position_lower_limits();
  const Eigen::VectorXd& hi = l.q_upper.size() ? l.q_upper : model.position_upper_limits();
  for (int i = 0; i < model.nq(); ++i) {
    if (lo(i) > hi(i)) {
      ThrowInvalidArgument(kWhere, "limits.q_lower[" + std::to_string(i) + "]", FormatValue(lo(i)),
                           "at most q_upper[" + std::to_string(i) + "] = " + FormatValue(hi(i)));
    }
  }
}

}  // namespace

void ProblemDefinition::Validate(const Model& model) const {
  CheckPositive(kWhere, "time_step", time_step);
  if (num_steps < 1) {
    ThrowInvalidArgument(kWhere, "num_steps", std::to_string(num_steps), "at least 1");
  }
  CheckMemory(model, num_steps);
  const int nq = model.nq(), nv = model.nv();
  CheckVector("q_init", q_init, nq, "model.nq()");
  CheckVector("v_init", v_init, nv, "model.nv()");
  for (JointIndex j : model.floating_joints()) {
    if (q_init.segment<4>(model.position_start(j)).norm() < 1e-12) {
      ThrowInvalidArgument(kWhere, "q_init quaternion of joint \"" + model.joint_name(j) + "\"",
                           "zero", "a non-zero quaternion");
    }
  }
  const size_t expected = static_cast<size_t>(num_steps) + 1;
  if (q_nom.size() != expected) {
    ThrowInvalidArgument(kWhere, "q_nom", std::to_string(q_nom.size()) + " entries",
                         std::to_string(expected) + " entries (num_steps + 1)");
  }
  if (v_nom.size() != expected) {
    ThrowInvalidArgument(kWhere, "v_nom", std::to_string(v_nom.size()) + " entries",
                         std::to_string(expected) + " entries (num_steps + 1)");
  }
  for (size_t k = 0; k < expected; ++k) {
    CheckVector("q_nom[" + std::to_string(k) + "]", q_nom[k], nq, "model.nq()");
    CheckVector("v_nom[" + std::to_string(k) + "]", v_nom[k], nv, "model.nv()");
  }
  CheckWeights("Qq", Qq, nq, "model.nq()");
  CheckWeights("Qv", Qv, nv, "model.nv()");
  CheckWeights("R", R, nv, "model.nv()");
  CheckWeights("Qfq", Qfq, nq, "model.nq()");
  CheckWeights("Qfv", Qfv, nv, "model.nv()");
  if (unactuated_dofs) {
    for (size_t i = 0; i < unactuated_dofs->size(); ++i) {
      const int d = (*unactuated_dofs)[i];
      if (d < 0 || d >= nv) {
        ThrowInvalidArgument(kWhere, "unactuated_dofs[" + std::to_string(i) + "]",
                             std::to_string(d),
                             "a velocity index in [0, " + std::to_string(nv) + ")");
      }
    }
  }
  contact.parameters.Validate("ProblemDefinition: contact.parameters");
  ValidateLimits(model, limits);
}

std::vector<int> ProblemDefinition::UnactuatedDofs(const Model& model) const {
  std::vector<int> dofs;
  if (unactuated_dofs) {
    dofs = *unactuated_dofs;
  } else {
    for (int i = 0; i < model.nv(); ++i) {
      if (model.is_base_velocity()[i]) dofs.push_back(i);
    }
  }
  std::sort(dofs.begin(), dofs.end());
  dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
  return dofs;
}

ProblemDefinition ProblemDefinition::MakeDefault(const Model& model, double time_step,
                                                 int num_steps) {
  ProblemDefinition p;
  p.time_step = time_step;
  p.num_steps = num_steps;
  p.q_init = model.NeutralConfiguration();
  p.v_init = Eigen::VectorXd::Zero(model.nv());
  p.Qq = Eigen::VectorXd::Zero(model.nq());
  p.Qfq = Eigen::VectorXd::Zero(model.nq());
  p.Qv = Eigen::VectorXd::Zero(model.nv());
  p.Qfv = Eigen::VectorXd::Zero(model.nv());
  p.R = Eigen::VectorXd::Zero(model.nv());
  p.SetConstantNominal(p.q_init, p.v_init);
  return p;
}

void ProblemDefinition::SetConstantNominal(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  q_nom.assign(std::max(num_steps, 0) + 1, q);
  v_nom.assign(std::max(num_steps, 0) + 1, v);
}

}  // namespace idto
