// Contact on a model: pair selection and filters, forces on both bodies, Newton's third law,
// generalized contact forces against point Jacobians, pruning, allocation-free evaluation.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "support/eigen_matchers.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using ::testing::HasSubstr;

// Two free balls above a ground plane, plus a two-link arm with a fingertip sphere.
Model Scene() {
  ModelBuilder builder("scene");
  builder.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  for (const char* name : {"ball1", "ball2"}) {
    JointSpec j;
    j.name = std::string(name) + "_free";
    j.type = JointType::kFloating;
    const BodyIndex b = builder.AddBody(name, test::SolidBall(0.5, 0.1), kWorldBody, j);
    builder.AddGeometry(std::string(name) + "_sphere", b, Eigen::Isometry3d::Identity(),
                        Sphere{0.1});
  }
  JointSpec shoulder;
  shoulder.name = "shoulder";
  shoulder.type = JointType::kRevolute;
  shoulder.axis = Eigen::Vector3d::UnitY();
  shoulder.X_PJ.translation() << 0.0, 0.0, 1.0;
  const BodyIndex upper = builder.AddBody("upper", test::SolidBall(1.0, 0.1), kWorldBody, shoulder);
  builder.AddGeometry("upper_sphere", upper, Eigen::Isometry3d::Identity(), Sphere{0.05});
  JointSpec elbow = shoulder;
  elbow.name = "elbow";
  elbow.X_PJ.translation() << 0.5, 0.0, 0.0;
  const BodyIndex lower = builder.AddBody("lower", test::SolidBall(1.0, 0.1), upper, elbow);
  Eigen::Isometry3d X_tip = Eigen::Isometry3d::Identity();
  X_tip.translation() << 0.5, 0.0, 0.0;
  builder.AddGeometry("tip", lower, X_tip, Sphere{0.02});
  return builder.Build();
}

bool HasPair(const Model& model, const ContactEngine& engine, const std::string& a,
             const std::string& b) {
  for (const ContactPair& p : engine.pairs()) {
    const std::string& ga = model.geometries()[p.geometry_a].name;
    const std::string& gb = model.geometries()[p.geometry_b].name;
    if ((ga == a && gb == b) || (ga == b && gb == a)) return true;
  }
  return false;
}

TEST(ContactEngine, PairsSkipSameBodyParentChildAndFilters) {
  const Model model = Scene();
  const ContactEngine engine(model, ContactOptions{});
  EXPECT_TRUE(HasPair(model, engine, "ground", "ball1_sphere"));
  EXPECT_TRUE(HasPair(model, engine, "ball1_sphere", "ball2_sphere"));
  EXPECT_TRUE(HasPair(model, engine, "ground", "tip"));
  EXPECT_FALSE(HasPair(model, engine, "upper_sphere", "tip"));  // parent and child
  // The upper arm hangs from the world on a hinge: no contact with world geometry.
  EXPECT_FALSE(HasPair(model, engine, "ground", "upper_sphere"));
  // Ground contacts put the half-space first.
  for (const ContactPair& p : engine.pairs()) {
    if (p.body_a == kWorldBody || p.body_b == kWorldBody) {
      EXPECT_EQ(model.geometries()[p.geometry_a].name, "ground");
    }
  }
  ContactOptions o;
  o.excluded_pairs = {{"ball1", "ball2"}};
  o.collision_groups = {{"tip", "ball1_sphere"}};
  const ContactEngine filtered(model, o);
  EXPECT_FALSE(HasPair(model, filtered, "ball1_sphere", "ball2_sphere"));
  EXPECT_FALSE(HasPair(model, filtered, "ball1_sphere", "tip"));
  EXPECT_TRUE(HasPair(model, filtered, "ball2_sphere", "tip"));
  ContactOptions only;
  only.included_pairs = {{"ground", "*"}};
  const ContactEngine included(model, only);
  for (const ContactPair& p : included.pairs()) {
    EXPECT_EQ(model.geometries()[p.geometry_a].name, "ground");
  }
  EXPECT_EQ(included.num_pairs(), 4);  // ground with ball1, ball2, upper (re-enabled), tip
}

TEST(ContactEngine, UnknownNamesAndBadParametersAreErrors) {
  const Model model = Scene();
  ContactOptions o;
  o.excluded_pairs = {{"ball1", "nope"}};
  EXPECT_THAT([&] { ContactEngine(model, o); },
              ::testing::ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("options.excluded_pairs[0]"), HasSubstr("\"nope\""))));
  ContactOptions p;
  ContactParameterOverride over;
  over.a = "ball1";
  over.b = "ground";
  over.friction_coefficient = -0.3;
  p.overrides = {over};
  EXPECT_THAT([&] { ContactEngine(model, p); },
              ::testing::ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("friction_coefficient is -0.3"), HasSubstr("ball1_sphere"))));
}

TEST(ContactEngine, ForcesAreEqualAndOppositeAndMatchPointJacobians) {
  const Model model = Scene();
  ContactOptions o;
  o.force_tolerance = 0.0;  // no pruning: every pair evaluated
  ContactParameterOverride over;
  over.a = "ball1";
  over.b = "ball2";
  over.friction_coefficient = 0.3;
  o.overrides = {over};
  const ContactEngine engine(model, o);
  ContactData cdata = engine.MakeData(model);
  Data data(model);
  test::Random rng(5);
  Eigen::VectorXd q = model.NeutralConfiguration();
  q.segment<3>(model.GetPositionStart("ball1_free") + 4) << 0.0, 0.0, 0.09;  // in penetration
  q.segment<3>(model.GetPositionStart("ball2_free") + 4) << 0.15, 0.05, 0.2;
  q(model.GetPositionStart("shoulder")) = 0.8;
  const Eigen::VectorXd v = rng.Vector(model.nv());
  ForwardKinematics(model, q, v, &data);
  engine.Evaluate(model, data, &cdata);
  EXPECT_EQ(cdata.num_active, engine.num_pairs());
  EXPECT_EQ(cdata.num_pruned, 0);
  // Generalized contact force: sum over pairs of (J_B(C) - J_A(C))^T f.
  Eigen::VectorXd tau_jac = Eigen::VectorXd::Zero(model.nv());
  Eigen::Matrix3Xd Ja, Jb;
  for (int i = 0; i < cdata.num_active; ++i) {
    const ContactResult& r = cdata.results[i];
    const ContactPair& p = engine.pairs()[r.pair];
    const Eigen::Vector3d p_BC = data.pose(p.body_b).inverse() * r.p_WC;
    const Eigen::Vector3d p_AC = data.pose(p.body_a).inverse() * r.p_WC;
    CalcPointJacobian(model, data, p.body_b, p_BC, &Jb);
    CalcPointJacobian(model, data, p.body_a, p_AC, &Ja);
    tau_jac += (Jb - Ja).transpose() * r.force.f;
    // The contact velocity is (J_B - J_A) v.
    const Eigen::Vector3d v_c = (Jb - Ja) * v;
    EXPECT_NEAR(r.vn, r.normal_W.dot(v_c), 1e-12);
    EXPECT_EIGEN_NEAR(r.vt, Eigen::Vector3d(v_c - r.vn * r.normal_W), 1e-12);
    if (model.geometries()[p.geometry_a].name == "ball1_sphere" &&
        model.geometries()[p.geometry_b].name == "ball2_sphere") {
      EXPECT_EQ(p.parameters.friction_coefficient, 0.3);
    }
  }
  Eigen::VectorXd tau_c;
  GeneralizedForceFromBodyForces(model, cdata.F_ext, &data, &tau_c);
  EXPECT_EIGEN_NEAR_REL(tau_c, tau_jac, 1e-12);
  // Newton's third law: without the ground (a world body), all contact wrenches about the
  // world origin cancel.
  ContactOptions no_ground = o;
  no_ground.excluded_pairs = {{"ground", "*"}};
  const ContactEngine free_engine(model, no_ground);
  ContactData fdata = free_engine.MakeData(model);
  free_engine.Evaluate(model, data, &fdata);
  Eigen::Matrix<double, 6, 1> total = Eigen::Matrix<double, 6, 1>::Zero();
  for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
    const Eigen::Vector3d f = fdata.F_ext.col(b).tail<3>();
    total.head<3>() += fdata.F_ext.col(b).head<3>() + data.p_WB(b).cross(f);
    total.tail<3>() += f;
  }
  EXPECT_EIGEN_NEAR(total, (Eigen::Matrix<double, 6, 1>::Zero()), 1e-12);
  EXPECT_GT(fdata.F_ext.norm(), 0.0);
}

TEST(ContactEngine, GroundPushesABallUpWithTheLawsForce) {
  const Model model = Scene();
  ContactOptions o;
  o.parameters.stiffness = 1000.0;
  o.parameters.smoothing = 0.001;
  const ContactEngine engine(model, o);
  ContactData cdata = engine.MakeData(model);
  Data data(model);
  Eigen::VectorXd q = model.NeutralConfiguration();
  q.segment<3>(model.GetPositionStart("ball1_free") + 4) << 0.0, 0.0, 0.095;  // 5 mm deep
  q.segment<3>(model.GetPositionStart("ball2_free") + 4) << 3.0, 0.0, 2.0;    // far away
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());
  ForwardKinematics(model, q, v, &data);
  engine.Evaluate(model, data, &cdata);
  const BodyIndex ball1 = model.GetBodyIndex("ball1");
  const double fz = cdata.F_ext(5, ball1);
  double c, dc;
  ComplianceAndDerivative(o.parameters, -0.005, &c, &dc);
  EXPECT_NEAR(fz, c, 1e-9 * c);                                      // d(0) = 1
  EXPECT_NEAR(cdata.F_ext.col(ball1).head<3>().norm(), 0.0, 1e-12);  // through the centre
  // ball2 is 1.9 m above the ground: pruned (its force would be below 1e-8 N).
  EXPECT_GE(cdata.num_pruned, 1);
  EXPECT_EQ(cdata.F_ext.col(model.GetBodyIndex("ball2")).norm(), 0.0);
}

TEST(ContactEngine, PruningChangesForcesByLessThanTheTolerance) {
  const Model model = Scene();
  test::Random rng(9);
  for (double tol : {1e-6, 1e-3, 1e-1}) {
    ContactOptions pruned_options;
    pruned_options.force_tolerance = tol;
    pruned_options.parameters.smoothing = 0.02;
    ContactOptions full_options = pruned_options;
    full_options.force_tolerance = 0.0;
    const ContactEngine pruned(model, pruned_options), full(model, full_options);
    ContactData pd = pruned.MakeData(model), fd = full.MakeData(model);
    Data data(model);
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::VectorXd q = model.NeutralConfiguration();
      q.segment<3>(model.GetPositionStart("ball1_free") + 4) = rng.Vector(3, 0.0, 0.6);
      q.segment<3>(model.GetPositionStart("ball2_free") + 4) = rng.Vector(3, 0.0, 0.6);
      q(model.GetPositionStart("shoulder")) = rng.Uniform(-1.5, 1.5);
      const Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());  // d(v_n) = 1
      ForwardKinematics(model, q, v, &data);
      pruned.Evaluate(model, data, &pd);
      full.Evaluate(model, data, &fd);
      // Each pruned pair contributes at most tol to any force entry; forces (not moments).
      for (BodyIndex b = 1; b < model.num_bodies(); ++b) {
        EXPECT_LE((pd.F_ext.col(b).tail<3>() - fd.F_ext.col(b).tail<3>()).norm(),
                  tol * (1 + 1e-9) * pruned.num_pairs());
      }
    }
  }
}

TEST(ContactEngine, BroadPhaseOverStaticGeometryNeverMissesAPairWithinTheCutoff) {
  // Two free balls among 60 static spheres (some welded to a fixed body), near and far.
  const Model model = test::StaticCrowd(17, /*with_arm=*/false);
  test::Random rng(18);
  ContactOptions pruned_options;
  pruned_options.force_tolerance = 1e-3;
  ContactOptions full_options = pruned_options;
  full_options.force_tolerance = 0.0;
  const ContactEngine pruned(model, pruned_options), full(model, full_options);
  ContactData pd = pruned.MakeData(model), fd = full.MakeData(model);
  Data data(model);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::VectorXd q = model.NeutralConfiguration();
    q.segment<3>(model.GetPositionStart("ball1_free") + 4) = rng.Vector(3, -1.0, 1.0);
    q.segment<3>(model.GetPositionStart("ball2_free") + 4) = rng.Vector(3, -1.0, 1.0);
    ForwardKinematics(model, q, Eigen::VectorXd::Zero(model.nv()), &data);
    pruned.Evaluate(model, data, &pd);
    full.Evaluate(model, data, &fd);
    EXPECT_GT(pd.num_pruned, 0);
    for (int i = 0; i < fd.num_active; ++i) {
      const ContactResult& r = fd.results[i];
      if (r.phi > pruned.pairs()[r.pair].cutoff_distance) continue;
      bool found = false;
      for (int j = 0; j < pd.num_active; ++j) found = found || pd.results[j].pair == r.pair;
      EXPECT_TRUE(found) << "pair " << r.pair << " at phi " << r.phi << " missed";
      ++checked;
    }
    // Evaluated in pair order (deterministic).
    for (int j = 1; j < pd.num_active; ++j) EXPECT_LT(pd.results[j - 1].pair, pd.results[j].pair);
  }
  EXPECT_GT(checked, 50);
}

TEST(ContactEngine, EvaluateChangedReusesUnmovedPairsAndMatchesEvaluate) {
  const Model model = Scene();
  ContactOptions o;
  o.force_tolerance = 1e-6;
  const ContactEngine engine(model, o);
  ContactData reference = engine.MakeData(model), changed = engine.MakeData(model),
              fresh = engine.MakeData(model);
  Data data(model);
  test::Random rng(21);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q = model.NeutralConfiguration();
    q.segment<3>(model.GetPositionStart("ball1_free") + 4) = rng.Vector(3, -0.2, 0.2);
    q(model.GetPositionStart("ball1_free") + 6) = 0.09;
    q.segment<3>(model.GetPositionStart("ball2_free") + 4) = rng.Vector(3, -0.2, 0.3);
    q(model.GetPositionStart("shoulder")) = rng.Uniform(0.5, 1.5);
    q(model.GetPositionStart("elbow")) = rng.Uniform(-1.0, 1.0);
    Eigen::VectorXd v = rng.Vector(model.nv());
    ForwardKinematics(model, q, v, &data);
    engine.Evaluate(model, data, &reference);
    // Perturb the elbow: only the lower arm moves.
    q(model.GetPositionStart("elbow")) += 1e-3;
    v(model.GetVelocityStart("elbow")) += 0.1;
    std::vector<char> moved(model.num_bodies(), 0);
    moved[model.GetBodyIndex("lower")] = 1;
    ForwardKinematics(model, q, v, &data);
    engine.EvaluateChanged(model, data, reference, moved, &changed);
    engine.Evaluate(model, data, &fresh);
    ASSERT_EQ(changed.num_active, fresh.num_active);
    EXPECT_EIGEN_NEAR(changed.F_ext, fresh.F_ext, 1e-12);
    for (int i = 0; i < fresh.num_active; ++i) {
      EXPECT_EQ(changed.results[i].pair, fresh.results[i].pair);
    }
  }
  // Wrong sizes are errors.
  std::vector<char> short_mask(2, 0);
  EXPECT_THAT([&] { engine.EvaluateChanged(model, data, reference, short_mask, &changed); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("EvaluateChanged")));
}

TEST(ContactEngine, EvaluationDoesNotAllocate) {
  // Allocation counting lives in the multibody test binary; here check the buffers are reused.
  const Model model = Scene();
  const ContactEngine engine(model, ContactOptions{});
  ContactData cdata = engine.MakeData(model);
  Data data(model);
  const double* before = cdata.F_ext.data();
  const ContactResult* results_before = cdata.results.data();
  ForwardKinematics(model, model.NeutralConfiguration(), Eigen::VectorXd::Zero(model.nv()), &data);
  engine.Evaluate(model, data, &cdata);
  EXPECT_EQ(cdata.F_ext.data(), before);
  EXPECT_EQ(cdata.results.data(), results_before);
}

}  // namespace
}  // namespace idto
