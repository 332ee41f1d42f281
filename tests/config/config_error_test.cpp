// Example configuration files (YAML): every kind of error reported with the file, the key
// path, the value found, what was expected and the line.

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

// ------------------------------------------------------------------------------ errors

TEST(ConfigErrorTest, MissingFile) {
  EXPECT_THAT(
      [] { LoadExampleConfig(FixturePath("no_such_file.yaml")); },
      ThrowsMessage<FileError>(AllOf(HasSubstr("no_such_file.yaml"), HasSubstr("no such file"))));
}

TEST(ConfigErrorTest, MalformedYaml) {
  EXPECT_THAT([] { LoadExampleConfig(FixturePath("syntax_error.yaml"), kShareDirs); },
              ThrowsMessage<FileError>(AllOf(HasSubstr("syntax_error.yaml"),
                                             HasSubstr("malformed YAML"), HasSubstr("line"))));
}

TEST(ConfigErrorTest, EmptyFile) {
  EXPECT_THAT(Loading(""), ThrowsMessage<FileError>(
                               AllOf(HasSubstr("test.yaml"), HasSubstr("the file is empty"))));
}

TEST(ConfigErrorTest, UnknownTopLevelKey) {
  EXPECT_THAT([] { LoadExampleConfig(FixturePath("unknown_top_level.yaml"), kShareDirs); },
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("unknown_top_level.yaml: solvers"), HasSubstr("unknown key"),
                        HasSubstr("expected one of name, description"), HasSubstr("(line 7)"))));
}

TEST(ConfigErrorTest, UnknownNestedKey) {
  EXPECT_THAT(
      Loading(With("    R: 0.01", "    R: 0.01\n    Qqq: 1")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("test.yaml: problem.weights.Qqq"),
                                     HasSubstr("unknown key"), HasSubstr("Qq, Qv, R, Qfq, Qfv"))));
  EXPECT_THAT(Loading(With("max_iterations: 10", "max_iteration: 10")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("solver.max_iteration: unknown key"),
                                             HasSubstr("max_iterations"))));
}

TEST(ConfigErrorTest, DuplicateKey) {
  EXPECT_THAT(
      Loading(With("  horizon: 1.0", "  horizon: 1.0\n  horizon: 2.0")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("problem.horizon"), HasSubstr("duplicate key"))));
}

TEST(ConfigErrorTest, MissingSection) {
  EXPECT_THAT(Loading("scene:\n  models:\n    - urdf: acrobot.urdf\n"),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("test.yaml: problem"), HasSubstr("missing (required)"))));
}

TEST(ConfigErrorTest, WrongSize) {
  EXPECT_THAT(
      Loading(With("q_init: [0, 0]", "q_init: [0, 0, 0]")),
      ThrowsMessage<FileError>(
          AllOf(HasSubstr("test.yaml: problem.q_init"), HasSubstr("a list of 3 entries [0, 0, 0]"),
                HasSubstr("expected a list of nq = 2 numbers"), HasSubstr("shoulder, elbow"))));
  EXPECT_THAT(Loading(With("    R: 0.01", "    R: {elbow: [1, 2]}")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("problem.weights.R.elbow"),
                                             HasSubstr("a list of 2 entries"),
                                             HasSubstr("expected a number"))));
  EXPECT_THAT(
      Loading(With("  models:", "  gravity: [0, -9.81]\n  models:")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("scene.gravity"), HasSubstr("a list of 2 entries"),
                                     HasSubstr("expected a list of 3 numbers"))));
}

TEST(ConfigErrorTest, NegativeWeight) {
  EXPECT_THAT(Loading(With("elbow: 0.2", "elbow: -1")),
              ThrowsMessage<FileError>(AllOf(
                  HasSubstr("test.yaml: problem.weights.Qq.elbow"), HasSubstr("is -1"),
                  HasSubstr("expected a finite non-negative number"), HasSubstr("(line 10)"))));
  EXPECT_THAT(
      Loading(With("    R: 0.01", "    R: [0.1, -0.5]")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("problem.weights.R[1]"), HasSubstr("is -0.5"))));
}

TEST(ConfigErrorTest, NonPositiveTimeStep) {
  EXPECT_THAT(Loading(With("time_step: 0.05", "time_step: 0")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("problem.time_step"), HasSubstr("is 0"),
                                             HasSubstr("expected a finite positive number"))));
  EXPECT_THAT(
      Loading(With("time_step: 0.05", "time_step: -0.05")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("problem.time_step"), HasSubstr("is -0.05"))));
}

TEST(ConfigErrorTest, NotANumber) {
  EXPECT_THAT(Loading(With("    R: 0.01", "    R: .nan")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("problem.weights.R"), HasSubstr("is nan"),
                                             HasSubstr("expected a finite"))));
  EXPECT_THAT(Loading(With("q_init: [0, 0]", "q_init: [0, .inf]")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("problem.q_init[1]"), HasSubstr("is inf"),
                                             HasSubstr("expected a finite number"))));
}

TEST(ConfigErrorTest, WrongType) {
  EXPECT_THAT(Loading(With("time_step: 0.05", "time_step: fast")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("problem.time_step"), HasSubstr("'fast'"),
                                             HasSubstr("expected a number"))));
  EXPECT_THAT(Loading(With("max_iterations: 10", "max_iterations: 2.5")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("solver.max_iterations"), HasSubstr("'2.5'"),
                                             HasSubstr("expected an integer"))));
  EXPECT_THAT(Loading(With("max_iterations: 10", "fixed_iterations: maybe")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("solver.fixed_iterations"),
                                             HasSubstr("expected true or false"))));
  EXPECT_THAT(Loading(With("  models:\n    - urdf: acrobot.urdf", "  models: acrobot.urdf")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.models"),
                                             HasSubstr("expected a non-empty list of models"))));
}

TEST(ConfigErrorTest, Horizon) {
  EXPECT_THAT(
      Loading(With("horizon: 1.0", "horizon: 1.01")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("problem.horizon"), HasSubstr("is 1.01"),
                                     HasSubstr("a positive multiple of time_step = 0.05"))));
  EXPECT_THAT(Loading(With("horizon: 1.0", "horizon: 1.0\n  num_steps: 20")),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("problem.horizon"), HasSubstr("given together with num_steps"))));
  EXPECT_THAT(Loading(With("  horizon: 1.0\n", "")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("problem.horizon"),
                                             HasSubstr("expected horizon (s) or num_steps"))));
  EXPECT_THAT(Loading(With("horizon: 1.0", "num_steps: 0")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("problem.num_steps"), HasSubstr("is 0"),
                                             HasSubstr("an integer >= 1"))));
  // One limit in both spellings of the length (10^7 steps).
  EXPECT_THAT(
      Loading(With("horizon: 1.0", "num_steps: 10000001")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("problem.num_steps"), HasSubstr("is 10000001"),
                                     HasSubstr("an integer from 1 to 10000000"))));
  EXPECT_THAT(Loading(With("horizon: 1.0", "horizon: 500000.05")),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("problem.horizon"), HasSubstr("at most 10000000 steps"))));
}

TEST(ConfigErrorTest, UnknownJoint) {
  EXPECT_THAT(
      Loading(With("q_init: [0, 0]", "q_init: {elbw: 1}")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("problem.q_init.elbw"), HasSubstr("unknown joint"),
                                     HasSubstr("one of shoulder, elbow"))));
  // `default` is for weights only.
  EXPECT_THAT(Loading(With("q_init: [0, 0]", "q_init: {default: 1}")),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("problem.q_init.default"), HasSubstr("weights only"))));
  EXPECT_THAT(Loading(With("  weights:", "  unactuated_dofs: [shoulder, wrist]\n  weights:")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("problem.unactuated_dofs[1]"),
                                             HasSubstr("'wrist'"), HasSubstr("a joint name"))));
  EXPECT_THAT(Loading(With("  weights:", "  unactuated_dofs: [5]\n  weights:")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("problem.unactuated_dofs[0]"),
                                             HasSubstr("a velocity index in [0, 2)"))));
}

TEST(ConfigErrorTest, BadEnumValue) {
  EXPECT_THAT(
      Loading(With("max_iterations: 10", "constraint_method: maybe")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("solver.constraint_method"), HasSubstr("'maybe'"),
                                     HasSubstr("one of none, penalty, lagrange"))));
  EXPECT_THAT(Loading(With("- urdf: acrobot.urdf", "- {urdf: acrobot.urdf, base: wobbly}")),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("scene.models[0].base"), HasSubstr("fixed, floating, planar"))));
}

TEST(ConfigErrorTest, InvalidSolverOptions) {
  EXPECT_THAT(
      Loading(With("max_iterations: 10", "initial_trust_radius: 10\n  max_trust_radius: 1")),
      ThrowsMessage<FileError>(
          AllOf(HasSubstr("test.yaml: solver: invalid options"), HasSubstr("max_trust_radius"))));
  EXPECT_THAT(Loading(With("max_iterations: 10", "constraint_correction: 20")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("test.yaml: solver: invalid options"),
                                             HasSubstr("constraint_correction"), HasSubstr("20"),
                                             HasSubstr("in [0, 10]"))));
}

TEST(ConfigErrorTest, Urdf) {
  EXPECT_THAT(Loading(With("urdf: acrobot.urdf", "urdf: no_such_robot.urdf")),
              ThrowsMessage<FileError>(AllOf(
                  HasSubstr("scene.models[0].urdf"),
                  HasSubstr("cannot find URDF file 'no_such_robot.urdf'"), HasSubstr("searched"))));
  EXPECT_THAT(
      Loading(With("urdf: acrobot.urdf", "urdf: ../urdf/errors/negative_mass.urdf")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("test.yaml: scene.models[0].urdf: cannot load"),
                                     HasSubstr("negative_mass.urdf"))));
  EXPECT_THAT(
      Loading(With("- urdf: acrobot.urdf", "- {urdf: acrobot.urdf, planar_normal: [0, 1, 0]}")),
      ThrowsMessage<FileError>(
          AllOf(HasSubstr("scene.models[0].planar_normal"), HasSubstr("expected base: planar"))));
  EXPECT_THAT(Loading(With("- urdf: acrobot.urdf",
                           "- {urdf: acrobot.urdf, rpy: [0, 0, 0], quaternion: [1, 0, 0, 0]}")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.models[0].quaternion"),
                                             HasSubstr("given together with rpy"))));
}

TEST(ConfigErrorTest, Geometry) {
  const auto scene_with = [](const std::string& geometry) {
    return With("  models:", "  geometry:\n    - " + geometry + "\n  models:");
  };
  EXPECT_THAT(Loading(scene_with("{name: b, shape: box}")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].size"),
                                             HasSubstr("missing (required by shape box)"))));
  EXPECT_THAT(Loading(scene_with("{name: g, shape: half_space, radius: 1}")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].radius"),
                                             HasSubstr("not used by shape half_space"))));
  EXPECT_THAT(Loading(scene_with("{name: s, shape: sphere, radius: -0.1}")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].radius"),
                                             HasSubstr("is -0.1"), HasSubstr("positive"))));
  EXPECT_THAT(Loading(scene_with("{name: s, shape: sphere, radius: 0.1, body: hand}")),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("scene.geometry[0].body"), HasSubstr("unknown body 'hand'"))));
  EXPECT_THAT(Loading(scene_with("{name: s, shape: blob}")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].shape"),
                                             HasSubstr("'blob'"), HasSubstr("half_space"))));
  EXPECT_THAT(
      Loading(scene_with("{name: b, shape: box, size: [1, 0, 1]}")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].size[1]"), HasSubstr("is 0"))));
}

TEST(ConfigErrorTest, InscribedSpheres) {
  const auto scene_with = [](const std::string& geometry) {
    return With("  models:", "  geometry:\n    - " + geometry + "\n  models:");
  };
  const std::string box = "{name: b, shape: box, size: [0.1, 0.1, 0.1], inscribed_spheres: ";
  EXPECT_THAT(Loading(scene_with("{name: s, shape: sphere, radius: 0.1, inscribed_spheres: true}")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].inscribed_spheres"),
                                             HasSubstr("not used by shape sphere"),
                                             HasSubstr("only with shape: box"))));
  EXPECT_THAT(
      Loading(scene_with(box + "maybe}")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].inscribed_spheres"),
                                     HasSubstr("'maybe'"), HasSubstr("true, false or a map"))));
  EXPECT_THAT(Loading(scene_with(box + "[1, 2]}")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].inscribed_spheres"),
                                             HasSubstr("a list of 2 entries"))));
  EXPECT_THAT(Loading(scene_with(box + "{radius_fraction: 0.7}}")),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("scene.geometry[0].inscribed_spheres.radius_fraction"),
                        HasSubstr("is 0.7"), HasSubstr("(0, 0.5]"))));
  EXPECT_THAT(
      Loading(scene_with(box + "{num_per_axis: 1}}")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].inscribed_spheres.num_per_axis"),
                                     HasSubstr("is 1"), HasSubstr("integer >= 2"))));
  EXPECT_THAT(
      Loading(scene_with(box + "{num_per_axis: 101}}")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].inscribed_spheres.num_per_axis"),
                                     HasSubstr("from 2 to 100"))));
  EXPECT_THAT(
      Loading(scene_with(box + "{centre_sphere: true}}")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].inscribed_spheres.centre_sphere"),
                                     HasSubstr("unknown key"), HasSubstr("center_sphere"))));
  EXPECT_THAT(
      Loading(scene_with(box + "{center_sphere: 3}}")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("scene.geometry[0].inscribed_spheres.center_sphere"),
                                     HasSubstr("true or false"))));
  EXPECT_THAT(
      Loading(With("    - urdf: acrobot.urdf",
                   "    - urdf: acrobot.urdf\n"
                   "    - {urdf: box.urdf, base: floating, inscribed_spheres: "
                   "{radius_fraction: 0}}")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("scene.models[1].inscribed_spheres.radius_fraction"),
                                     HasSubstr("is 0"))));
  // A sphere name that the replacement did not make is unknown to the contact filters.
  EXPECT_THAT(Loading(With("  models:", "  geometry:\n    - " + box +
                                            "true}\n  contact: {excluded_pairs: [[b, b_sphere8]]}"
                                            "\n  models:")),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("scene.contact.excluded_pairs[0][0]"), HasSubstr("'b'"))));
}

TEST(ConfigErrorTest, Contact) {
  const auto contact_with = [](const std::string& contact) {
    return With("  models:", "  contact:\n    " + contact + "\n  models:");
  };
  EXPECT_THAT(Loading(contact_with("stiffness: -5")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.contact.stiffness"),
                                             HasSubstr("is -5"), HasSubstr("positive"))));
  EXPECT_THAT(
      Loading(contact_with("excluded_pairs: [['*', elbow_link]]")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("scene.contact.excluded_pairs[0][1]"),
                                     HasSubstr("'elbow_link'"), HasSubstr("a body name, or '*'"))));
  EXPECT_THAT(Loading(contact_with("excluded_pairs: [[upper_link]]")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.contact.excluded_pairs[0]"),
                                             HasSubstr("a pair of names"))));
  EXPECT_THAT(
      Loading(contact_with("overrides: [{a: '*', b: '*', mu: 1}]")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("scene.contact.overrides[0].mu"),
                                     HasSubstr("unknown key"), HasSubstr("friction_coefficient"))));
}

TEST(ConfigErrorTest, Nominal) {
  EXPECT_THAT(
      Loading(With("q_init: [0, 0]", "q_init: [0, 0]\n  nominal: {q_nom: [1, 1], q_end: [2, 2]}")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("problem.nominal.q_nom"),
                                     HasSubstr("given together with q_start/q_end"))));
  EXPECT_THAT(
      Loading(With("q_init: [0, 0]", "q_init: [0, 0]\n  nominal: {v_nom: [1, 1, 1]}")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("problem.nominal.v_nom"), HasSubstr("nv = 2"))));
}

TEST(ConfigErrorTest, MpcSectionIsAMap) {
  EXPECT_THAT(
      Loading(kBase + "mpc: 3\n"),
      ThrowsMessage<FileError>(AllOf(HasSubstr("test.yaml: mpc"), HasSubstr("expected a map"))));
}

TEST(ConfigErrorTest, ErrorsAreFileErrorsNamingFileAndKey) {
  try {
    LoadText(With("time_step: 0.05", "time_step: 0"));
    FAIL() << "no exception";
  } catch (const FileError& e) {
    EXPECT_EQ(e.file(), "test.yaml");
    EXPECT_EQ(e.element(), "problem.time_step");
  }
}
}  // namespace
}  // namespace idto
