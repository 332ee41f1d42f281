// mpc::PositionFilter (the controller's estimate of q, MpcOptions::Estimator): no lag on a
// motion measured exactly (quaternions included), the predicted noise reduction, non-finite
// measurements skipped, errors that name the argument, no allocation per update; and the key
// `mpc.estimator` read from YAML (its effect in the closed loop: tests/mpc/closed_loop_test.cpp).

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/config/config.hpp"
#include "idto/config/mpc_config.hpp"
#include "idto/core/errors.hpp"
#include "idto/mpc/controller.hpp"
#include "idto/mpc/position_filter.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "support/allocation_counter.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kDt = 1e-3;

// The largest tangent distance between two configurations of `model`.
double Distance(const Model& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  Eigen::VectorXd d;
  Difference(model, a, b, &d);
  return d.lpNorm<Eigen::Infinity>();
}

TEST(PositionFilter, FollowsAConstantVelocityMotionWithoutLag) {
  // Every joint type, a floating joint at the root and one deeper: measured exactly, the
  // estimate is the motion itself at every step (the prediction carries it, the correction
  // has nothing to correct), however slow the filter.
  const Model model = test::RandomTreeModel(7);
  test::Random rng(3);
  Eigen::VectorXd q = test::RandomConfiguration(model, &rng);
  const Eigen::VectorXd v = rng.Vector(model.nv(), -2.0, 2.0);
  mpc::PositionFilter filter(model, 0.5);
  filter.Reset(q);
  Eigen::VectorXd q_est;
  for (int k = 0; k < 500; ++k) {
    Integrate(model, q, v, kDt, &q);
    filter.Update(kDt, q, v, &q_est);
    ASSERT_LT(Distance(model, q_est, q), 1e-12) << "step " << k;
  }
}

TEST(PositionFilter, ConvergesToAConstantOffsetMeasurementAtItsRate) {
  // At rest, the estimate approaches a measurement 1 cm (or 10 mrad) away exponentially with
  // time constant T: after T the remaining offset is exp(-1) of it (within the discretization).
  const Model model = test::RandomTreeModel(11);
  test::Random rng(5);
  const Eigen::VectorXd q0 = test::RandomConfiguration(model, &rng);
  const Eigen::VectorXd dv = Eigen::VectorXd::Constant(model.nv(), 0.01);
  Eigen::VectorXd q1;
  Integrate(model, q0, dv, 1.0, &q1);
  const double T = 0.03;
  mpc::PositionFilter filter(model, T);
  filter.Reset(q0);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv());
  Eigen::VectorXd q_est;
  for (int k = 0; k < 30; ++k) filter.Update(kDt, q1, zero, &q_est);
  EXPECT_NEAR(Distance(model, q1, q_est), 0.01 * std::exp(-1.0), 1e-9);
}

TEST(PositionFilter, ReducesWhiteNoiseByThePredictedFactor) {
  // White noise of standard deviation sigma on every position at rest: the estimate's error has
  // standard deviation sigma sqrt(alpha / (2 - alpha)), alpha = 1 - exp(-dt / T) (the
  // stationary variance of x <- (1 - alpha) x + alpha n); 0.13 sigma for T = 30 ms. Without the
  // filter the error is sigma. 20,000 updates: the sample estimate is within a few percent.
  const Model model = test::Pendulum();
  const double sigma = 1e-3, T = 0.03;
  const double alpha = 1.0 - std::exp(-kDt / T);
  mpc::PositionFilter filter(model, T);
  test::Random rng(9);
  const Eigen::VectorXd q_true = Eigen::VectorXd::Constant(1, 0.3);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1);
  filter.Reset(q_true);
  Eigen::VectorXd q_hat(1), q_est;
  double sum2 = 0.0;
  const int n = 20000;
  for (int k = 0; k < n + 1000; ++k) {
    q_hat(0) = q_true(0) + sigma * rng.Normal();
    filter.Update(kDt, q_hat, zero, &q_est);
    if (k >= 1000) sum2 += (q_est(0) - q_true(0)) * (q_est(0) - q_true(0));
  }
  const double predicted = sigma * std::sqrt(alpha / (2.0 - alpha));
  EXPECT_NEAR(std::sqrt(sum2 / n), predicted, 0.1 * predicted);
  EXPECT_LT(predicted, 0.14 * sigma);
}

TEST(PositionFilter, SkipsNonFiniteMeasurementsAndStaysFinite) {
  const Model model = test::RandomTreeModel(13);
  test::Random rng(1);
  const Eigen::VectorXd q0 = test::RandomConfiguration(model, &rng);
  const Eigen::VectorXd v = rng.Vector(model.nv());
  mpc::PositionFilter filter(model, 0.02);
  filter.Reset(q0);
  // A non-finite position: the estimate is the prediction alone.
  Eigen::VectorXd q_bad = q0;
  q_bad(0) = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd predicted, q_est;
  Integrate(model, q0, v, kDt, &predicted);
  filter.Update(kDt, q_bad, v, &q_est);
  EXPECT_TRUE(q_est.allFinite());
  EXPECT_LT(Distance(model, q_est, predicted), 1e-15);
  // A non-finite velocity: no prediction, only the correction towards the (finite) measurement.
  Eigen::VectorXd v_bad = v;
  v_bad(model.nv() - 1) = std::numeric_limits<double>::infinity();
  const Eigen::VectorXd before = filter.estimate();
  filter.Update(kDt, q0, v_bad, &q_est);
  EXPECT_TRUE(q_est.allFinite());
  EXPECT_LT(Distance(model, q_est, q0), Distance(model, before, q0));
}

TEST(PositionFilter, UpdatesInPlaceWithoutAllocating) {
  const Model model = test::RandomTreeModel(17);
  test::Random rng(2);
  Eigen::VectorXd q = test::RandomConfiguration(model, &rng);
  const Eigen::VectorXd v = rng.Vector(model.nv());
  mpc::PositionFilter filter(model, 0.03);
  filter.Reset(q);
  filter.Update(kDt, q, v, &q);  // q_hat and the output may be the same vector
  EXPECT_LT(Distance(model, q, filter.estimate()), 1e-300);
  if (test::AllocationCountingAvailable()) {
    test::ScopedAllocationCounter counter;
    for (int k = 0; k < 10; ++k) filter.Update(kDt, q, v, &q);
    EXPECT_EQ(counter.count(), 0);
  }
}

TEST(PositionFilter, ErrorsNameTheArgument) {
  const Model model = test::Pendulum();
  const auto throws = [](const std::string& argument, const std::string& found) {
    return ThrowsMessage<InvalidArgument>(AllOf(HasSubstr(argument), HasSubstr(found)));
  };
  EXPECT_THAT([&] { mpc::PositionFilter(model, 0.0); }, throws("time_constant", "0"));
  EXPECT_THAT([&] { mpc::PositionFilter(model, std::nan("")); }, throws("time_constant", "nan"));
  mpc::PositionFilter filter(model, 0.03);
  const Eigen::VectorXd one = Eigen::VectorXd::Zero(1), two = Eigen::VectorXd::Zero(2);
  Eigen::VectorXd out;
  EXPECT_THAT([&] { filter.Update(kDt, one, one, &out); }, throws("Reset", "without an estimate"));
  EXPECT_THAT([&] { filter.Reset(two); }, throws("q", "2"));
  EXPECT_THAT([&] { filter.Reset(Eigen::VectorXd::Constant(1, INFINITY)); }, throws("q(0)", "inf"));
  filter.Reset(one);
  EXPECT_THAT([&] { filter.Update(-kDt, one, one, &out); }, throws("dt", "-0.001"));
  EXPECT_THAT([&] { filter.Update(kDt, two, one, &out); }, throws("q_hat", "2"));
  EXPECT_THAT([&] { filter.Update(kDt, one, two, &out); }, throws("v_hat", "2"));
  mpc::MpcOptions options;
  options.estimator.position_time_constant = -1.0;
  EXPECT_THAT([&] { options.Validate(model); }, throws("estimator.position_time_constant", "-1"));
}

TEST(PositionFilter, YamlKeyAndErrors) {
  const std::string path = std::string(IDTO_SOURCE_DIR) + "/examples/allegro/allegro.yaml";
  const ExampleConfig allegro = LoadExampleConfig(path, {IDTO_SOURCE_DIR});
  EXPECT_DOUBLE_EQ(ParseMpcConfig(allegro).controller.estimator.position_time_constant, 0.1);
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string key = "estimator: {position_time_constant: 0.1}";
  ASSERT_NE(text.find(key), std::string::npos);
  const auto load_with = [&](const std::string& to) {
    std::string t = text;
    t.replace(t.find(key), key.size(), to);
    const std::string file = ::testing::TempDir() + "/allegro_estimator.yaml";
    std::ofstream(file) << t;
    return ParseMpcConfig(LoadExampleConfig(file, {IDTO_SOURCE_DIR}));
  };
  EXPECT_DOUBLE_EQ(load_with("estimator: {}").controller.estimator.position_time_constant, 0.0);
  EXPECT_THAT([&] { load_with("estimator: {position_time_constant: -0.1}"); },
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("mpc.estimator.position_time_constant"), HasSubstr("-0.1"))));
  EXPECT_THAT([&] { load_with("estimator: {time_constant: 0.1}"); },
              ThrowsMessage<FileError>(HasSubstr("time_constant")));
}

}  // namespace
}  // namespace idto
