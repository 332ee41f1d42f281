#pragma once

/// @file
/// A complementary filter on measured positions: the controller's estimate of q from a stream
/// of noisy position measurements and the measured velocities (MpcOptions::estimator).

#include <Eigen/Core>

#include "idto/multibody/model.hpp"

namespace idto::mpc {

/// Estimates q from measurements (q_hat, v_hat) taken dt apart. Each update predicts with the
/// measured velocity, q_pred = q_est "+" v_hat dt (Integrate: exact on quaternions), and moves
/// the prediction towards the measured positions by the fraction alpha = 1 - exp(-dt / T) of
/// their difference (Difference: the shortest rotation on quaternions). A constant-velocity
/// motion measured exactly is followed without lag; white position noise of standard deviation
/// sigma at every update leaves sigma sqrt(alpha / (2 - alpha)) (0.13 sigma for dt = 1 ms,
/// T = 30 ms). Non-finite measurements are not used: a v_hat with a non-finite entry skips the
/// prediction, a q_hat with one the correction, so the estimate stays finite. Not thread-safe;
/// Update allocates nothing.
class PositionFilter {
 public:
  /// time_constant: T in s (finite, > 0). Throws InvalidArgument otherwise.
  PositionFilter(const Model& model, double time_constant);

  /// Starts the estimate at q (nq, finite). Throws InvalidArgument for a wrong size or a
  /// non-finite entry.
  void Reset(const Eigen::VectorXd& q);

  /// One measurement dt (s, finite, > 0) after the previous one (or the Reset): q_hat (nq) and
  /// v_hat (nv). Writes the estimate to *q (nq; may be q_hat itself). Throws InvalidArgument for
  /// wrong sizes, a bad dt, or an update before Reset.
  void Update(double dt, const Eigen::VectorXd& q_hat, const Eigen::VectorXd& v_hat,
              Eigen::VectorXd* q);

  /// The estimate (nq); empty before Reset.
  const Eigen::VectorXd& estimate() const { return q_est_; }
  double time_constant() const { return time_constant_; }

 private:
  const Model& model_;
  double time_constant_;
  Eigen::VectorXd q_est_;   // nq: the estimate (Reset, Update)
  Eigen::VectorXd v_step_;  // nv: scratch, the correction's tangent step (Update)
};

}  // namespace idto::mpc
