#pragma once

// Helpers shared by the plants (not installed).

#include <cmath>
#include <string>

#include <Eigen/Core>

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/multibody/model.hpp"

namespace idto::sim::internal {

/// The plant's clock in whole steps of size h. Advance(duration) adds to the requested time and
/// returns the number of steps that bring the clock to the step nearest to it, so that the
/// clock stays within half a step of the sum of the requested durations whatever they are
/// (e.g. a 1/60 s control period on 1 ms steps: 17, 17, 16, 17, 17, 16, ... steps).
class StepClock {
 public:
  explicit StepClock(double h) : h_(h) {}

  void Reset() {
    steps_ = 0;
    requested_ = 0.0;
  }

  long Advance(const char* where, double duration) {
    CheckNonNegative(where, "duration", duration);
    requested_ += duration;
    const long target = std::lround(requested_ / h_);
    return target > steps_ ? target - steps_ : 0;
  }

  void CountStep() { ++steps_; }
  double time() const { return static_cast<double>(steps_) * h_; }

 private:
  double h_;
  long steps_{0};
  double requested_{0.0};
};

/// Checks Plant::Advance's disturbance arguments: body -1 (none) or a body index, finite force.
inline void CheckDisturbance(const char* where, const Model& model, int disturbed_body,
                             const Eigen::Vector3d& f_ext_W) {
  if (disturbed_body < -1 || disturbed_body >= model.num_bodies()) {
    ThrowInvalidArgument(
        where, "disturbed_body", std::to_string(disturbed_body),
        "-1 (none) or a body index in [0, " + std::to_string(model.num_bodies()) + ")");
  }
  CheckFinite(where, "f_ext_W", f_ext_W);
}

/// Checks Plant::Advance's arguments: u (nv, finite) and the disturbance (CheckDisturbance).
inline void CheckAdvanceArguments(const char* where, const Model& model, const Eigen::VectorXd& u,
                                  int disturbed_body, const Eigen::Vector3d& f_ext_W) {
  CheckDisturbance(where, model, disturbed_body, f_ext_W);
  model.CheckVelocity(where, "u", u);
  CheckFinite(where, "u", u);
}

/// Checks Plant::Reset's state (q: nq entries, a valid configuration; v: nv; both finite) and
/// sets *q_out to q with its quaternions normalized.
inline void CheckResetState(const char* where, const Model& model, const Eigen::VectorXd& q,
                            const Eigen::VectorXd& v, Eigen::VectorXd* q_out) {
  model.CheckConfiguration(where, "q", q);
  model.CheckVelocity(where, "v", v);
  CheckFinite(where, "q", q);
  CheckFinite(where, "v", v);
  *q_out = q;
  NormalizeQuaternions(model, q_out);
}

/// Checks Plant::SetExtraDamping's argument: nv entries, finite, >= 0, zero on multi-DoF joints.
inline void CheckExtraDamping(const char* where, const Model& model, const Eigen::VectorXd& d) {
  CheckSize(where, "d", d.size(), model.nv(), "model.nv()");
  CheckFinite(where, "d", d);
  CheckNonNegative(where, "d", d);
  for (int i = 0; i < model.nv(); ++i) {
    if (d(i) == 0.0) continue;
    const JointIndex j = model.GetJointIndex(model.velocity_name(i));
    if (model.joint_nv(j) != 1) {
      ThrowInvalidArgument(where, "d(" + std::to_string(i) + ")",
                           FormatValue(d(i)) + " on joint \"" + model.joint_name(j) + "\"",
                           "0 on the DoFs of multi-DoF joints");
    }
  }
}

}  // namespace idto::sim::internal
