// Campaigns (examples/campaign, idto-campaign) and the closed-loop conditions they use (sensor
// noise, latency jitter, late re-plans): a small fixed-seed spinner campaign is reproducible bit
// for bit, different seeds draw different conditions, shards merge into the campaign, the
// Wilson interval matches published values, and the plant's mass-scaled model is the model
// itself at scale 1. (The command line: idto_campaign.* in examples/CMakeLists.txt.)

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Core>

#include "campaign/campaign.hpp"
#include "campaign/campaign_report.hpp"
#include "core/parallel.hpp"
#include "examples/example_test_support.hpp"
#include "idto/config/config.hpp"
#include "idto/config/mpc_config.hpp"
#include "idto/core/errors.hpp"
#include "idto/mpc/closed_loop.hpp"
#include "idto/mpc/controller.hpp"
#include "idto/sim/plant.hpp"

namespace idto {
namespace {

using test::kShareDirs;
using test::LoadExample;

using ::testing::HasSubstr;

TEST(Campaign, WilsonIntervalMatchesPublishedValues) {
  // Tables of the Wilson score interval at 95% (e.g. Newcombe 1998, Table I; Brown, Cai and
  // DasGupta 2001): 0/10 -> [0, 0.2775], 5/10 -> [0.2366, 0.7634], 10/10 -> [0.7225, 1].
  campaign::Interval i = campaign::WilsonInterval(0, 10);
  EXPECT_NEAR(i.low, 0.0, 1e-12);
  EXPECT_NEAR(i.high, 0.2775, 1e-4);
  i = campaign::WilsonInterval(5, 10);
  EXPECT_NEAR(i.low, 0.2366, 1e-4);
  EXPECT_NEAR(i.high, 0.7634, 1e-4);
  i = campaign::WilsonInterval(10, 10);
  EXPECT_NEAR(i.low, 0.7225, 1e-4);
  EXPECT_NEAR(i.high, 1.0, 1e-12);
  // 45 of 50: the interval is not symmetric about 0.9 (a normal interval would reach 0.983).
  i = campaign::WilsonInterval(45, 50);
  EXPECT_NEAR(i.low, 0.7864, 1e-4);
  EXPECT_NEAR(i.high, 0.9565, 1e-4);
  EXPECT_THROW(campaign::WilsonInterval(3, 2), std::invalid_argument);
  EXPECT_THROW(campaign::WilsonInterval(-1, 2), std::invalid_argument);
}

TEST(Campaign, ScaledMassesChangeOnlyTheMasses) {
  const ExampleConfig config = LoadExample("quadruped");
  const Model& model = config.model;
  std::vector<double> scale(model.num_bodies(), 1.0);
  sim::MujocoPlantOptions options;
  options.pairs = config.problem.contact;
  // At scale 1 the rebuilt model exports the same MuJoCo model, every joint, frame and shape.
  EXPECT_EQ(sim::MakeMujocoPlantMjcf(ScaleBodyInertias(model, scale), options),
            sim::MakeMujocoPlantMjcf(model, options));
  const BodyIndex body = model.GetBodyIndex("body");
  scale[body] = 1.25;
  const Model scaled = ScaleBodyInertias(model, scale);
  EXPECT_DOUBLE_EQ(scaled.body_mass(body), 1.25 * model.body_mass(body));
  EXPECT_NEAR(scaled.total_mass() - model.total_mass(), 0.25 * model.body_mass(body), 1e-12);
  EXPECT_EQ(scaled.nq(), model.nq());
  EXPECT_EQ(scaled.geometries().size(), model.geometries().size());
  scale[body] = 0.0;
  EXPECT_THROW(ScaleBodyInertias(model, scale), std::invalid_argument);
}

TEST(Campaign, DifferentSeedsDrawDifferentConditions) {
  const ExampleConfig config = LoadExample("spinner");
  const campaign::CampaignSettings settings = campaign::DefaultSettings("spinner");
  const campaign::RunConditions a = campaign::DrawConditions(settings, config, 7);
  const campaign::RunConditions b = campaign::DrawConditions(settings, config, 8);
  const campaign::RunConditions a2 = campaign::DrawConditions(settings, config, 7);
  EXPECT_EQ(a.push_time, a2.push_time);
  EXPECT_EQ(a.mass_scale, a2.mass_scale);
  EXPECT_NE(a.push_time, b.push_time);
  EXPECT_NE(a.push_impulse, b.push_impulse);
  EXPECT_NE(a.friction_scale, b.friction_scale);
  EXPECT_NE(a.mass_scale, b.mass_scale);
  // Within the settings' ranges (5 s run, 0.5 N s, +-30%).
  for (const campaign::RunConditions& c : {a, b}) {
    EXPECT_GE(c.push_time, 0.5);
    EXPECT_LE(c.push_time, 3.8);
    EXPECT_LE(c.push_impulse, 0.5);
    EXPECT_GE(c.friction_scale, 0.7);
    EXPECT_LE(c.friction_scale, 1.3);
  }
  EXPECT_THROW(campaign::DefaultSettings("pendulum"), std::invalid_argument);
}

/// Three spinner runs of the campaign with seed 21 (about a second in all).
std::vector<campaign::RunResult> SpinnerRuns(const ExampleConfig& config,
                                             const campaign::CampaignSettings& settings) {
  std::vector<campaign::RunResult> runs;
  for (int i = 0; i < 3; ++i) runs.push_back(campaign::RunOne(settings, config, i, 21 + i));
  return runs;
}

TEST(Campaign, SpinnerCampaignIsReproducibleAndMerges) {
  if (!sim::HaveMujoco()) GTEST_SKIP() << "idto was built without MuJoCo";
  const ExampleConfig config = LoadExample("spinner");
  const campaign::CampaignSettings settings = campaign::DefaultSettings("spinner");
  const std::vector<campaign::RunResult> runs = SpinnerRuns(config, settings);
  const std::string json = campaign::CampaignJson(settings, runs);
  EXPECT_EQ(campaign::CampaignJson(settings, SpinnerRuns(config, settings)), json);
  // The runs differ from each other (conditions and outcome measures).
  EXPECT_NE(runs[0].conditions.push_time, runs[1].conditions.push_time);
  ASSERT_FALSE(runs[0].metrics.empty());
  EXPECT_NE(runs[0].metrics[0].values, runs[1].metrics[0].values);
  for (const campaign::RunResult& r : runs) {
    EXPECT_GT(r.num_replans, 900);  // 200 Hz over 5 s
    EXPECT_EQ(r.nonfinite_commands, 0);
    EXPECT_EQ(r.plant_failure, "");
    EXPECT_EQ(r.success, r.failure_mode.empty());
  }
  // Two shards (runs 0 and 2 in one, 1 in the other) merge into the same campaign file.
  const std::string shard_a = campaign::CampaignJson(settings, {runs[2], runs[0]});
  const std::string shard_b = campaign::CampaignJson(settings, {runs[1]});
  campaign::CampaignSettings merged_settings;
  std::vector<campaign::RunResult> merged;
  campaign::MergeCampaigns({shard_a, shard_b}, {"a.json", "b.json"}, &merged_settings, &merged);
  EXPECT_EQ(campaign::CampaignJson(merged_settings, merged), json);
  // The same run twice, or shards of different campaigns, are refused naming the file.
  EXPECT_THAT(
      [&] {
        campaign::MergeCampaigns({shard_a, shard_a}, {"a.json", "c.json"}, &merged_settings,
                                 &merged);
      },
      ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("c.json: run 2")));
  campaign::CampaignSettings other = settings;
  other.max_impulse = 1.0;
  EXPECT_THAT(
      [&] {
        campaign::MergeCampaigns({shard_a, campaign::CampaignJson(other, {runs[1]})},
                                 {"a.json", "d.json"}, &merged_settings, &merged);
      },
      ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("d.json: its settings")));
  EXPECT_THAT(
      [&] { campaign::MergeCampaigns({"{\"runs\": []}"}, {"e.json"}, &merged_settings, &merged); },
      ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("e.json")));
  // The report counts what the runs say.
  const std::string markdown = campaign::CampaignMarkdown(settings, runs);
  int successes = 0;
  for (const campaign::RunResult& r : runs) successes += r.success ? 1 : 0;
  EXPECT_THAT(markdown, HasSubstr(std::to_string(successes) + " of 3 runs succeeded"));
}

/// The breakdown row `name` of a campaign's Markdown report: "| name | runs | successes | ...".
std::string BreakdownRow(const std::string& markdown, const std::string& name) {
  const std::string key = "| " + name + " | ";
  const size_t at = markdown.find(key);
  if (at == std::string::npos) return "(missing)";
  return markdown.substr(at, markdown.find('\n', at) - at);
}

TEST(Campaign, BreakdownByPushDirection) {
  // Six synthetic runs: directions about each axis (and exactly between +x and +y, which counts
  // towards +y), impulses in the upper and lower thirds of 0.05 N s.
  campaign::CampaignSettings settings = campaign::DefaultSettings("allegro");
  const double pi = std::acos(-1.0);
  const struct {
    double direction, impulse;
    bool success;
  } cases[] = {{0.1, 0.045, false}, {-0.3, 0.04, true},        {0.25 * pi, 0.01, true},
               {pi, 0.045, true},   {-0.5 * pi, 0.002, false}, {1.9 * pi, 0.001, true}};
  std::vector<campaign::RunResult> runs;
  for (const auto& c : cases) {
    campaign::RunResult r;
    r.run_index = static_cast<int>(runs.size());
    r.conditions.push_direction = c.direction;
    r.conditions.push_impulse = c.impulse;
    r.success = c.success;
    r.failure_mode = c.success ? "" : "not held";
    runs.push_back(r);
  }
  const std::string md = campaign::CampaignMarkdown(settings, runs);
  EXPECT_EQ(BreakdownRow(md, "push towards +x"), "| push towards +x | 3 | 2 | 66.7 % |");
  EXPECT_EQ(BreakdownRow(md, "push towards +y"), "| push towards +y | 1 | 1 | 100.0 % |");
  EXPECT_EQ(BreakdownRow(md, "push towards -x"), "| push towards -x | 1 | 1 | 100.0 % |");
  EXPECT_EQ(BreakdownRow(md, "push towards -y"), "| push towards -y | 1 | 0 | 0.0 % |");
  EXPECT_EQ(BreakdownRow(md, "push impulse in the upper third towards +x"),
            "| push impulse in the upper third towards +x | 2 | 1 | 50.0 % |");
  EXPECT_EQ(BreakdownRow(md, "push impulse in the upper third towards -x"),
            "| push impulse in the upper third towards -x | 1 | 1 | 100.0 % |");
  EXPECT_EQ(BreakdownRow(md, "push impulse in the upper third towards -y"),
            "| push impulse in the upper third towards -y | 0 | 0 | - |");
  // The JSON summary carries the same groups.
  const std::string json = campaign::CampaignJson(settings, runs);
  EXPECT_THAT(json, HasSubstr("{\"condition\": \"push towards +x\", \"runs\": 3, "
                              "\"successes\": 2}"));
  // Systems pushed along x only (the hopper) get the +x and -x rows, no +-y rows.
  settings.push_along_x = true;
  runs[0].conditions.push_direction = 0.0;
  runs[1].conditions.push_direction = pi;
  const std::string along_x = campaign::CampaignMarkdown(settings, {runs[0], runs[1]});
  EXPECT_EQ(BreakdownRow(along_x, "push towards +x"), "| push towards +x | 1 | 0 | 0.0 % |");
  EXPECT_EQ(BreakdownRow(along_x, "push towards -x"), "| push towards -x | 1 | 1 | 100.0 % |");
  EXPECT_EQ(BreakdownRow(along_x, "push towards +y"), "(missing)");
  EXPECT_EQ(BreakdownRow(along_x, "push impulse in the upper third towards +x"),
            "| push impulse in the upper third towards +x | 1 | 0 | 0.0 % |");
  EXPECT_EQ(BreakdownRow(along_x, "push impulse in the upper third towards -x"),
            "| push impulse in the upper third towards -x | 1 | 1 | 100.0 % |");
  // A direction that is not a number (a merged file's null) counts in no direction's row.
  settings.push_along_x = false;
  runs[0].conditions.push_direction = std::nan("");
  const std::string nan_direction = campaign::CampaignMarkdown(settings, {runs[0], runs[1]});
  EXPECT_EQ(BreakdownRow(nan_direction, "push towards +x"), "| push towards +x | 0 | 0 | - |");
  EXPECT_EQ(BreakdownRow(nan_direction, "push towards -x"),
            "| push towards -x | 1 | 1 | 100.0 % |");
}

TEST(ClosedLoopConditions, MeasuredStateIsNoisyButValid) {
  const ExampleConfig config = LoadExample("quadruped");
  const Model& model = config.model;
  const Eigen::VectorXd q = config.problem.q_init;
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(model.nv(), -2.0, 2.0);
  std::mt19937_64 rng(3);
  Eigen::VectorXd q_hat, v_hat;
  mpc::MeasureState(model, q, v, mpc::SensorNoise{}, &rng, &q_hat, &v_hat);
  EXPECT_EQ(q_hat, q);
  EXPECT_EQ(v_hat, v);
  const mpc::SensorNoise noise{1e-3, 0.02, 1e-3};
  const int n = 2000;
  double sum_q = 0.0, sum_v = 0.0;
  for (int k = 0; k < n; ++k) {
    mpc::MeasureState(model, q, v, noise, &rng, &q_hat, &v_hat);
    EXPECT_NEAR(q_hat.head<4>().norm(), 1.0, 1e-14);
    const double dq = q_hat(7) - q(7);  // first leg joint, rad
    sum_q += dq * dq;
    const int last = model.nv() - 1;  // |v| = 2: standard deviation 0.04
    sum_v += (v_hat(last) - v(last)) * (v_hat(last) - v(last));
  }
  EXPECT_NEAR(std::sqrt(sum_q / n), 1e-3, 1e-4);
  EXPECT_NEAR(std::sqrt(sum_v / n), 0.04, 4e-3);
}

/// The spinner against the built-in plant for 0.3 s with the given closed-loop options.
mpc::ClosedLoopLog RunSpinner(const mpc::ClosedLoopOptions& cl) {
  const ExampleConfig config = LoadExample("spinner");
  const MpcConfig mpc = ParseMpcConfig(config);
  std::unique_ptr<sim::Plant> plant = sim::MakeBuiltinPlant(config.model, mpc.builtin);
  plant->Reset(config.problem.q_init, config.problem.v_init);
  mpc::Controller controller(config.model, config.problem, config.solver, mpc.controller);
  controller.Initialize(MakeInitialGuess(config), 20);
  return mpc::RunClosedLoop(config.model, cl, &controller, plant.get());
}

/// Closed-loop options for `duration` s with a fixed latency (reproducible), logging every step.
mpc::ClosedLoopOptions FixedLatencyOptions(double duration, double latency) {
  mpc::ClosedLoopOptions cl;
  cl.duration = duration;
  cl.latency = mpc::LatencyModel::kFixed;
  cl.fixed_latency = latency;
  cl.log_every = 1;
  return cl;
}

TEST(ClosedLoopConditions, NoiseAndJitterAreReproducibleFromTheSeed) {
  mpc::ClosedLoopOptions cl = FixedLatencyOptions(0.3, 1e-3);
  const mpc::ClosedLoopLog quiet = RunSpinner(cl);
  cl.sensor_noise = {1e-3, 0.02, 1e-3};
  cl.latency_jitter = 2e-3;
  cl.seed = 5;
  const mpc::ClosedLoopLog a = RunSpinner(cl);
  const mpc::ClosedLoopLog b = RunSpinner(cl);
  cl.seed = 6;
  const mpc::ClosedLoopLog c = RunSpinner(cl);
  ASSERT_EQ(a.q.size(), b.q.size());
  for (size_t k = 0; k < a.q.size(); ++k) {
    ASSERT_EQ(a.q[k], b.q[k]) << k;
    ASSERT_EQ(a.u[k], b.u[k]) << k;
  }
  EXPECT_NE(a.u.back(), c.u.back());
  EXPECT_NE(a.u.back(), quiet.u.back());
  // 1 ms + up to 2 ms is within the 5 ms period: nothing late, nothing rejected.
  EXPECT_EQ(a.num_late_plans, 0);
  EXPECT_EQ(a.num_rejected_plans, 0);
  EXPECT_EQ(a.num_nonfinite_commands, 0);
}

TEST(ClosedLoopConditions, LatePlansAreDiscardedAndCounted) {
  mpc::ClosedLoopOptions cl = FixedLatencyOptions(0.1, 4e-3);
  cl.latency_jitter = 2e-3;  // late when the draw exceeds 1 ms: about half the re-plans
  cl.seed = 1;
  const mpc::ClosedLoopLog some = RunSpinner(cl);
  EXPECT_GT(some.num_late_plans, 0);
  EXPECT_LT(some.num_late_plans, static_cast<int>(some.solve_time.size()));
  cl.fixed_latency = 6e-3;  // beyond the 5 ms period: every plan is late
  const mpc::ClosedLoopLog all = RunSpinner(cl);
  EXPECT_EQ(all.num_late_plans, static_cast<int>(all.solve_time.size()));
  // So the initial plan stays in force: the PD target is the initial plan's throughout.
  const ExampleConfig config = LoadExample("spinner");
  mpc::Controller controller(config.model, config.problem, config.solver,
                             ParseMpcConfig(config).controller);
  controller.Initialize(MakeInitialGuess(config), 20);
  Eigen::VectorXd q_d, v_d, u_ff;
  for (size_t k = 0; k < all.t.size(); k += 10) {
    controller.plan().Sample(config.model, all.t[k], &q_d, &v_d, &u_ff);
    ASSERT_EQ(all.q_plan[k], q_d) << "t = " << all.t[k];
  }
}

TEST(ClosedLoopConditions, LatePlansUsedOnArrivalTakeOverWhenTheyArrive) {
  // On time (4 ms at the 5 ms period), both policies run the same loop, bit for bit.
  mpc::ClosedLoopOptions cl = FixedLatencyOptions(0.1, 4e-3);
  const mpc::ClosedLoopLog discard = RunSpinner(cl);
  cl.late_plans = mpc::LatePlanPolicy::kUseOnArrival;
  const mpc::ClosedLoopLog arrival = RunSpinner(cl);
  ASSERT_EQ(arrival.q.size(), discard.q.size());
  for (size_t k = 0; k < arrival.q.size(); ++k) ASSERT_EQ(arrival.u[k], discard.u[k]) << k;
  EXPECT_EQ(arrival.num_skipped_replans, 0);

  // 6 ms: every re-plan is late. The one at 5 ms drives the plant from 11 ms on; the control
  // step at 10 ms finds the solver busy, so the next re-plan is at 15 ms.
  cl.fixed_latency = 6e-3;
  const mpc::ClosedLoopLog late = RunSpinner(cl);
  ASSERT_EQ(late.replan_time.size(), 10u);
  for (size_t i = 0; i < late.replan_time.size(); ++i) {
    EXPECT_NEAR(late.replan_time[i], 0.005 + 0.01 * static_cast<double>(i), 1e-12) << i;
  }
  EXPECT_EQ(late.num_late_plans, 10);
  EXPECT_EQ(late.num_skipped_replans, 9);
  // The plan in force, rebuilt by a second controller from the logged state at 5 ms (no noise:
  // the controller measured exactly that state): the initial plan up to 10 ms, then the re-plan's.
  const ExampleConfig config = LoadExample("spinner");
  mpc::Controller controller(config.model, config.problem, config.solver,
                             ParseMpcConfig(config).controller);
  controller.Initialize(MakeInitialGuess(config), 20);
  const mpc::Plan initial = controller.plan();
  controller.Replan(0.005, late.q[5], late.v[5]);
  Eigen::VectorXd q_d, v_d, u_ff;
  for (int k : {5, 10}) {
    initial.Sample(config.model, late.t[k], &q_d, &v_d, &u_ff);
    EXPECT_EQ(late.q_plan[k], q_d) << "t = " << late.t[k];
  }
  for (int k : {11, 14, 20}) {
    controller.plan().Sample(config.model, late.t[k], &q_d, &v_d, &u_ff);
    EXPECT_EQ(late.q_plan[k], q_d) << "t = " << late.t[k];
  }
  initial.Sample(config.model, late.t[11], &q_d, &v_d, &u_ff);
  EXPECT_NE(late.q_plan[11], q_d);
}

TEST(ClosedLoopConditions, RealTimeAndAwakeWorkersChangeNothingButTheTiming) {
  mpc::ClosedLoopOptions cl = FixedLatencyOptions(0.3, 1e-3);
  const mpc::ClosedLoopLog free_running = RunSpinner(cl);
  cl.real_time = true;
  const auto start = std::chrono::steady_clock::now();
  const mpc::ClosedLoopLog paced = RunSpinner(cl);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The last re-plan (200 Hz) is due at 0.295 s after the loop's start.
  EXPECT_GE(wall, 0.295);
  // Workers kept awake: the same run, and the pool's idle setting is restored afterwards.
  cl.keep_workers_awake = true;
  const std::chrono::microseconds idle_yield = internal::ThreadPoolIdleYield();
  const mpc::ClosedLoopLog awake = RunSpinner(cl);
  EXPECT_EQ(internal::ThreadPoolIdleYield(), idle_yield);
  for (const mpc::ClosedLoopLog* log : {&paced, &awake}) {
    ASSERT_EQ(log->replan_time, free_running.replan_time);
    ASSERT_EQ(log->q.size(), free_running.q.size());
    for (size_t k = 0; k < log->q.size(); ++k) {
      ASSERT_EQ(log->q[k], free_running.q[k]) << k;
      ASSERT_EQ(log->u[k], free_running.u[k]) << k;
    }
  }
}

// Two paced loops at once (on two threads), both keeping the workers awake; the first to start
// ends first. While the second runs the pool keeps the raised setting, and afterwards it is the
// one from before both (restoring on each loop's own end would leave it raised).
TEST(ClosedLoopConditions, ConcurrentLoopsWithAwakeWorkersRestoreThePoolSetting) {
  const std::chrono::microseconds before = internal::ThreadPoolIdleYield();
  mpc::ClosedLoopOptions first = FixedLatencyOptions(0.3, 1e-3);
  first.real_time = true;
  first.keep_workers_awake = true;
  mpc::ClosedLoopOptions second = first;
  second.duration = 0.6;
  bool first_ok = false;
  std::thread other([&] {
    try {
      first_ok = !RunSpinner(first).solve_time.empty();
    } catch (...) {
      first_ok = false;
    }
  });
  // Start the second loop once the first one has raised the setting.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (internal::ThreadPoolIdleYield() == before && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_GT(internal::ThreadPoolIdleYield(), before);
  const mpc::ClosedLoopLog log = RunSpinner(second);
  other.join();
  EXPECT_TRUE(first_ok);
  EXPECT_FALSE(log.solve_time.empty());
  EXPECT_EQ(internal::ThreadPoolIdleYield(), before);
}

/// The spinner's file with `lines` as its `mpc:` section.
ExampleConfig LoadSpinnerWithMpc(const std::string& lines) {
  const std::string dir = std::string(IDTO_SOURCE_DIR) + "/examples/spinner";
  std::ifstream in(dir + "/spinner.yaml");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string before = text.str().substr(0, text.str().find("\nmpc:") + 1);
  return LoadExampleConfigString(before + "mpc:\n" + lines, "spinner.yaml", dir, kShareDirs);
}

TEST(ClosedLoopConditions, MpcSectionReadsNoiseJitterAndSeed) {
  EXPECT_FALSE(ParseMpcConfig(LoadExample("spinner")).closed_loop.sensor_noise.enabled());
  EXPECT_EQ(ParseMpcConfig(LoadExample("spinner")).closed_loop.latency_jitter, 0.0);
  const ExampleConfig config = LoadSpinnerWithMpc(
      "  latency_jitter: 0.002\n  seed: 42\n"
      "  sensor_noise: {position: 0.001, velocity_relative: 0.02, velocity_floor: 0.003}\n");
  const mpc::ClosedLoopOptions& cl = ParseMpcConfig(config).closed_loop;
  EXPECT_EQ(cl.latency_jitter, 0.002);
  EXPECT_EQ(cl.seed, 42u);
  EXPECT_EQ(cl.sensor_noise.position, 0.001);
  EXPECT_EQ(cl.sensor_noise.velocity_relative, 0.02);
  EXPECT_EQ(cl.sensor_noise.velocity_floor, 0.003);
  EXPECT_THAT([] { LoadSpinnerWithMpc("  latency_jitter: -1\n"); },
              ::testing::ThrowsMessage<FileError>(HasSubstr("mpc.latency_jitter")));
  EXPECT_THAT([] { LoadSpinnerWithMpc("  sensor_noise: {angle: 1}\n"); },
              ::testing::ThrowsMessage<FileError>(HasSubstr("mpc.sensor_noise.angle")));
  EXPECT_THAT([] { LoadSpinnerWithMpc("  seed: 1.5\n"); },
              ::testing::ThrowsMessage<FileError>(HasSubstr("mpc.seed")));
  EXPECT_FALSE(ParseMpcConfig(LoadExample("spinner")).closed_loop.real_time);
  EXPECT_TRUE(ParseMpcConfig(LoadSpinnerWithMpc("  real_time: true\n")).closed_loop.real_time);
  EXPECT_THAT([] { LoadSpinnerWithMpc("  real_time: 2\n"); },
              ::testing::ThrowsMessage<FileError>(HasSubstr("mpc.real_time")));
  EXPECT_FALSE(ParseMpcConfig(LoadExample("spinner")).closed_loop.keep_workers_awake);
  EXPECT_TRUE(ParseMpcConfig(LoadSpinnerWithMpc("  keep_workers_awake: true\n"))
                  .closed_loop.keep_workers_awake);
  EXPECT_THAT([] { LoadSpinnerWithMpc("  keep_workers_awake: yes please\n"); },
              ::testing::ThrowsMessage<FileError>(HasSubstr("mpc.keep_workers_awake")));
}

}  // namespace
}  // namespace idto
