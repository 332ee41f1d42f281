// The mpc section's sub-sections: mpc.problem, mpc.contact, mpc.solver.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "config_test_helpers.hpp"
#include "idto/config/config.hpp"
#include "idto/core/errors.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "support/eigen_matchers.hpp"

namespace idto {
namespace {

using test::FixturePath;
using test::kBase;
using test::kShareDirs;
using test::Loading;
using test::LoadText;
using test::With;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// ------------------------------------------------------------------------------ mpc.problem

TEST(ConfigTest, MpcProblemOverridesMergeIntoTheOpenLoopProblem) {
  const ExampleConfig config = LoadText(kBase + R"(mpc:
  control_rate: 50
  problem:
    horizon: 0.5
    nominal: {q_end: [1.5, 0]}
    weights: {R: 0.5}
)");
  // The open-loop problem is unchanged.
  EXPECT_EQ(config.problem.num_steps, 20);
  EXPECT_DOUBLE_EQ(config.problem.R(0), 0.01);
  ASSERT_TRUE(config.mpc_problem.has_value());
  const ProblemDefinition& p = *config.mpc_problem;
  EXPECT_EQ(p.num_steps, 10);
  EXPECT_DOUBLE_EQ(p.q_nom.back()(0), 1.5);
  EXPECT_DOUBLE_EQ(p.q_nom[5](0), 0.75);  // interpolated from q_init over the new horizon
  // weights merged key by key: R replaced, Qq kept from the open-loop problem.
  EXPECT_DOUBLE_EQ(p.R(1), 0.5);
  EXPECT_DOUBLE_EQ(p.Qq(0), 0.1);
  EXPECT_DOUBLE_EQ(p.Qq(1), 0.2);
}

// horizon and num_steps spell one length: the controller's replaces the open loop's whichever
// spelling each uses (the open loop giving num_steps and the controller a horizon once failed
// with "given together with num_steps").
TEST(ConfigTest, MpcProblemLengthReplacesTheOpenLoopsInEitherSpelling) {
  const std::string with_steps = With("  horizon: 1.0\n", "  num_steps: 20\n");
  const ExampleConfig a = LoadText(with_steps + "mpc:\n  problem: {horizon: 0.5}\n");
  EXPECT_EQ(a.problem.num_steps, 20);
  EXPECT_EQ(a.mpc_problem->num_steps, 10);
  const ExampleConfig b = LoadText(kBase + "mpc:\n  problem: {num_steps: 7}\n");
  EXPECT_EQ(b.problem.num_steps, 20);
  EXPECT_EQ(b.mpc_problem->num_steps, 7);
  // A new time step alone keeps the open loop's spelling: horizon 1.0 s at 0.025 s is 40 steps,
  // num_steps 20 stays 20.
  EXPECT_EQ(LoadText(kBase + "mpc:\n  problem: {time_step: 0.025}\n").mpc_problem->num_steps, 40);
  EXPECT_EQ(LoadText(with_steps + "mpc:\n  problem: {time_step: 0.025}\n").mpc_problem->num_steps,
            20);
  EXPECT_THAT(Loading(kBase + "mpc:\n  problem: {horizon: 0.5, num_steps: 10}\n"),
              ThrowsMessage<FileError>(AllOf(HasSubstr("mpc.problem.horizon"),
                                             HasSubstr("given together with num_steps"))));
}

TEST(ConfigTest, NoMpcProblemWithoutTheKey) {
  EXPECT_FALSE(LoadText(kBase + "mpc: {control_rate: 50}\n").mpc_problem.has_value());
  EXPECT_FALSE(LoadText(kBase).mpc_problem.has_value());
}

TEST(ConfigTest, MpcProblemErrorsNameTheKey) {
  EXPECT_THAT(
      Loading(kBase + "mpc:\n  problem:\n    weights: {R: -1}\n"),
      ThrowsMessage<FileError>(AllOf(HasSubstr("test.yaml"), HasSubstr("mpc.problem.weights.R"))));
  EXPECT_THAT(Loading(kBase + "mpc:\n  problem:\n    no_such_key: 1\n"),
              ThrowsMessage<FileError>(HasSubstr("mpc.problem.no_such_key")));
}

// ------------------------------------------------------------------ mpc.contact, mpc.solver

TEST(ConfigTest, MpcContactReplacesTheControllersLawParametersOnly) {
  const std::string scene = With("    - urdf: acrobot.urdf\n",
                                 "    - urdf: acrobot.urdf\n  contact: {stiffness: 800, "
                                 "smoothing: 0.01, friction_coefficient: 0.5}\n");
  const ExampleConfig config = LoadText(scene + R"(mpc:
  contact: {stiffness: 20000, smoothing: 0.003}
)");
  // The open-loop problem (and so the plant's friction) keeps the scene's law.
  EXPECT_DOUBLE_EQ(config.problem.contact.parameters.stiffness, 800);
  EXPECT_DOUBLE_EQ(config.problem.contact.parameters.smoothing, 0.01);
  // The controller's problem exists even without mpc.problem: the same problem, its own law.
  ASSERT_TRUE(config.mpc_problem.has_value());
  const ContactParameters& p = config.mpc_problem->contact.parameters;
  EXPECT_DOUBLE_EQ(p.stiffness, 20000);
  EXPECT_DOUBLE_EQ(p.smoothing, 0.003);
  EXPECT_DOUBLE_EQ(p.friction_coefficient, 0.5);  // not given: the scene's
  EXPECT_EQ(p.dissipation_velocity, config.problem.contact.parameters.dissipation_velocity);
  EXPECT_EQ(config.mpc_problem->num_steps, config.problem.num_steps);
  EXPECT_FALSE(config.mpc_solver.has_value());
}

// mpc.contact.overrides: appended after the scene's (later overrides win) in the controller's
// problem only; the open-loop problem and the plants keep the scene's.
TEST(ConfigTest, MpcContactOverridesFollowTheScenesInTheControllerOnly) {
  // The acrobot has no collision geometry of its own: a ball at the tip of its lower link and the
  // ground (the upper link is hinged to the world, so nothing on it meets the ground).
  const std::string scene = With("    - urdf: acrobot.urdf\n",
                                 "    - urdf: acrobot.urdf\n  geometry:\n"
                                 "    - {name: ground, shape: half_space, position: [0, 0, -3]}\n"
                                 "    - {name: elbow_ball, shape: sphere, radius: 0.1, "
                                 "body: upper_link, position: [0, 0, -1]}\n"
                                 "    - {name: tip_ball, shape: sphere, radius: 0.1, "
                                 "body: lower_link, position: [0, 0, -1]}\n"
                                 "  contact: {smoothing: 0.01, "
                                 "overrides: [{a: lower_link, b: \"*\", smoothing: 0.005}]}\n");
  const ExampleConfig config = LoadText(scene + R"(mpc:
  contact: {smoothing: 0.002, overrides: [{a: tip_ball, b: ground, smoothing: 0.02, stiffness: 900}]}
)");
  ASSERT_EQ(config.problem.contact.overrides.size(), 1u);
  EXPECT_EQ(config.problem.contact.overrides[0].a, "lower_link");
  ASSERT_TRUE(config.mpc_problem.has_value());
  const ContactOptions& c = config.mpc_problem->contact;
  EXPECT_DOUBLE_EQ(c.parameters.smoothing, 0.002);
  ASSERT_EQ(c.overrides.size(), 2u);
  EXPECT_EQ(c.overrides[0].a, "lower_link");
  EXPECT_DOUBLE_EQ(*c.overrides[0].smoothing, 0.005);
  EXPECT_EQ(c.overrides[1].a, "tip_ball");
  EXPECT_EQ(c.overrides[1].b, "ground");
  EXPECT_DOUBLE_EQ(*c.overrides[1].smoothing, 0.02);
  EXPECT_DOUBLE_EQ(*c.overrides[1].stiffness, 900);
  EXPECT_FALSE(c.overrides[1].friction_coefficient.has_value());
  ASSERT_EQ(ParseMpcConfig(config).mujoco.pairs.overrides.size(), 1u);
  EXPECT_THAT(Loading(scene + "mpc:\n  contact: {overrides: [{a: no_such_body, b: \"*\"}]}\n"),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("mpc.contact.overrides[0].a"), HasSubstr("no_such_body"))));
  EXPECT_THAT(
      Loading(scene + "mpc:\n  contact: {overrides: [{a: lower_link, b: \"*\", smoothing: 0}]}\n"),
      ThrowsMessage<FileError>(HasSubstr("mpc.contact.overrides[0].smoothing")));
  // An override that changes no evaluated pair is refused, in mpc.contact as in scene.contact:
  // the two links are hinged to each other, the upper link to the world.
  for (const std::string pair : {"{a: upper_link, b: lower_link}", "{a: elbow_ball, b: ground}"}) {
    EXPECT_THAT(Loading(scene + "mpc:\n  contact: {overrides: [" + pair.substr(0, pair.size() - 1) +
                        ", smoothing: 0.1}]}\n"),
                ThrowsMessage<FileError>(AllOf(HasSubstr("mpc.contact.overrides[0]"),
                                               HasSubstr("matches no contact pair that is "
                                                         "evaluated"),
                                               HasSubstr("hinged"))))
        << pair;
  }
}

TEST(ConfigTest, MpcContactAndProblemCombine) {
  const ExampleConfig config = LoadText(kBase + R"(mpc:
  contact: {stiffness: 20000}
  problem: {time_step: 0.01}
)");
  ASSERT_TRUE(config.mpc_problem.has_value());
  EXPECT_DOUBLE_EQ(config.mpc_problem->contact.parameters.stiffness, 20000);
  EXPECT_EQ(config.mpc_problem->num_steps, 100);
  EXPECT_EQ(config.problem.num_steps, 20);
  EXPECT_NE(config.problem.contact.parameters.stiffness, 20000);
}

TEST(ConfigTest, MpcSolverMergesIntoTheOpenLoopSolverOptions) {
  const ExampleConfig config = LoadText(kBase + R"(mpc:
  solver: {constraint_method: penalty, initial_trust_radius: 0.001}
)");
  EXPECT_EQ(config.solver.constraint_method, SolverOptions{}.constraint_method);
  EXPECT_EQ(config.solver.initial_trust_radius, SolverOptions{}.initial_trust_radius);
  ASSERT_TRUE(config.mpc_solver.has_value());
  EXPECT_EQ(config.mpc_solver->constraint_method, ConstraintMethod::kPenalty);
  EXPECT_DOUBLE_EQ(config.mpc_solver->initial_trust_radius, 0.001);
  EXPECT_EQ(config.mpc_solver->max_iterations, 10);  // the open loop's (solver.max_iterations)
  EXPECT_FALSE(config.mpc_problem.has_value());
  EXPECT_FALSE(LoadText(kBase + "mpc: {control_rate: 50}\n").mpc_solver.has_value());
}

TEST(ConfigTest, MpcContactAndSolverErrorsNameTheKey) {
  EXPECT_THAT(Loading(kBase + "mpc:\n  contact: {stiffness: -5}\n"),
              ThrowsMessage<FileError>(AllOf(HasSubstr("test.yaml"),
                                             HasSubstr("mpc.contact.stiffness"), HasSubstr("-5"))));
  EXPECT_THAT(Loading(kBase + "mpc:\n  contact: {excluded_pairs: [[a, b]]}\n"),
              ThrowsMessage<FileError>(HasSubstr("mpc.contact.excluded_pairs")));
  EXPECT_THAT(Loading(kBase + "mpc:\n  contact: 3\n"),
              ThrowsMessage<FileError>(AllOf(HasSubstr("mpc.contact"), HasSubstr("map"))));
  EXPECT_THAT(Loading(kBase + "mpc:\n  solver: {max_iterations: -1}\n"),
              ThrowsMessage<FileError>(HasSubstr("mpc.solver.max_iterations")));
  EXPECT_THAT(Loading(kBase + "mpc:\n  solver: {constraint_method: magic}\n"),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("mpc.solver.constraint_method"), HasSubstr("magic"))));
  EXPECT_THAT(Loading(kBase + "mpc:\n  solver: {no_such_key: 1}\n"),
              ThrowsMessage<FileError>(HasSubstr("mpc.solver.no_such_key")));
}
}  // namespace
}  // namespace idto
