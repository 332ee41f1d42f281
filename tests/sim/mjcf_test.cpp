// MJCF generation and the idto <-> MuJoCo coordinate maps, without MuJoCo (the numerical
// comparison against MuJoCo itself is tests/multibody/mujoco_oracle_test.cpp).

#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "support/eigen_matchers.hpp"
#include "support/random.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using test::Random;
using test::RandomConfiguration;
using test::RandomInertia;
using test::RandomPose;
using test::RandomTreeModel;
using test::RandomTreeOptions;
using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::ThrowsMessage;

// world -> base (floating, tilted J) -> arm (revolute) -> hand (fixed) -> finger (floating: not
// top level) ; world -> cart (planar) ; world -> post (fixed, with a half-space).
Model SmallModel() {
  Random rng(4);
  ModelBuilder builder("small&model");
  builder.SetGravity(Eigen::Vector3d(0.0, 1.0, -9.0));
  JointSpec base;
  base.name = "base_joint";
  base.type = JointType::kFloating;
  base.X_PJ = RandomPose(&rng);
  base.damping = 0.25;
  const BodyIndex b = builder.AddBody("base", RandomInertia(&rng), kWorldBody, base);
  JointSpec arm;
  arm.name = "arm_joint";
  arm.axis = Eigen::Vector3d(0, 1, 0);
  arm.lower_limit = -1.0;
  arm.upper_limit = 1.5;
  arm.effort_limit = 7.0;
  const BodyIndex a = builder.AddBody("arm", RandomInertia(&rng), b, arm);
  JointSpec weld;
  weld.name = "hand_weld";
  weld.type = JointType::kFixed;
  weld.X_PJ = RandomPose(&rng);
  const BodyIndex h = builder.AddBody("hand", RandomInertia(&rng), a, weld);
  JointSpec finger;
  finger.name = "finger_joint";
  finger.type = JointType::kFloating;
  builder.AddBody("finger", RandomInertia(&rng), h, finger);
  JointSpec cart;
  cart.name = "cart_joint";
  cart.type = JointType::kPlanar;
  builder.AddBody("cart", RandomInertia(&rng), kWorldBody, cart);
  JointSpec post;
  post.name = "post_weld";
  post.type = JointType::kFixed;
  const BodyIndex p = builder.AddBody("post", RandomInertia(&rng), kWorldBody, post);
  builder.AddFrame("tool", h, RandomPose(&rng));
  builder.AddGeometry("floor", p, Eigen::Isometry3d::Identity(), HalfSpace{});
  builder.AddGeometry("palm", h, RandomPose(&rng), Box{Eigen::Vector3d(0.1, 0.2, 0.3)});
  builder.AddGeometry("tip", a, RandomPose(&rng), Cylinder{0.02, 0.1});
  return builder.Build();
}

TEST(Mjcf, DescribesBodiesJointsAndOptions) {
  const Model model = SmallModel();
  MjcfOptions options;
  options.disable_contact = true;
  options.timestep = 0.002;
  const std::string xml = MakeMjcf(model, options);
  EXPECT_THAT(xml, HasSubstr("<mujoco model=\"small&amp;model\">"));
  EXPECT_THAT(xml, HasSubstr("<compiler angle=\"radian\" inertiafromgeom=\"false\"/>"));
  EXPECT_THAT(xml, HasSubstr("timestep=\"0.002\" gravity=\"0 1 -9\""));
  EXPECT_THAT(xml, HasSubstr("<flag contact=\"disable\"/>"));
  EXPECT_THAT(xml, HasSubstr("<joint name=\"base_joint\" type=\"free\" damping=\"0.25\""));
  EXPECT_THAT(xml, HasSubstr("<joint name=\"arm_joint\" type=\"hinge\" axis=\"0 1 0\""));
  // A floating joint below a moving body: three slides and a ball.
  EXPECT_THAT(xml, HasSubstr("<joint name=\"finger_joint_x\" type=\"slide\" axis=\"1 0 0\""));
  EXPECT_THAT(xml, HasSubstr("<joint name=\"finger_joint_ball\" type=\"ball\""));
  EXPECT_THAT(xml, HasSubstr("<joint name=\"cart_joint_theta\" type=\"hinge\" axis=\"0 0 1\""));
  // Welded bodies are not MuJoCo bodies; they become sites of their moving ancestor.
  EXPECT_THAT(xml, Not(HasSubstr("<body name=\"hand\"")));
  EXPECT_THAT(xml, HasSubstr("<site name=\"hand\""));
  EXPECT_THAT(xml, HasSubstr("<site name=\"tool\""));
  EXPECT_THAT(xml, HasSubstr("<geom name=\"floor\" type=\"plane\""));
  EXPECT_THAT(xml, HasSubstr("<geom name=\"palm\" type=\"box\" size=\"0.05 0.1 0.15\""));
  EXPECT_THAT(xml, HasSubstr("<geom name=\"tip\" type=\"cylinder\" size=\"0.02 0.05\""));
  EXPECT_THAT(xml, HasSubstr("diaginertia="));
  EXPECT_THAT(xml, Not(HasSubstr("fullinertia=")));
  EXPECT_THAT(xml, Not(HasSubstr("range=")));
  EXPECT_THAT(xml, Not(HasSubstr("<actuator>")));
}

TEST(Mjcf, OptionalParts) {
  const Model model = SmallModel();
  MjcfOptions options;
  options.include_geometry = false;
  options.include_sites = false;
  options.include_joint_limits = true;
  options.include_actuators = true;
  options.diagonalize_inertia = false;
  const std::string xml = MakeMjcf(model, options);
  EXPECT_THAT(xml, Not(HasSubstr("<geom")));
  EXPECT_THAT(xml, Not(HasSubstr("<site")));
  EXPECT_THAT(xml, Not(HasSubstr("<flag")));
  EXPECT_THAT(xml, HasSubstr("fullinertia="));
  EXPECT_THAT(xml, HasSubstr("limited=\"true\" range=\"-1 1.5\""));
  EXPECT_THAT(xml, HasSubstr("<motor name=\"arm_joint\" joint=\"arm_joint\" gear=\"1\" "
                             "ctrllimited=\"true\" ctrlrange=\"-7 7\"/>"));
}

TEST(Mjcf, RejectsInvalidOptions) {
  const Model model = SmallModel();
  MjcfOptions options;
  options.timestep = 0.0;
  EXPECT_THAT([&] { MakeMjcf(model, options); },
              ThrowsMessage<InvalidArgument>(HasSubstr("timestep is 0")));
  options = MjcfOptions{};
  options.integrator = "Verlet";
  std::string why;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_THAT(why, HasSubstr("'Verlet'"));
  EXPECT_THAT([&] { MakeMjcf(model, options); },
              ThrowsMessage<InvalidArgument>(HasSubstr("integrator is 'Verlet'")));
}

TEST(Mjcf, RejectsHalfSpaceOnMovingBody) {
  ModelBuilder builder("bad");
  JointSpec joint;
  joint.name = "j";
  BodyInertia inertia;
  inertia.mass = 1.0;
  inertia.I_BBcm_B = 0.01 * Eigen::Matrix3d::Identity();
  const BodyIndex b = builder.AddBody("link", inertia, kWorldBody, joint);
  builder.AddGeometry("moving_floor", b, Eigen::Isometry3d::Identity(), HalfSpace{});
  const Model model = builder.Build();
  EXPECT_THAT([&] { MakeMjcf(model); },
              ThrowsMessage<InvalidArgument>(HasSubstr("geometry 'moving_floor'")));
  MjcfOptions options;
  options.include_geometry = false;
  EXPECT_NO_THROW(MakeMjcf(model, options));
}

TEST(MujocoMap, StateRoundTripAndOrthogonalVelocityMap) {
  for (const BaseType base : {BaseType::kFixed, BaseType::kFloating, BaseType::kPlanar}) {
    RandomTreeOptions o;
    o.base = base;
    o.num_bodies = 10;
    const Model model = RandomTreeModel(17, o);
    const MujocoMap map(model);
    ASSERT_EQ(map.nq(), model.nq());
    ASSERT_EQ(map.nv(), model.nv());
    Random rng(8);
    const Eigen::VectorXd q = RandomConfiguration(model, &rng);
    const Eigen::VectorXd v = rng.Vector(model.nv());
    Eigen::VectorXd qpos(model.nq()), qvel(model.nv());
    map.IdtoToMujocoState(q, v, qpos.data(), qvel.data());
    Eigen::VectorXd q2, v2;
    map.MujocoToIdtoState(qpos.data(), qvel.data(), &q2, &v2);
    EXPECT_EIGEN_NEAR(q2, q, 1e-14);
    EXPECT_EIGEN_NEAR(v2, v, 1e-14);

    Eigen::MatrixXd T;
    map.VelocityMap(q, &T);
    EXPECT_EIGEN_NEAR(T * T.transpose(), Eigen::MatrixXd::Identity(model.nv(), model.nv()), 1e-14);
    EXPECT_EIGEN_NEAR(qvel, T * v, 1e-14);
    Eigen::VectorXd tau;
    map.MujocoToIdtoForce(q, qvel.data(), &tau);
    EXPECT_EIGEN_NEAR(tau, T.transpose() * qvel, 1e-14);

    // The free functions agree with the class.
    Eigen::VectorXd qpos2(model.nq()), qvel2(model.nv());
    IdtoToMujocoState(model, q, v, qpos2.data(), qvel2.data());
    EXPECT_EQ(qpos2, qpos);
    EXPECT_EQ(qvel2, qvel);
    Eigen::MatrixXd T2;
    IdtoToMujocoVelocityMap(model, q, &T2);
    EXPECT_EQ(T2, T);
  }
}

// A free joint's qpos is the world pose of its body, and its qvel is [v_WBo; w in B].
TEST(MujocoMap, FreeJointCarriesWorldPoseAndMujocoVelocity) {
  const Model model = SmallModel();
  const MujocoMap map(model);
  Random rng(2);
  const Eigen::VectorXd q = RandomConfiguration(model, &rng);
  const Eigen::VectorXd v = rng.Vector(model.nv());
  Data data(model);
  ForwardKinematics(model, q, v, &data);
  Eigen::VectorXd qpos(model.nq()), qvel(model.nv());
  map.IdtoToMujocoState(q, v, qpos.data(), qvel.data());
  const BodyIndex base = model.GetBodyIndex("base");
  const int iq = map.mujoco_qpos_start(base);
  const int iv = map.mujoco_dof_start(base);
  EXPECT_EQ(map.MujocoBodyId(base), 1);
  EXPECT_EIGEN_NEAR(qpos.segment<3>(iq), data.p_WB(base), 1e-14);
  const Eigen::Quaterniond Q(qpos(iq + 3), qpos(iq + 4), qpos(iq + 5), qpos(iq + 6));
  EXPECT_EIGEN_NEAR(Q.toRotationMatrix(), data.R_WB(base), 1e-14);
  const Eigen::Matrix<double, 6, 1> V = data.V_WB(base);
  EXPECT_EIGEN_NEAR(qvel.segment<3>(iv), V.tail<3>(), 1e-14);
  EXPECT_EIGEN_NEAR(qvel.segment<3>(iv + 3), data.R_WB(base).transpose() * V.head<3>(), 1e-14);
  // Welded bodies map to their moving ancestor at X_MB; bodies welded to the world to body 0.
  const BodyIndex hand = model.GetBodyIndex("hand");
  EXPECT_EQ(map.MujocoBodyId(hand), map.MujocoBodyId(model.GetBodyIndex("arm")));
  EXPECT_EQ(map.MujocoBodyId(model.GetBodyIndex("post")), 0);
  EXPECT_EIGEN_NEAR((data.X_WB(model.GetBodyIndex("arm")) * map.X_MB(hand)).matrix(),
                    data.X_WB(hand).matrix(), 1e-14);
  EXPECT_EQ(map.IdtoBodyOfMujocoBody(map.MujocoBodyId(base)), base);
}

}  // namespace
}  // namespace idto
