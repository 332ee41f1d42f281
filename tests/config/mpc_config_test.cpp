// The `mpc:` section: read by the same reader as the rest of the file, so that its errors name
// the file, the key path and the line of the file itself; integers are integers; unknown and
// duplicate keys are errors; no yaml-cpp exception escapes.

#include "idto/config/mpc_config.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "config_test_helpers.hpp"
#include "idto/config/config.hpp"
#include "idto/core/errors.hpp"

namespace idto {
namespace {

using test::kBase;
using test::kShareDirs;
using test::LoadText;
using test::With;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

/// kBase (13 lines) and an mpc section whose first two lines (15, 16) are valid; `lines` start
/// at line 17 of the file.
std::string MpcFile(const std::string& lines) {
  return kBase + "mpc:\n  plant: builtin\n  duration: 1.0\n" + lines;
}

/// Writes `text` to a file `name` in a folder of this test process; returns its path. (ctest
/// runs the tests as parallel processes: a shared folder let two tests overwrite each other's
/// file between writing and loading it.)
std::string WriteFile(const std::string& name, const std::string& text) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                    ("idto_mpc_config_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

/// A callable that loads the file `name` holding `text`.
auto LoadingFile(const std::string& name, const std::string& text) {
  const std::string path = WriteFile(name, text);
  return [path]() { LoadExampleConfig(path, kShareDirs); };
}

/// The message of a FileError naming `file`, `key_path` and `line`, with `text` in it.
auto ErrorAt(const std::string& file, const std::string& key_path, int line,
             const std::string& text) {
  return ThrowsMessage<FileError>(AllOf(HasSubstr(file), HasSubstr(": " + key_path + ": "),
                                        HasSubstr("(line " + std::to_string(line) + ")"),
                                        HasSubstr(text)));
}

TEST(MpcConfigTest, ReadWithTheFile) {
  const ExampleConfig config = LoadText(MpcFile(
      "  control_rate: 50\n  iterations_per_step: 3\n  initial_iterations: 0\n"
      "  kp: {default: 1, elbow: 4}\n  kd: [0.5, 0.25]\n  latency: 0.002\n"
      "  late_plans: use_on_arrival\n"
      "  disturbances: [{body: lower_link, start: 0.5, duration: 0.1, force: [0, 1, 0]}]\n"));
  ASSERT_TRUE(config.mpc.has_value());
  const MpcConfig& m = *config.mpc;
  EXPECT_EQ(m.plant, "builtin");
  EXPECT_DOUBLE_EQ(m.closed_loop.duration, 1.0);
  EXPECT_DOUBLE_EQ(m.controller.control_rate, 50);
  EXPECT_EQ(m.controller.iterations_per_step, 3);
  EXPECT_EQ(m.initial_iterations, 0);
  EXPECT_DOUBLE_EQ(m.controller.gains.Kp(config.model.GetVelocityStart("shoulder")), 1.0);
  EXPECT_DOUBLE_EQ(m.controller.gains.Kp(config.model.GetVelocityStart("elbow")), 4.0);
  EXPECT_DOUBLE_EQ(m.controller.gains.Kd(1), 0.25);
  EXPECT_EQ(m.closed_loop.latency, mpc::LatencyModel::kFixed);
  EXPECT_DOUBLE_EQ(m.closed_loop.fixed_latency, 0.002);
  EXPECT_EQ(m.closed_loop.late_plans, mpc::LatePlanPolicy::kUseOnArrival);
  ASSERT_EQ(m.closed_loop.disturbances.size(), 1u);
  EXPECT_EQ(m.closed_loop.disturbances[0].body, config.model.GetBodyIndex("lower_link"));
  // ParseMpcConfig gives the section as read.
  EXPECT_EQ(ParseMpcConfig(config).controller.iterations_per_step, 3);
}

TEST(MpcConfigTest, DefaultsWithoutTheSection) {
  const ExampleConfig config = LoadText(kBase);
  EXPECT_FALSE(config.mpc.has_value());
  const MpcConfig m = ParseMpcConfig(config);
  EXPECT_EQ(m.controller.gains.Kp.size(), config.model.nv());
  EXPECT_EQ(m.controller.iterations_per_step, 1);
  EXPECT_EQ(m.initial_iterations, 50);
  EXPECT_EQ(m.closed_loop.late_plans, mpc::LatePlanPolicy::kDiscard);
  EXPECT_EQ(m.mujoco.friction_coefficient, config.problem.contact.parameters.friction_coefficient);
}

// The cases of the issue: each error names the file, the key path and the file's own line.
TEST(MpcConfigTest, ErrorsNameFileKeyPathAndLineOfTheFile) {
  const std::string f = "bad_mpc.yaml";
  EXPECT_THAT(LoadingFile(f, MpcFile("  control_rate: [1, 2]\n")),
              ErrorAt(f, "mpc.control_rate", 17, "is a list of 2 entries [1, 2]; expected a"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  control_rate: 10\n  kp:\n    shoulder: 1\n"
                                     "    elbow: [1, 2]\n")),
              ErrorAt(f, "mpc.kp.elbow", 20, "is a list of 2 entries"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  iterations_per_step: 2.5\n")),
              ErrorAt(f, "mpc.iterations_per_step", 17, "is '2.5'; expected an integer >= 1"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  control_rate: 10\n  initial_iterations: 1e300\n")),
              ErrorAt(f, "mpc.initial_iterations", 18, "is '1e300'; expected an integer >= 0"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  initial_iterations: 2.0\n")),
              ErrorAt(f, "mpc.initial_iterations", 17, "expected an integer"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  control_rate: 10\n  replan_hz: 50\n")),
              ErrorAt(f, "mpc.replan_hz", 18, "unknown key; expected one of control_rate"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  control_rate: 10\n  control_rate: 20\n")),
              ErrorAt(f, "mpc.control_rate", 18, "duplicate key"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  kp: {shoulder: 1,\n       shoulder: 2}\n")),
              ErrorAt(f, "mpc.kp.shoulder", 18, "duplicate key"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  orientation_lead: {a: 1, a: 2}\n")),
              ErrorAt(f, "mpc.orientation_lead.a", 17, "duplicate key"));
}

TEST(MpcConfigTest, DurationShorterThanAPlantStep) {
  EXPECT_THAT(LoadingFile("short.yaml", MpcFile("  plant_time_step: 2.0\n")),
              ErrorAt("short.yaml", "mpc.duration", 16,
                      "is 1 s; expected at least one plant step (plant_time_step = 2 s)"));
  // At the default plant step (1 ms).
  EXPECT_THAT(LoadingFile("short.yaml", kBase + "mpc:\n  duration: 0.0004\n"),
              ErrorAt("short.yaml", "mpc.duration", 15, "expected at least one plant step"));
}

TEST(MpcConfigTest, SubSectionsNameTheirKeyPathAndLine) {
  const std::string f = "bad_mpc.yaml";
  EXPECT_THAT(LoadingFile(f, MpcFile("  solver: {max_iterations: 2.5}\n")),
              ErrorAt(f, "mpc.solver.max_iterations", 17, "is '2.5'"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  problem:\n    weights: {R: [1]}\n")),
              ErrorAt(f, "mpc.problem.weights.R", 18, "nv = 2"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  contact:\n    stiffness: -1\n")),
              ErrorAt(f, "mpc.contact.stiffness", 18, "is -1"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  relative: [{elbow: [0.5]}]\n")),
              ErrorAt(f, "mpc.relative[0].elbow[0]", 17, "is '0.5'; expected an integer"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  disturbances:\n    - {body: lower_link, duration: 0.1, "
                                     "force: [1, x, 0]}\n")),
              ErrorAt(f, "mpc.disturbances[0].force[1]", 18, "is 'x'; expected a number"));
}

// Keys that used to be read and then lost: each is now used or refused.
TEST(MpcConfigTest, NoKeyIsSilentlyIgnored) {
  const std::string f = "ignored.yaml";
  // A push without a duration never acted.
  EXPECT_THAT(
      LoadingFile(f, MpcFile("  disturbances:\n    - {body: lower_link, force: [1, 0, 0]}\n")),
      ErrorAt(f, "mpc.disturbances[0].duration", 18, "missing (required)"));
  // builtin_contact without friction_coefficient kept the plant's 1.0, not the scene's.
  const std::string scene =
      With("    - urdf: acrobot.urdf\n",
           "    - urdf: acrobot.urdf\n  contact: {friction_coefficient: 0.3}\n");
  const std::string mpc = "mpc:\n  plant: builtin\n  builtin_contact: ";
  const ExampleConfig stiff = LoadText(scene + mpc + "{stiffness: 5000}\n");
  EXPECT_DOUBLE_EQ(stiff.mpc->builtin.contact.stiffness, 5000);
  EXPECT_DOUBLE_EQ(stiff.mpc->builtin.contact.friction_coefficient, 0.3);
  const ExampleConfig slippery = LoadText(scene + mpc + "{friction_coefficient: 0.1}\n");
  EXPECT_DOUBLE_EQ(slippery.mpc->builtin.contact.friction_coefficient, 0.1);
  // mpc.problem.initial_guess was checked, then dropped: it is now the controller's cold start.
  const ExampleConfig open_loop_guess = LoadText(MpcFile("  problem: {q_init: [0.1, 0]}\n"));
  EXPECT_FALSE(open_loop_guess.mpc_initial_guess.has_value());
  const ExampleConfig constant =
      LoadText(With("  q_init: [0, 0]\n", "  q_init: [0, 0]\n  nominal: {q_end: [1, 1]}\n") +
               "mpc:\n  plant: builtin\n  problem: {initial_guess: constant}\n");
  ASSERT_EQ(constant.mpc_initial_guess, InitialGuessType::kConstant);
  EXPECT_EQ(constant.initial_guess, InitialGuessType::kInterpolate);
  const std::vector<Eigen::VectorXd> q = ControllerInitialGuess(constant);
  ASSERT_EQ(q.size(), 21u);
  EXPECT_EQ(q.back(), constant.problem.q_init);            // constant: q_init throughout
  EXPECT_NE(MakeInitialGuess(constant).back(), q.back());  // the open loop interpolates to q_end
}

TEST(MpcConfigTest, NoYamlExceptionEscapes) {
  for (const std::string lines :
       {"  plant: [builtin]\n", "  latency: [1]\n", "  latency: {a: 1}\n", "  kp: {[1]: 2}\n",
        "  relative: [{elbow: {a: 1}}]\n", "  relative: [{[elbow]: [0]}]\n",
        "  orientation_lead: {[a]: 1}\n", "  disturbances: [{body: [a], force: [1, 0, 0]}]\n",
        "  disturbances: [3]\n", "  builtin_contact: [1]\n", "  problem: [1]\n", "  solver: 3\n",
        "  contact: {stiffness: {a: 1}}\n", "  kd: \n", "  mujoco_friction: ~\n",
        "  iterations_per_step: 99999999999999999999\n", "  initial_iterations: -1\n",
        "  problem: {nominal: 3}\n", "  problem: {weights: {Qq: [[1]]}}\n"}) {
    SCOPED_TRACE(lines);
    const std::string text = kBase + "mpc:\n" + lines;
    EXPECT_THROW(LoadText(text), FileError);
  }
}

// ------------------------------------------------------------------------------------------
// The keys of the spinner and Allegro examples, with their mpc sections replaced.

/// The example's file with its `mpc:` section (the last one) replaced by `lines`; the first of
/// `lines` is at line *first_line of the file.
std::string ExampleWithMpc(const std::string& name, const std::string& lines, int* first_line) {
  std::ifstream in(std::string(IDTO_SOURCE_DIR) + "/examples/" + name + "/" + name + ".yaml");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  const std::string before = s.substr(0, s.find("\nmpc:") + 1);
  // `before` ends with a newline: "mpc:" is on line (newlines + 1), the first of `lines` next.
  *first_line = static_cast<int>(std::count(before.begin(), before.end(), '\n')) + 2;
  return before + "mpc:\n" + lines;
}

ExampleConfig LoadExample(const std::string& name, const std::string& text) {
  const std::string dir = std::string(IDTO_SOURCE_DIR) + "/examples/" + name;
  return LoadExampleConfigString(text, name + ".yaml", dir, kShareDirs);
}

/// A checker of example `name` with an mpc section holding the given lines (and `more` after
/// them): loading fails with an error at `key_path`, on the section's first line, containing
/// `text`.
auto MpcErrorChecker(const std::string& name, const std::string& more = "") {
  return [name, more](const std::string& lines, const std::string& key_path,
                      const std::string& text) {
    int first = 0;
    const std::string yaml = ExampleWithMpc(name, lines + more, &first);
    EXPECT_THAT([&] { LoadExample(name, yaml); }, ErrorAt(name + ".yaml", key_path, first, text));
  };
}

TEST(MpcConfigTest, SpinnerKeysAndErrors) {
  int line = 0;
  ExampleConfig config =
      LoadExample("spinner", ExampleWithMpc("spinner",
                                            "  relative: [{spinner_axle: [0]}, finger_elbow]\n"
                                            "  latency: 0.004\n",
                                            &line));
  const Model& model = config.model;
  ASSERT_TRUE(config.mpc.has_value());
  EXPECT_EQ(config.mpc->controller.relative_positions,
            (std::vector<int>{model.GetPositionStart("spinner_axle"),
                              model.GetPositionStart("finger_elbow")}));
  EXPECT_EQ(config.mpc->closed_loop.latency, mpc::LatencyModel::kFixed);
  EXPECT_DOUBLE_EQ(config.mpc->closed_loop.fixed_latency, 0.004);

  const auto throws = MpcErrorChecker("spinner");
  throws("  control_rate: -5\n", "mpc.control_rate", "is -5; expected a finite positive number");
  throws("  plant: gazebo\n", "mpc.plant", "is 'gazebo'; expected one of mujoco, builtin");
  throws("  late_plans: keep\n", "mpc.late_plans",
         "is 'keep'; expected one of discard, use_on_arrival");
  throws("  no_such_key: 1\n", "mpc.no_such_key", "unknown key");
  throws("  relative: [elbow]\n", "mpc.relative[0]", "is 'elbow'; expected a joint of the scene");
  throws("  kp: [1, 2]\n", "mpc.kp", "is a list of 2 entries [1, 2]; expected a list of nv = 3");
  throws("  disturbances: [{body: nowhere, force: [1, 0, 0]}]\n", "mpc.disturbances[0].body",
         "expected a body of the scene");
  throws("  latency: sometimes\n", "mpc.latency",
         "expected solve_time, control_period or a delay in seconds");
  throws("  latency: -0.01\n", "mpc.latency",
         "expected solve_time, control_period or a delay in seconds");
  throws("  relative: [{spinner_axle: [1]}]\n", "mpc.relative[0].spinner_axle[0]",
         "is 1; expected a coordinate index in [0, 1)");
  throws("  relative: [{spinner_axle: x}]\n", "mpc.relative[0].spinner_axle",
         "expected a non-empty list of coordinate indices");
  throws("  relative: [[1, 2]]\n", "mpc.relative[0]",
         "expected a joint name or {joint: [coordinate indices");
}

TEST(MpcConfigTest, RelativeGoalKeysAndErrors) {
  int line = 0;
  const ExampleConfig config = LoadExample(
      "spinner", ExampleWithMpc("spinner",
                                "  relative: [{spinner_axle: [0]}, finger_elbow]\n"
                                "  relative_goal: {finger_elbow: [-1.5], spinner_axle: 2.5}\n",
                                &line));
  ASSERT_TRUE(config.mpc.has_value());
  const std::vector<mpc::MpcOptions::RelativeGoal>& goals = config.mpc->controller.relative_goals;
  ASSERT_EQ(goals.size(), 2u);
  EXPECT_EQ(goals[0].position, config.model.GetPositionStart("finger_elbow"));
  EXPECT_DOUBLE_EQ(goals[0].goal, -1.5);
  EXPECT_EQ(goals[1].position, config.model.GetPositionStart("spinner_axle"));
  EXPECT_DOUBLE_EQ(goals[1].goal, 2.5);
  const auto throws = MpcErrorChecker("spinner", "  relative: [spinner_axle]\n");
  throws("  relative_goal: {finger_shoulder: 1}\n", "mpc.relative_goal.finger_shoulder",
         "is 'finger_shoulder'; expected a joint listed in mpc.relative");
  throws("  relative_goal: {no_joint: 1}\n", "mpc.relative_goal.no_joint",
         "is 'no_joint'; expected a joint listed in mpc.relative");
  throws("  relative_goal: {spinner_axle: [1, 2]}\n", "mpc.relative_goal.spinner_axle",
         "expected a list of 1 number");
  throws("  relative_goal: {spinner_axle: .inf}\n", "mpc.relative_goal.spinner_axle",
         "expected a finite number");
  throws("  relative_goal: [1]\n", "mpc.relative_goal", "expected a map {joint: goal or [goals]}");
}

TEST(MpcConfigTest, ModelMassScaleKeyAndErrors) {
  int line = 0;
  const ExampleConfig config = LoadExample(
      "spinner", ExampleWithMpc("spinner", "  model_mass_scale: {spinner: 1.3}\n", &line));
  ASSERT_TRUE(config.mpc_model.has_value());
  const Model& controller = ControllerModel(config);
  EXPECT_EQ(&controller, &*config.mpc_model);
  for (BodyIndex b = 1; b < config.model.num_bodies(); ++b) {
    const double factor = config.model.body_name(b) == "spinner" ? 1.3 : 1.0;
    EXPECT_DOUBLE_EQ(controller.body_mass(b), factor * config.model.body_mass(b)) << b;
    EXPECT_TRUE(controller.body_inertia(b).I_BBcm_B.isApprox(
        factor * config.model.body_inertia(b).I_BBcm_B, 1e-15))
        << b;
  }
  EXPECT_EQ(controller.geometries().size(), config.model.geometries().size());
  // Without the key the controller plans with the scene's model.
  const ExampleConfig plain =
      LoadExample("spinner", ExampleWithMpc("spinner", "  control_rate: 100\n", &line));
  EXPECT_FALSE(plain.mpc_model.has_value());
  EXPECT_EQ(&ControllerModel(plain), &plain.model);
  const auto throws = MpcErrorChecker("spinner");
  throws("  model_mass_scale: {world: 2}\n", "mpc.model_mass_scale.world",
         "is 'world'; expected a body of the scene other than the world");
  throws("  model_mass_scale: {no_body: 2}\n", "mpc.model_mass_scale.no_body",
         "is 'no_body'; expected a body of the scene");
  throws("  model_mass_scale: {spinner: 0}\n", "mpc.model_mass_scale.spinner",
         "expected a finite positive number");
  throws("  model_mass_scale: {spinner: .nan}\n", "mpc.model_mass_scale.spinner",
         "is nan; expected a finite number");
  throws("  model_mass_scale: [1.3]\n", "mpc.model_mass_scale",
         "expected a map {body: mass factor > 0}");
  throws("  model_mass_scale: {}\n", "mpc.model_mass_scale", "is an empty map");
}

TEST(MpcConfigTest, OrientationLeadAndMujocoFrictionKeys) {
  int line = 0;
  const ExampleConfig config =
      LoadExample("allegro", ExampleWithMpc("allegro",
                                            "  orientation_lead: {ball_root_joint: 0.4}\n"
                                            "  mujoco_torsional_friction: 0.002\n"
                                            "  mujoco_rolling_friction: 0.01\n"
                                            "  mujoco_cone: pyramidal\n",
                                            &line));
  ASSERT_TRUE(config.mpc.has_value());
  const MpcConfig& m = *config.mpc;
  ASSERT_EQ(m.controller.orientation_leads.size(), 1u);
  EXPECT_EQ(m.controller.orientation_leads[0].position_start,
            config.model.GetPositionStart("ball_root_joint"));
  EXPECT_DOUBLE_EQ(m.controller.orientation_leads[0].max_angle, 0.4);
  EXPECT_DOUBLE_EQ(m.mujoco.torsional_friction, 0.002);
  EXPECT_DOUBLE_EQ(m.mujoco.rolling_friction, 0.01);
  EXPECT_EQ(m.mujoco.friction_cone, "pyramidal");
  EXPECT_EQ(LoadExample("allegro", ExampleWithMpc("allegro", "  seed: 1\n", &line))
                .mpc->mujoco.friction_cone,
            "elliptic");
  const auto throws = MpcErrorChecker("allegro");
  throws("  mujoco_cone: round\n", "mpc.mujoco_cone", "is 'round'");
  throws("  orientation_lead: {index_joint0: 0.4}\n", "mpc.orientation_lead.index_joint0",
         "is 'index_joint0'; expected a floating joint");
  throws("  orientation_lead: {ball_root_joint: -1}\n", "mpc.orientation_lead.ball_root_joint",
         "is -1; expected a finite positive number");
  throws("  orientation_lead: [ball_root_joint]\n", "mpc.orientation_lead", "is a list");
  throws("  mujoco_rolling_friction: -0.01\n", "mpc.mujoco_rolling_friction",
         "is -0.01; expected a finite non-negative number");
  throws("  mujoco_torsional_friction: lots\n", "mpc.mujoco_torsional_friction",
         "is 'lots'; expected a number");
}

TEST(MpcConfigTest, RealtimePriorityKey) {
  EXPECT_EQ(LoadText(MpcFile("  control_rate: 10\n")).mpc->closed_loop.realtime_priority, 0);
  EXPECT_EQ(LoadText(MpcFile("  realtime_priority: 20\n")).mpc->closed_loop.realtime_priority, 20);
  const std::string f = "rt_mpc.yaml";
  EXPECT_THAT(LoadingFile(f, MpcFile("  realtime_priority: 100\n")),
              ErrorAt(f, "mpc.realtime_priority", 17,
                      "is 100; expected 0 (off) or a SCHED_FIFO priority in [1, 99]"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  realtime_priority: -1\n")),
              ErrorAt(f, "mpc.realtime_priority", 17, "expected an integer >= 0"));
  EXPECT_THAT(LoadingFile(f, MpcFile("  realtime_priority: high\n")),
              ErrorAt(f, "mpc.realtime_priority", 17, "expected an integer"));
}

}  // namespace
}  // namespace idto
