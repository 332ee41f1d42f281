// ContactOptions filters and overrides that would have no effect are errors of ContactEngine
// (the API path; the YAML loader makes the same checks with the key and line of the entry).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "idto/idto.hpp"
#include "support/test_models.hpp"

namespace idto {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// The ground and a post on the world; a free ball; an arm hinged to the world ('upper', with a
// sphere) and a 'hand' welded to it without geometry of its own.
Model Scene() {
  ModelBuilder builder("scene");
  builder.AddGeometry("ground", kWorldBody, Eigen::Isometry3d::Identity(), HalfSpace{});
  Eigen::Isometry3d X_post = Eigen::Isometry3d::Identity();
  X_post.translation() << 1.0, 0.0, 0.5;
  builder.AddGeometry("post", kWorldBody, X_post, Cylinder{0.05, 1.0});
  JointSpec free;
  free.name = "ball_free";
  free.type = JointType::kFloating;
  const BodyIndex ball = builder.AddBody("ball", test::SolidBall(0.5, 0.1), kWorldBody, free);
  builder.AddGeometry("ball_sphere", ball, Eigen::Isometry3d::Identity(), Sphere{0.1});
  JointSpec shoulder;
  shoulder.name = "shoulder";
  shoulder.type = JointType::kRevolute;
  shoulder.axis = Eigen::Vector3d::UnitY();
  shoulder.X_PJ.translation() << 0.0, 0.0, 1.0;
  const BodyIndex upper = builder.AddBody("upper", test::SolidBall(1.0, 0.1), kWorldBody, shoulder);
  builder.AddGeometry("upper_sphere", upper, Eigen::Isometry3d::Identity(), Sphere{0.05});
  JointSpec weld;
  weld.name = "wrist";
  weld.type = JointType::kFixed;
  builder.AddBody("hand", test::SolidBall(0.1, 0.05), upper, weld);
  return builder.Build();
}

ContactParameterOverride Override(const std::string& a, const std::string& b) {
  ContactParameterOverride o;
  o.a = a;
  o.b = b;
  o.stiffness = 10.0;
  return o;
}

auto Refused(const ContactOptions& options) {
  return [options] { ContactEngine(Scene(), options); };
}

TEST(ContactOptions, NamesMustMatchGeometry) {
  ContactOptions o;
  o.excluded_pairs = {{"ball", "ground"}, {"ball", "hand"}};
  EXPECT_THAT(Refused(o), ThrowsMessage<InvalidArgument>(AllOf(
                              HasSubstr("ContactEngine: options.excluded_pairs[1][1] is \"hand\""),
                              HasSubstr("body 'hand' has no collision geometry"))));
  o = ContactOptions{};
  o.collision_groups = {{"ball", "hand"}};
  EXPECT_THAT(Refused(o), ThrowsMessage<InvalidArgument>(
                              HasSubstr("options.collision_groups[0][1] is \"hand\"")));
  o = ContactOptions{};
  o.overrides = {Override("hand", "*")};
  EXPECT_THAT(Refused(o),
              ThrowsMessage<InvalidArgument>(HasSubstr("options.overrides[0].a is \"hand\"")));
  o = ContactOptions{};
  o.included_pairs = {{"nope", "*"}};
  EXPECT_THAT(Refused(o), ThrowsMessage<InvalidArgument>(
                              AllOf(HasSubstr("options.included_pairs[0][0] is \"nope\""),
                                    HasSubstr("a geometry name (ground, post, ball_sphere, "
                                              "upper_sphere), a body name, or '*'"))));
  // Bodies with geometry, geometries and '*' are fine.
  o = ContactOptions{};
  o.excluded_pairs = {{"ball", "ground"}, {"*", "upper_sphere"}};
  EXPECT_NO_THROW(ContactEngine(Scene(), o));
}

TEST(ContactOptions, CollisionGroupsNeedTwoNames) {
  ContactOptions o;
  o.collision_groups = {{"ball", "ground"}, {"ball"}};
  EXPECT_THAT(Refused(o), ThrowsMessage<InvalidArgument>(
                              AllOf(HasSubstr("options.collision_groups[1] is a list of one name "
                                              "\"ball\""),
                                    HasSubstr("expected a list of at least two names"))));
  o.collision_groups = {{}};
  EXPECT_THAT(Refused(o), ThrowsMessage<InvalidArgument>(
                              HasSubstr("options.collision_groups[0] is an empty list")));
}

TEST(ContactOptions, IncludedPairsMustMatchAPairThatCanTouch) {
  ContactOptions o;
  o.included_pairs = {{"ball", "*"}, {"ground", "post"}};
  EXPECT_THAT(Refused(o), ThrowsMessage<InvalidArgument>(
                              AllOf(HasSubstr("options.included_pairs[1] is [ground, post]"),
                                    HasSubstr("[ground, post] matches no two geometries on "
                                              "different bodies"))));
  // A pair hinged together is not evaluated by default, but can be included explicitly.
  o.included_pairs = {{"upper_sphere", "ground"}};
  EXPECT_EQ(ContactEngine(Scene(), o).num_pairs(), 1);
}

TEST(ContactOptions, OverridesMustChangeAnEvaluatedPair) {
  ContactOptions o;
  o.overrides = {Override("ball", "*"), Override("ground", "post")};
  EXPECT_THAT(Refused(o), ThrowsMessage<InvalidArgument>(AllOf(
                              HasSubstr("options.overrides[1] is [ground, post]"),
                              HasSubstr("[ground, post] matches no contact pair that is evaluated"),
                              HasSubstr("it matches no two geometries on different bodies"))));
  // Left out by a filter, or by the hinge between the upper arm and the world.
  ContactOptions excluded;
  excluded.excluded_pairs = {{"ball", "ground"}};
  ContactOptions included;
  included.included_pairs = {{"ball", "post"}};
  ContactOptions grouped;
  grouped.collision_groups = {{"ball", "ground"}};
  for (ContactOptions filtered : {excluded, included, grouped}) {
    filtered.overrides = {Override("ground", "ball_sphere")};
    EXPECT_THAT(Refused(filtered),
                ThrowsMessage<InvalidArgument>(AllOf(
                    HasSubstr("options.overrides[0] is [ground, ball_sphere]"),
                    HasSubstr("every pair it matches is left out by the options' excluded_pairs, "
                              "included_pairs or collision_groups"))));
  }
  o.overrides = {Override("upper_sphere", "ground")};
  EXPECT_THAT(Refused(o), ThrowsMessage<InvalidArgument>(HasSubstr("hinged to each other")));
  // Accepted: overrides of evaluated pairs, including a hinged pair included again.
  o.overrides = {Override("ball", "*"), Override("upper", "ball_sphere")};
  EXPECT_NO_THROW(ContactEngine(Scene(), o));
  o.included_pairs = {{"upper_sphere", "ground"}};
  o.overrides = {Override("upper_sphere", "ground")};
  EXPECT_NO_THROW(ContactEngine(Scene(), o));
}

TEST(ContactOptions, ExclusionsOfPairsThatNeverTouchAreAccepted) {
  // Excluding pairs that are never evaluated anyway (both on the world, hinged neighbours)
  // loses nothing: what the options ask for holds.
  ContactOptions o;
  o.excluded_pairs = {{"ground", "post"}, {"upper_sphere", "ground"}};
  o.collision_groups = {{"upper", "ground", "post"}};
  const ContactEngine engine(Scene(), o);
  EXPECT_EQ(engine.num_pairs(), ContactEngine(Scene(), ContactOptions{}).num_pairs());
}

TEST(ContactOptions, TheChecksOneEntryAtATime) {
  const Model model = Scene();
  EXPECT_EQ(ContactNameProblem(model, "*"), "");
  EXPECT_EQ(ContactNameProblem(model, "upper"), "");
  EXPECT_THAT(ContactNameProblem(model, "hand"), HasSubstr("has no collision geometry"));
  EXPECT_EQ(CollisionGroupProblem(2), "");
  EXPECT_THAT(CollisionGroupProblem(1), HasSubstr("at least two names"));
  EXPECT_EQ(IncludedPairProblem(model, "ball", "post"), "");
  EXPECT_THAT(IncludedPairProblem(model, "upper_sphere", "upper"),
              HasSubstr("matches no two geometries"));
  const ContactEngine engine(model, ContactOptions{});
  EXPECT_EQ(ContactOverrideProblem(model, engine.pairs(), "ball", "*", "x's"), "");
  EXPECT_THAT(ContactOverrideProblem(model, engine.pairs(), "upper", "post", "x's"),
              HasSubstr("left out by x's excluded_pairs"));
}

}  // namespace
}  // namespace idto
