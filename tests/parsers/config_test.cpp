// Example configuration files (YAML): every section read correctly, and every kind of error
// reported with the file, the key path, the value found and what was expected.

#include "idto/parsers/config.hpp"

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

#include "idto/core/errors.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "support/eigen_matchers.hpp"

namespace idto {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kTol = 1e-12;

std::string FixturePath(const std::string& name) {
  return std::string(IDTO_TEST_DATA_DIR) + "/config/" + name;
}

const std::vector<std::string> kShareDirs = {IDTO_SOURCE_DIR};

/// A small valid configuration (the acrobot, nq = nv = 2); tests replace one piece of it.
const std::string kBase = R"(name: base
scene:
  models:
    - urdf: acrobot.urdf
problem:
  time_step: 0.05
  horizon: 1.0
  q_init: [0, 0]
  weights:
    Qq: {default: 0.1, elbow: 0.2}
    R: 0.01
solver:
  max_iterations: 10
)";

/// kBase with `from` replaced by `to` (which must occur).
std::string With(const std::string& from, const std::string& to) {
  std::string text = kBase;
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

ExampleConfig LoadText(const std::string& text) {
  return LoadExampleConfigString(text, "test.yaml", FixturePath(""), kShareDirs);
}

/// A callable that loads `text`, for EXPECT_THAT(..., ThrowsMessage<FileError>(...)).
auto Loading(const std::string& text) {
  return [text]() { LoadText(text); };
}

// ------------------------------------------------------------------------------ happy paths

TEST(ConfigTest, BaseConfiguration) {
  const ExampleConfig config = LoadText(kBase);
  EXPECT_EQ(config.name, "base");
  EXPECT_EQ(config.source_file, "test.yaml");
  ASSERT_EQ(config.model.nq(), 2);
  const ProblemDefinition& p = config.problem;
  EXPECT_EQ(p.num_steps, 20);
  EXPECT_DOUBLE_EQ(p.time_step, 0.05);
  EXPECT_EIGEN_NEAR(p.Qq, Eigen::Vector2d(0.1, 0.2), kTol);
  EXPECT_EIGEN_NEAR(p.R, Eigen::Vector2d(0.01, 0.01), kTol);
  // Weights not given are zero; the nominal defaults to q_init, v_nom to zero.
  EXPECT_EIGEN_NEAR(p.Qv, Eigen::Vector2d::Zero(), 0.0);
  EXPECT_EIGEN_NEAR(p.Qfq, Eigen::Vector2d::Zero(), 0.0);
  ASSERT_EQ(p.q_nom.size(), 21u);
  ASSERT_EQ(p.v_nom.size(), 21u);
  EXPECT_EIGEN_NEAR(p.q_nom[20], p.q_init, 0.0);
  EXPECT_EIGEN_NEAR(p.v_nom[7], Eigen::Vector2d::Zero(), 0.0);
  EXPECT_EIGEN_NEAR(p.v_init, Eigen::Vector2d::Zero(), 0.0);
  EXPECT_FALSE(p.unactuated_dofs.has_value());
  EXPECT_EQ(config.solver.max_iterations, 10);
  EXPECT_EQ(config.solver.constraint_method, SolverOptions{}.constraint_method);
  EXPECT_EQ(config.initial_guess, InitialGuessType::kInterpolate);
  EXPECT_TRUE(config.mpc.empty());
}

TEST(ConfigTest, FullFixture) {
  const ExampleConfig config = LoadExampleConfig(FixturePath("full.yaml"), kShareDirs);
  EXPECT_EQ(config.name, "full_scene");
  EXPECT_EQ(config.description, "Acrobot and ball");
  EXPECT_EQ(config.task_success, "never");

  // Scene: two models, the acrobot prefixed and posed, the ball floating.
  const Model& model = config.model;
  ASSERT_EQ(model.nq(), 9);
  ASSERT_EQ(model.nv(), 8);
  EXPECT_EQ(model.GetPositionStart("a_shoulder"), 0);
  EXPECT_EQ(model.GetPositionStart("ball_root_joint"), 2);
  ASSERT_EQ(config.models.size(), 2u);
  EXPECT_EQ(config.models[0].options.prefix, "a_");
  EXPECT_EQ(config.models[0].options.base, BaseType::kFixed);
  EXPECT_EQ(config.models[1].options.base, BaseType::kFloating);
  EXPECT_TRUE(std::filesystem::exists(config.models[0].urdf_file));
  EXPECT_EIGEN_NEAR(config.models[0].options.X_WB.translation(), Eigen::Vector3d(0, 0, 2), kTol);
  EXPECT_EIGEN_NEAR(config.models[0].options.X_WB.linear(),
                    Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix(), kTol);
  EXPECT_EIGEN_NEAR(model.gravity(), Eigen::Vector3d(0, 0, -9.8), kTol);

  // Extra geometry, after the URDF's own.
  const auto& geometries = model.geometries();
  ASSERT_EQ(geometries.size(), 6u);
  EXPECT_EQ(geometries[model.GetGeometryIndex("ball_sphere")].body, model.GetBodyIndex("ball"));
  EXPECT_TRUE(
      std::holds_alternative<HalfSpace>(geometries[model.GetGeometryIndex("ground")].shape));
  const GeometryInstance& post = geometries[model.GetGeometryIndex("post")];
  ASSERT_TRUE(std::holds_alternative<Cylinder>(post.shape));
  EXPECT_DOUBLE_EQ(std::get<Cylinder>(post.shape).radius, 0.05);
  EXPECT_DOUBLE_EQ(std::get<Cylinder>(post.shape).length, 2.0);
  EXPECT_EQ(post.body, kWorldBody);
  EXPECT_EIGEN_NEAR(post.X_BG.translation(), Eigen::Vector3d(0, 0, 1), kTol);
  const GeometryInstance& block = geometries[model.GetGeometryIndex("block")];
  ASSERT_TRUE(std::holds_alternative<Box>(block.shape));
  EXPECT_EIGEN_NEAR(std::get<Box>(block.shape).size, Eigen::Vector3d(0.1, 0.2, 0.3), kTol);
  const GeometryInstance& tip = geometries[model.GetGeometryIndex("tip")];
  EXPECT_EQ(tip.body, model.GetBodyIndex("a_lower_link"));
  ASSERT_TRUE(std::holds_alternative<Sphere>(tip.shape));
  const GeometryInstance& rod = geometries[model.GetGeometryIndex("rod")];
  ASSERT_TRUE(std::holds_alternative<Capsule>(rod.shape));
  EXPECT_DOUBLE_EQ(std::get<Capsule>(rod.shape).length, 0.8);

  // Contact.
  const ProblemDefinition& p = config.problem;
  EXPECT_TRUE(p.enable_contact);
  EXPECT_DOUBLE_EQ(p.contact.parameters.stiffness, 500);
  EXPECT_DOUBLE_EQ(p.contact.parameters.smoothing, 0.005);
  EXPECT_DOUBLE_EQ(p.contact.parameters.dissipation_velocity, 0.2);
  EXPECT_DOUBLE_EQ(p.contact.parameters.friction_coefficient, 0.4);
  EXPECT_DOUBLE_EQ(p.contact.parameters.stiction_velocity, 0.05);
  EXPECT_DOUBLE_EQ(p.contact.force_tolerance, 1e-6);
  ASSERT_EQ(p.contact.excluded_pairs.size(), 2u);
  EXPECT_EQ(p.contact.excluded_pairs[1].first, "block");
  EXPECT_EQ(p.contact.excluded_pairs[1].second, "*");
  ASSERT_EQ(p.contact.collision_groups.size(), 1u);
  EXPECT_EQ(p.contact.collision_groups[0],
            (std::vector<std::string>{"a_upper_link", "a_lower_link"}));
  EXPECT_TRUE(p.contact.included_pairs.empty());
  ASSERT_EQ(p.contact.overrides.size(), 1u);
  EXPECT_EQ(p.contact.overrides[0].a, "ball_sphere");
  EXPECT_EQ(p.contact.overrides[0].b, "ground");
  EXPECT_EQ(p.contact.overrides[0].friction_coefficient, 0.9);
  EXPECT_EQ(p.contact.overrides[0].stiffness, 800);
  EXPECT_FALSE(p.contact.overrides[0].smoothing.has_value());

  // Problem.
  EXPECT_DOUBLE_EQ(p.time_step, 0.02);
  EXPECT_EQ(p.num_steps, 10);
  Eigen::VectorXd q_init(9);
  q_init << 0.1, 0, 1, 0, 0, 0, 1, 0, 0.06;
  EXPECT_EIGEN_NEAR(p.q_init, q_init, kTol);
  Eigen::VectorXd v_init(8);
  v_init << 0, -0.5, 0, 0, 1, 0.1, 0, 0;
  EXPECT_EIGEN_NEAR(p.v_init, v_init, kTol);
  // Nominal: q_start -> q_end; the ball's quaternion slerped (half a turn about z at k = N).
  ASSERT_EQ(p.q_nom.size(), 11u);
  EXPECT_EIGEN_NEAR(p.q_nom[0], q_init, kTol);
  Eigen::VectorXd q_mid(9);
  q_mid << (0.1 + M_PI) / 2, 0, std::sqrt(0.5), 0, 0, std::sqrt(0.5), 1.5, 0, 0.06;
  EXPECT_EIGEN_NEAR(p.q_nom[5], q_mid, 1e-12);
  Eigen::VectorXd q_end(9);
  q_end << M_PI, 0, 0, 0, 0, 1, 2, 0, 0.06;
  EXPECT_EIGEN_NEAR(p.q_nom[10], q_end, 1e-12);
  Eigen::VectorXd v_nom = Eigen::VectorXd::Zero(8);
  v_nom(5) = 0.5;
  EXPECT_EIGEN_NEAR(p.v_nom[3], v_nom, kTol);
  // Weights: defaults, per-joint values, lists, full vectors.
  Eigen::VectorXd Qq(9);
  Qq << 1, 2, 3, 3, 3, 3, 10, 10, 10;
  EXPECT_EIGEN_NEAR(p.Qq, Qq, kTol);
  EXPECT_EIGEN_NEAR(p.Qv, Eigen::VectorXd::Constant(8, 0.1), kTol);
  Eigen::VectorXd R(8);
  R << 0.01, 0.01, 1000, 1000, 1000, 1000, 1000, 1000;
  EXPECT_EIGEN_NEAR(p.R, R, kTol);
  Eigen::VectorXd Qfq(9);
  Qfq << 10, 20, 1, 1, 1, 1, 5, 5, 5;
  EXPECT_EIGEN_NEAR(p.Qfq, Qfq, kTol);
  EXPECT_EIGEN_NEAR(p.Qfv, Eigen::VectorXd::Ones(8), kTol);
  // Unactuated: the listed joint plus the floating base's six DoFs.
  ASSERT_TRUE(p.unactuated_dofs.has_value());
  EXPECT_EQ(*p.unactuated_dofs, (std::vector<int>{0, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(config.initial_guess, InitialGuessType::kNominal);

  // Solver: every key.
  const SolverOptions& s = config.solver;
  EXPECT_EQ(s.max_iterations, 42);
  EXPECT_EQ(s.num_threads, 2);
  EXPECT_EQ(s.constraint_method, ConstraintMethod::kLagrangeMultipliers);
  EXPECT_DOUBLE_EQ(s.penalty_weight, 500);
  EXPECT_EQ(s.derivative_method, DerivativeMethod::kCentralDifferences);
  EXPECT_DOUBLE_EQ(s.finite_difference_step, 1e-6);
  EXPECT_EQ(s.scaling, ScalingMethod::kSqrt);
  EXPECT_DOUBLE_EQ(s.initial_trust_radius, 0.5);
  EXPECT_DOUBLE_EQ(s.max_trust_radius, 100);
  EXPECT_DOUBLE_EQ(s.acceptance_ratio, 0.1);
  EXPECT_DOUBLE_EQ(s.cost_tolerance, 1e-8);
  EXPECT_DOUBLE_EQ(s.gradient_tolerance, 0);
  EXPECT_DOUBLE_EQ(s.step_tolerance, 1e-9);
  EXPECT_TRUE(s.fixed_iterations);
  EXPECT_EQ(s.verbosity, 1);

  // The reserved mpc section is kept as text.
  EXPECT_THAT(config.mpc, HasSubstr("replan_hz: 50"));
  EXPECT_THAT(config.mpc, HasSubstr("iterations_per_step: 1"));

  // The nominal initial guess.
  const std::vector<Eigen::VectorXd> guess = MakeInitialGuess(config);
  ASSERT_EQ(guess.size(), 11u);
  EXPECT_EIGEN_NEAR(guess[0], q_init, 0.0);
  EXPECT_EIGEN_NEAR(guess[5], q_mid, 1e-12);
}

TEST(ConfigTest, UrdfRelativeToTheFileAndNameFromTheFile) {
  const ExampleConfig config = LoadExampleConfig(FixturePath("relative_urdf.yaml"));
  EXPECT_EQ(config.name, "relative_urdf");
  ASSERT_EQ(config.model.nq(), 1);
  EXPECT_EQ(config.problem.num_steps, 10);
  EXPECT_DOUBLE_EQ(config.problem.q_init(0), 0.5);  // a number for a 1-DoF state
  EXPECT_DOUBLE_EQ(config.problem.q_nom[3](0), 1.0);
  EXPECT_DOUBLE_EQ(config.problem.Qq(0), 1.0);
}

TEST(ConfigTest, ExamplesLoad) {
  // Every example in the source tree loads (found by name, as idto-run finds them).
  const std::vector<std::string> names = ListExamples(kShareDirs);
  EXPECT_THAT(names, ::testing::IsSupersetOf({"pendulum", "acrobot"}));
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const std::string path = FindExampleConfig(name, kShareDirs);
    const ExampleConfig config = LoadExampleConfig(path, kShareDirs);
    EXPECT_EQ(config.name, name);
    EXPECT_FALSE(config.task_success.empty());
    EXPECT_FALSE(config.description.empty());
  }
}

TEST(ConfigTest, InscribedSpheresReplaceBoxes) {
  // A scene box with `inscribed_spheres: true` becomes InscribedSpheres(box): <name>_sphere0..8,
  // posed in the body like the box; a map chooses the layout; `false` keeps the box.
  const std::string geometry =
      "  geometry:\n"
      "    - {name: cube, shape: box, size: [0.15, 0.15, 0.15], position: [0.5, 0, 0.1],\n"
      "       rpy: [0, 0, 0.3], inscribed_spheres: true}\n"
      "    - {name: slab, shape: box, size: [0.2, 0.1, 0.05], body: lower_link,\n"
      "       inscribed_spheres: {num_per_axis: 3, radius_fraction: 0.2, center_sphere: false}}\n"
      "    - {name: kept, shape: box, size: [0.1, 0.1, 0.1], inscribed_spheres: false}\n"
      "  models:";
  const ExampleConfig config = LoadText(With("  models:", geometry));
  const Model& model = config.model;
  ASSERT_EQ(model.geometries().size(), 9u + 26u + 1u);
  Eigen::Isometry3d X_WCube = Eigen::Isometry3d::Identity();
  X_WCube.translation() = Eigen::Vector3d(0.5, 0, 0.1);
  X_WCube.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const std::vector<InscribedSphere> cube = InscribedSpheres(Box{Eigen::Vector3d::Constant(0.15)});
  for (std::size_t k = 0; k < cube.size(); ++k) {
    SCOPED_TRACE(k);
    const GeometryInstance& g =
        model.geometries()[model.GetGeometryIndex("cube_sphere" + std::to_string(k))];
    EXPECT_EQ(g.body, kWorldBody);
    ASSERT_TRUE(std::holds_alternative<Sphere>(g.shape));
    EXPECT_DOUBLE_EQ(std::get<Sphere>(g.shape).radius, cube[k].sphere.radius);
    EXPECT_EIGEN_NEAR(g.X_BG.matrix(), (X_WCube * cube[k].X_BoxSphere).matrix(), kTol);
  }
  EXPECT_DOUBLE_EQ(cube[8].sphere.radius, 0.075);  // the centre sphere comes last
  const GeometryInstance& slab = model.geometries()[model.GetGeometryIndex("slab_sphere25")];
  EXPECT_EQ(slab.body, model.GetBodyIndex("lower_link"));
  EXPECT_DOUBLE_EQ(std::get<Sphere>(slab.shape).radius, 0.2 * 0.05);
  EXPECT_TRUE(
      std::holds_alternative<Box>(model.geometries()[model.GetGeometryIndex("kept")].shape));
  // Contact filters can name the spheres.
  const std::string without_models = geometry.substr(0, geometry.rfind("  models:"));
  EXPECT_NO_THROW(LoadText(With(
      "  models:",
      without_models + "  contact: {excluded_pairs: [[cube_sphere8, slab_sphere0]]}\n  models:")));
}

TEST(ConfigTest, InscribedSpheresOfUrdfBoxes) {
  // scene.models[i].inscribed_spheres replaces every box collision of the URDF.
  std::string text =
      With("    - urdf: acrobot.urdf",
           "    - urdf: acrobot.urdf\n"
           "    - {urdf: box.urdf, base: floating, inscribed_spheres: true, prefix: b_}");
  text.replace(text.find("q_init: [0, 0]"), 14, "q_init: {shoulder: 0, elbow: 0}");
  const ExampleConfig config = LoadText(text);
  const Model& model = config.model;
  EXPECT_EQ(model.nv(), 2 + 6);
  ASSERT_EQ(model.geometries().size(), 9u);
  for (int k = 0; k < 9; ++k) {
    const GeometryInstance& g =
        model.geometries()[model.GetGeometryIndex("b_box_sphere" + std::to_string(k))];
    EXPECT_EQ(g.body, model.GetBodyIndex("b_box"));
  }
  ASSERT_EQ(config.models.size(), 2u);
  ASSERT_TRUE(config.models[1].options.box_inscribed_spheres.has_value());
  EXPECT_EQ(config.models[1].options.box_inscribed_spheres->num_per_axis, 2);
  EXPECT_FALSE(config.models[0].options.box_inscribed_spheres.has_value());
}

TEST(ConfigTest, Pendulum) {
  const ExampleConfig config =
      LoadExampleConfig(FindExampleConfig("pendulum", kShareDirs), kShareDirs);
  ASSERT_EQ(config.model.nq(), 1);
  EXPECT_EQ(config.problem.num_steps, 40);
  EXPECT_DOUBLE_EQ(config.problem.q_init(0), 0.0);
  EXPECT_DOUBLE_EQ(config.problem.q_nom.back()(0), M_PI);
  EXPECT_EQ(config.solver.max_iterations, 200);
  EXPECT_FALSE(config.problem.enable_contact);
  // The swing-up starts from hanging still at every step.
  EXPECT_EQ(config.initial_guess, InitialGuessType::kConstant);
  const std::vector<Eigen::VectorXd> guess = MakeInitialGuess(config);
  ASSERT_EQ(guess.size(), 41u);
  EXPECT_DOUBLE_EQ(guess[40](0), 0.0);
}

TEST(ConfigTest, Acrobot) {
  const ExampleConfig config =
      LoadExampleConfig(FindExampleConfig("acrobot", kShareDirs), kShareDirs);
  ASSERT_EQ(config.model.nq(), 2);
  EXPECT_EQ(config.model.GetVelocityStart("shoulder"), 0);
  EXPECT_EQ(config.problem.num_steps, 60);
  ASSERT_TRUE(config.problem.unactuated_dofs.has_value());
  EXPECT_EQ(*config.problem.unactuated_dofs, std::vector<int>{0});
  EXPECT_EQ(config.solver.constraint_method, ConstraintMethod::kLagrangeMultipliers);
  EXPECT_EIGEN_NEAR(config.problem.q_nom.back(), Eigen::Vector2d(M_PI, 0.0), kTol);
}

TEST(ConfigTest, PiExpressions) {
  const ExampleConfig config =
      LoadText(With("q_init: [0, 0]", "q_init: [-pi/2, 2*pi]\n  v_init: [pi, '0.5 * pi / 2']"));
  EXPECT_EIGEN_NEAR(config.problem.q_init, Eigen::Vector2d(-M_PI / 2, 2 * M_PI), kTol);
  EXPECT_EIGEN_NEAR(config.problem.v_init, Eigen::Vector2d(M_PI, M_PI / 4), kTol);
}

TEST(ConfigTest, InitialGuessTypes) {
  ExampleConfig config = LoadText(
      With("q_init: [0, 0]", "q_init: [0, 0]\n  nominal: {q_nom: {shoulder: 1, elbow: 2}}"));
  EXPECT_EQ(config.initial_guess, InitialGuessType::kInterpolate);
  std::vector<Eigen::VectorXd> guess = MakeInitialGuess(config);
  ASSERT_EQ(guess.size(), 21u);
  EXPECT_EIGEN_NEAR(guess[10], Eigen::Vector2d(0.5, 1.0), kTol);
  config.initial_guess = InitialGuessType::kConstant;
  guess = MakeInitialGuess(config);
  EXPECT_EIGEN_NEAR(guess[10], Eigen::Vector2d::Zero(), 0.0);
  config.initial_guess = InitialGuessType::kNominal;
  guess = MakeInitialGuess(config);
  EXPECT_EIGEN_NEAR(guess[0], Eigen::Vector2d::Zero(), 0.0);
  EXPECT_EIGEN_NEAR(guess[10], Eigen::Vector2d(1.0, 2.0), 0.0);
  EXPECT_EQ(InitialGuessTypeName(InitialGuessType::kNominal), "nominal");
}

TEST(ConfigTest, FindExampleConfig) {
  const std::string pendulum = FindExampleConfig("pendulum", kShareDirs);
  EXPECT_TRUE(std::filesystem::equivalent(
      pendulum, std::string(IDTO_SOURCE_DIR) + "/examples/pendulum/pendulum.yaml"));
  // An existing path is returned as given; the search folders are tried in order.
  EXPECT_EQ(FindExampleConfig(FixturePath("full.yaml"), {}), FixturePath("full.yaml"));
  EXPECT_EQ(FindExampleConfig("pendulum", {"/nonexistent", IDTO_SOURCE_DIR}), pendulum);
  EXPECT_THAT([] { FindExampleConfig("no_such_example", kShareDirs); },
              ThrowsMessage<FileError>(AllOf(HasSubstr("no_such_example"),
                                             HasSubstr("examples/no_such_example/"),
                                             HasSubstr("pendulum"))));
  EXPECT_THAT([] { FindExampleConfig("missing/file.yaml", kShareDirs); },
              ThrowsMessage<FileError>(HasSubstr("missing/file.yaml: no such file")));
}

TEST(ConfigTest, DefaultShareDirs) {
  const char* old = std::getenv("IDTO_SHARE_DIR");
  const std::string saved = old != nullptr ? old : "";
  setenv("IDTO_SHARE_DIR", "/opt/share/idto", 1);
  EXPECT_EQ(DefaultShareDirs("/src", "/usr/local/bin/idto-run"),
            (std::vector<std::string>{"/opt/share/idto", "/src", "/usr/local/share/idto"}));
  unsetenv("IDTO_SHARE_DIR");
  EXPECT_EQ(DefaultShareDirs("", "/usr/local/bin/idto-run"),
            (std::vector<std::string>{"/usr/local/share/idto"}));
  if (old != nullptr) setenv("IDTO_SHARE_DIR", saved.c_str(), 1);
}

TEST(ConfigTest, InterpolateConfigurationSlerps) {
  const ExampleConfig config = LoadExampleConfig(FixturePath("full.yaml"), kShareDirs);
  Eigen::VectorXd a = config.problem.q_init;
  Eigen::VectorXd b = a;
  // -q is the same rotation: the shortest arc is taken and the result stays normalized.
  b.segment<4>(2) << -std::sqrt(0.5), 0, 0, -std::sqrt(0.5);
  const Eigen::VectorXd q = InterpolateConfiguration(config.model, a, b, 0.5);
  EXPECT_NEAR(q.segment<4>(2).norm(), 1.0, kTol);
  const Eigen::Quaterniond Q(q(2), q(3), q(4), q(5));
  EXPECT_NEAR(Eigen::AngleAxisd(Q).angle(), M_PI / 4, 1e-12);
}

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
      Loading(contact_with("excluded_pairs: [[upper_link, elbow_link]]")),
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

TEST(ConfigErrorTest, ReservedMpcSection) {
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
