// Example configuration files (YAML): every section read correctly.

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

constexpr double kTol = 1e-12;

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
  EXPECT_FALSE(config.mpc.has_value());
}

// fixtures/full.yaml, which sets every key, loaded once for the FullFixture* tests.
const ExampleConfig& FullConfig() {
  static const ExampleConfig config = LoadExampleConfig(FixturePath("full.yaml"), kShareDirs);
  return config;
}

TEST(ConfigTest, FullFixtureScene) {
  const ExampleConfig& config = FullConfig();
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
}

TEST(ConfigTest, FullFixtureContact) {
  const ProblemDefinition& p = FullConfig().problem;
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
}

TEST(ConfigTest, FullFixtureProblemAndInitialGuess) {
  const ExampleConfig& config = FullConfig();
  const ProblemDefinition& p = config.problem;
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

  // The nominal initial guess.
  const std::vector<Eigen::VectorXd> guess = MakeInitialGuess(config);
  ASSERT_EQ(guess.size(), 11u);
  EXPECT_EIGEN_NEAR(guess[0], q_init, 0.0);
  EXPECT_EIGEN_NEAR(guess[5], q_mid, 1e-12);
}

TEST(ConfigTest, FullFixtureSolverAndMpc) {
  const ExampleConfig& config = FullConfig();
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
  EXPECT_DOUBLE_EQ(s.constraint_correction, 0.25);  // the default is 0.5
  EXPECT_DOUBLE_EQ(s.cost_tolerance, 1e-8);
  EXPECT_DOUBLE_EQ(s.gradient_tolerance, 0);
  EXPECT_DOUBLE_EQ(s.step_tolerance, 1e-9);
  EXPECT_TRUE(s.fixed_iterations);
  EXPECT_FALSE(s.trial_derivatives);  // the default is true
  EXPECT_TRUE(s.kkt_extended_residual);
  EXPECT_DOUBLE_EQ(s.kkt_extended_threshold, 1e-9);
  EXPECT_EQ(s.verbosity, 1);

  // The mpc section, read with the rest of the file.
  ASSERT_TRUE(config.mpc.has_value());
  EXPECT_DOUBLE_EQ(config.mpc->controller.control_rate, 50);
  EXPECT_EQ(config.mpc->controller.iterations_per_step, 1);
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

TEST(ConfigTest, DerivativeMethods) {
  const auto method = [](const std::string& name) {
    return LoadText(With("max_iterations: 10", "max_iterations: 10\n  derivative_method: " + name))
        .solver.derivative_method;
  };
  EXPECT_EQ(method("analytic"), DerivativeMethod::kAnalytic);
  EXPECT_EQ(method("forward"), DerivativeMethod::kForwardDifferences);
  EXPECT_EQ(method("central"), DerivativeMethod::kCentralDifferences);
  // An unknown name: the error names the key, the value and the accepted names.
  EXPECT_THAT(
      Loading(With("max_iterations: 10", "derivative_method: exact")),
      ThrowsMessage<FileError>(AllOf(HasSubstr("solver.derivative_method"), HasSubstr("'exact'"),
                                     HasSubstr("one of forward, central, analytic"))));
}

TEST(ConfigTest, JointLimitPenalties) {
  // problem.limits: weights (off when absent) and per-joint velocity / effort maxima over the
  // model's; unknown keys and negative weights are errors naming the key.
  EXPECT_FALSE(LoadText(kBase).problem.limits.any());
  const ExampleConfig config =
      LoadText(With("q_init: [0, 0]",
                    "q_init: [0, 0]\n  limits: {position_weight: 100, effort_weight: 10,"
                    " effort: {elbow: 2.5}, velocity: 3}"));
  const LimitPenalties& l = config.problem.limits;
  EXPECT_EQ(l.position_weight, 100.0);
  EXPECT_EQ(l.velocity_weight, 0.0);
  EXPECT_EQ(l.effort_weight, 10.0);
  ASSERT_EQ(l.tau_max.size(), 2);
  EXPECT_EQ(l.tau_max(1), 2.5);
  EXPECT_EQ(l.tau_max(0), config.model.effort_limits()(0));
  EXPECT_EIGEN_NEAR(l.v_max, Eigen::Vector2d(3.0, 3.0), 0.0);
  EXPECT_THAT(Loading(With("q_init: [0, 0]", "q_init: [0, 0]\n  limits: {stiffness: 1}")),
              ThrowsMessage<FileError>(HasSubstr("problem.limits")));
  EXPECT_THAT(Loading(With("q_init: [0, 0]", "q_init: [0, 0]\n  limits: {effort_weight: -1}")),
              ThrowsMessage<FileError>(HasSubstr("problem.limits.effort_weight")));
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
}  // namespace
}  // namespace idto
