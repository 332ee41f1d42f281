// ModelBuilder: structure, merging of welded bodies, and every documented error with its message.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>

#include "idto/idto.hpp"
#include "support/eigen_matchers.hpp"

namespace idto {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

BodyInertia UnitInertia() {
  BodyInertia I;
  I.mass = 1.0;
  I.I_BBcm_B = Eigen::Matrix3d::Identity() * 0.01;
  return I;
}

JointSpec Revolute(const std::string& name) {
  JointSpec j;
  j.name = name;
  j.type = JointType::kRevolute;
  j.axis = Eigen::Vector3d::UnitZ();
  return j;
}

TEST(ModelBuilder, CountsCoordinatesAndNamesInBodyOrder) {
  ModelBuilder builder("robot");
  JointSpec free;
  free.name = "base";
  free.type = JointType::kFloating;
  const BodyIndex base = builder.AddBody("torso", UnitInertia(), kWorldBody, free);
  JointSpec slide = Revolute("slide");
  slide.type = JointType::kPrismatic;
  slide.lower_limit = -0.5;
  slide.upper_limit = 0.5;
  slide.effort_limit = 40.0;
  slide.damping = 0.2;
  const BodyIndex s = builder.AddBody("slider", UnitInertia(), base, slide);
  JointSpec spin = Revolute("spin");
  spin.type = JointType::kContinuous;
  builder.AddBody("wheel", UnitInertia(), s, spin);
  JointSpec plane = Revolute("plane");
  plane.type = JointType::kPlanar;
  builder.AddBody("puck", UnitInertia(), base, plane);
  const Model model = builder.Build();
  EXPECT_EQ(model.name(), "robot");
  EXPECT_EQ(model.nq(), 7 + 1 + 1 + 3);
  EXPECT_EQ(model.nv(), 6 + 1 + 1 + 3);
  EXPECT_EQ(model.num_bodies(), 5);
  EXPECT_EQ(model.GetPositionStart("slide"), 7);
  EXPECT_EQ(model.GetVelocityStart("slide"), 6);
  EXPECT_EQ(model.GetPositionStart("plane"), 9);
  EXPECT_EQ(model.GetVelocityStart("plane"), 8);
  EXPECT_EQ(model.velocity_name(7), "spin");
  EXPECT_EQ(model.GetBodyIndex("wheel"), 3);
  EXPECT_EQ(model.lower_position_limits()(7), -0.5);
  EXPECT_EQ(model.effort_limits()(6), 40.0);
  EXPECT_EQ(model.damping()(6), 0.2);
  // The floating base's 6 velocities are base DoFs; the planar joint is not on the world.
  for (int i = 0; i < model.nv(); ++i) EXPECT_EQ(model.is_base_velocity()[i], i < 6) << i;
  const Eigen::VectorXd q0 = model.NeutralConfiguration();
  EXPECT_EQ(q0(0), 1.0);
  EXPECT_EQ(q0.tail(q0.size() - 1).cwiseAbs().sum(), 0.0);
  EXPECT_NEAR(model.total_mass(), 4.0, 1e-15);
}

TEST(ModelBuilder, WeldedBodiesAreMergedIntoTheirMovingParent) {
  ModelBuilder builder;
  const BodyIndex link = builder.AddBody("link", UnitInertia(), kWorldBody, Revolute("hinge"));
  JointSpec weld;
  weld.name = "weld";
  weld.type = JointType::kFixed;
  weld.X_PJ.translation() << 1.0, 0.0, 0.0;
  BodyInertia point;
  point.mass = 2.0;
  point.I_BBcm_B = Eigen::Matrix3d::Identity() * 1e-3;
  builder.AddBody("weight", point, link, weld);
  const Model model = builder.Build();
  EXPECT_EQ(model.nv(), 1);
  EXPECT_EQ(model.num_moving_bodies(), 1);
  EXPECT_NEAR(model.merged_inertia(link).mass, 3.0, 1e-15);
  // About the hinge: 0.01 + 2 * 1^2 + 1e-3.
  Data data(model);
  Eigen::VectorXd q(1);
  q << 0.3;
  EXPECT_NEAR(MassMatrix(model, q, &data)(0, 0), 0.01 + 2.0 + 1e-3, 1e-14);
}

TEST(ModelBuilder, ErrorsNameTheBodyTheValueAndWhatWasExpected) {
  ModelBuilder builder;
  builder.AddBody("link", UnitInertia(), kWorldBody, Revolute("hinge"));
  EXPECT_THAT([&] { builder.AddBody("link", UnitInertia(), kWorldBody, Revolute("other")); },
              ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("body name"), HasSubstr("\"link\" (already used)"))));
  EXPECT_THAT(
      [&] { builder.AddBody("b2", UnitInertia(), kWorldBody, Revolute("hinge")); },
      ThrowsMessage<InvalidArgument>(AllOf(HasSubstr("joint name"), HasSubstr("\"hinge\""))));
  EXPECT_THAT([&] { builder.AddBody("b3", UnitInertia(), 7, Revolute("j3")); },
              ThrowsMessage<InvalidArgument>(AllOf(HasSubstr("parent of body \"b3\" is 7"),
                                                   HasSubstr("existing body index"))));
  BodyInertia negative = UnitInertia();
  negative.mass = -1.0;
  EXPECT_THAT([&] { builder.AddBody("b4", negative, kWorldBody, Revolute("j4")); },
              ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("mass of body \"b4\" is -1"), HasSubstr("non-negative"))));
  BodyInertia indefinite = UnitInertia();
  indefinite.I_BBcm_B(0, 0) = -0.01;
  EXPECT_THAT([&] { builder.AddBody("b5", indefinite, kWorldBody, Revolute("j5")); },
              ThrowsMessage<InvalidArgument>(HasSubstr("inertia of body \"b5\" is indefinite")));
  BodyInertia asymmetric = UnitInertia();
  asymmetric.I_BBcm_B(0, 1) = 0.001;
  EXPECT_THAT([&] { builder.AddBody("b6", asymmetric, kWorldBody, Revolute("j6")); },
              ThrowsMessage<InvalidArgument>(HasSubstr("not symmetric")));
  BodyInertia triangle = UnitInertia();
  triangle.I_BBcm_B = Eigen::Vector3d(0.01, 0.01, 0.05).asDiagonal();
  EXPECT_THAT([&] { builder.AddBody("b7", triangle, kWorldBody, Revolute("j7")); },
              ThrowsMessage<InvalidArgument>(HasSubstr("triangle inequality")));
  JointSpec zero_axis = Revolute("j8");
  zero_axis.axis.setZero();
  EXPECT_THAT([&] { builder.AddBody("b8", UnitInertia(), kWorldBody, zero_axis); },
              ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("axis of joint \"j8\" is (0, 0, 0)"), HasSubstr("non-zero"))));
  JointSpec damped = Revolute("j9");
  damped.damping = -0.1;
  EXPECT_THAT([&] { builder.AddBody("b9", UnitInertia(), kWorldBody, damped); },
              ThrowsMessage<InvalidArgument>(HasSubstr("damping of joint \"j9\" is -0.1")));
  JointSpec limits = Revolute("j10");
  limits.lower_limit = 1.0;
  limits.upper_limit = -1.0;
  EXPECT_THAT([&] { builder.AddBody("b10", UnitInertia(), kWorldBody, limits); },
              ThrowsMessage<InvalidArgument>(HasSubstr("limits of joint \"j10\" is [1, -1]")));
  JointSpec bad_pose = Revolute("j11");
  bad_pose.X_PJ.linear() *= 2.0;
  EXPECT_THAT([&] { builder.AddBody("b11", UnitInertia(), kWorldBody, bad_pose); },
              ThrowsMessage<InvalidArgument>(HasSubstr("X_PJ of joint \"j11\"")));
  EXPECT_THAT([&] { builder.AddGeometry("g", 0, Eigen::Isometry3d::Identity(), Sphere{-1.0}); },
              ThrowsMessage<InvalidArgument>(HasSubstr("radius of geometry \"g\" is -1")));
  EXPECT_THAT([&] { builder.AddFrame("link", 1, Eigen::Isometry3d::Identity()); },
              ThrowsMessage<InvalidArgument>(HasSubstr("frame name is \"link\" (already used)")));
}

// A JointSpec field the joint type does not use used to be dropped without a word: position
// limits exist on revolute and prismatic joints only, and a fixed joint has no damping, effort
// or velocity.
TEST(ModelBuilder, FieldsTheJointTypeDoesNotUseAreErrors) {
  ModelBuilder builder;
  const BodyIndex base = builder.AddBody("base", UnitInertia(), kWorldBody, Revolute("hinge"));
  int n = 0;
  auto add = [&](JointType type, const std::function<void(JointSpec*)>& set) {
    JointSpec j = Revolute("j" + std::to_string(++n));
    j.type = type;
    set(&j);
    builder.AddBody("b" + std::to_string(n), UnitInertia(), base, j);
  };
  const std::string kOnlyRevolute = "only revolute and prismatic joints have position limits";
  for (JointType type :
       {JointType::kContinuous, JointType::kFloating, JointType::kPlanar, JointType::kFixed}) {
    SCOPED_TRACE(JointTypeName(type));
    EXPECT_THAT([&] { add(type, [](JointSpec* j) { j->lower_limit = -1.0; }); },
                ThrowsMessage<InvalidArgument>(
                    AllOf(HasSubstr("limits of " + JointTypeName(type) + " joint \"j"),
                          HasSubstr("is [-1, inf]"), HasSubstr(kOnlyRevolute))));
    EXPECT_THAT([&] { add(type, [](JointSpec* j) { j->upper_limit = 2.0; }); },
                ThrowsMessage<InvalidArgument>(HasSubstr("is [-inf, 2]")));
  }
  EXPECT_THAT([&] { add(JointType::kFixed, [](JointSpec* j) { j->damping = 0.5; }); },
              ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("damping of fixed joint \"j"), HasSubstr("is 0.5"),
                        HasSubstr("expected 0: a fixed joint does not move"))));
  EXPECT_THAT([&] { add(JointType::kFixed, [](JointSpec* j) { j->effort_limit = 3.0; }); },
              ThrowsMessage<InvalidArgument>(HasSubstr("effort limit of fixed joint")));
  EXPECT_THAT([&] { add(JointType::kFixed, [](JointSpec* j) { j->velocity_limit = 3.0; }); },
              ThrowsMessage<InvalidArgument>(HasSubstr("velocity limit of fixed joint")));
  // The fields a joint does use are taken; infinite limits are the defaults, not values.
  add(JointType::kContinuous, [](JointSpec* j) {
    j->damping = 0.1;
    j->effort_limit = 2.0;
    j->velocity_limit = 3.0;
  });
  add(JointType::kFixed, [](JointSpec* j) { j->axis = Eigen::Vector3d::UnitX(); });
  const Model model = builder.Build();
  EXPECT_EQ(model.nv(), 2);
  EXPECT_EQ(model.damping()(1), 0.1);
  EXPECT_EQ(model.effort_limits()(1), 2.0);
  EXPECT_EQ(model.velocity_limits()(1), 3.0);
  EXPECT_EQ(model.position_lower_limits()(1), -std::numeric_limits<double>::infinity());
}

TEST(ModelBuilder, BuildRejectsMovingBodiesWithoutMass) {
  ModelBuilder builder;
  builder.AddBody("massless", BodyInertia{}, kWorldBody, Revolute("hinge"));
  EXPECT_THAT([&] { builder.Build(); },
              ThrowsMessage<InvalidArgument>(AllOf(HasSubstr("mass of moving body \"massless\""),
                                                   HasSubstr("positive mass"))));
  // A massless moving body is fine when a welded child carries the mass.
  ModelBuilder ok;
  const BodyIndex b = ok.AddBody("massless", BodyInertia{}, kWorldBody, Revolute("hinge"));
  JointSpec weld;
  weld.name = "weld";
  weld.type = JointType::kFixed;
  weld.X_PJ.translation() << 0.3, 0.0, 0.0;
  ok.AddBody("weight", UnitInertia(), b, weld);
  EXPECT_NO_THROW(ok.Build());
  // A point mass on a free joint has no rotational inertia: rejected.
  ModelBuilder point;
  BodyInertia p;
  p.mass = 1.0;
  JointSpec free;
  free.name = "free";
  free.type = JointType::kFloating;
  point.AddBody("point", p, kWorldBody, free);
  EXPECT_THAT([&] { point.Build(); },
              ThrowsMessage<InvalidArgument>(HasSubstr("not positive definite")));
}

TEST(ModelBuilder, UnknownNamesThrow) {
  ModelBuilder builder;
  builder.AddBody("link", UnitInertia(), kWorldBody, Revolute("hinge"));
  const Model model = builder.Build();
  EXPECT_THAT(
      [&] { model.GetBodyIndex("nope"); },
      ThrowsMessage<InvalidArgument>(AllOf(HasSubstr("GetBodyIndex"), HasSubstr("\"nope\""))));
  EXPECT_THAT([&] { model.GetPositionStart("nope"); },
              ThrowsMessage<InvalidArgument>(HasSubstr("GetPositionStart")));
  EXPECT_THAT([&] { model.GetVelocityStart("nope"); },
              ThrowsMessage<InvalidArgument>(HasSubstr("GetVelocityStart")));
  EXPECT_THAT([&] { model.GetFrameIndex("nope"); },
              ThrowsMessage<InvalidArgument>(HasSubstr("frame")));
  EXPECT_THAT([&] { model.GetJointIndex("nope"); },
              ThrowsMessage<InvalidArgument>(HasSubstr("joint")));
}

}  // namespace
}  // namespace idto
