// Scene inputs that used to be lost without a word: the URDF files' warnings, contact filters
// naming a body without geometry, collision groups of one name, included pairs and overrides
// that match nothing. Each is now kept (warnings) or an error naming the key.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "config_test_helpers.hpp"
#include "idto/config/config.hpp"
#include "idto/core/errors.hpp"

namespace idto {
namespace {

using test::Loading;
using test::LoadText;
using test::With;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// The acrobot (no collision geometry of its own) with a ball on each link, the ground and a post.
// The upper link is hinged to the world and to the lower link: its ball meets neither the
// ground nor the other ball; the lower link's ball meets the ground and the post.
const std::string kModels = "    - urdf: acrobot.urdf\n";
const std::string kGeometry =
    "    - urdf: acrobot.urdf\n"
    "  geometry:\n"
    "    - {name: ground, shape: half_space, position: [0, 0, -3]}\n"
    "    - {name: post, shape: cylinder, radius: 0.05, length: 1, position: [1, 0, -2.5]}\n"
    "    - {name: elbow_ball, shape: sphere, radius: 0.1, body: upper_link, "
    "position: [0, 0, -1]}\n"
    "    - {name: tip_ball, shape: sphere, radius: 0.1, body: lower_link, position: [0, 0, -1]}\n";

std::string WithContact(const std::string& contact, const std::string& extra = "") {
  return With(kModels, kGeometry + extra + "  contact: " + contact + "\n");
}

TEST(SceneInputs, UrdfWarningsAreKept) {
  const ExampleConfig plain = LoadText(test::kBase);
  EXPECT_TRUE(plain.urdf_warnings.empty());
  // box.urdf on a fixed base: its mass does not move.
  const ExampleConfig config =
      LoadText(With(kModels, kModels + "    - {urdf: box.urdf, prefix: b_}\n"));
  ASSERT_EQ(config.urdf_warnings.size(), 1u);
  EXPECT_THAT(config.urdf_warnings[0].file, HasSubstr("box.urdf"));
  // The element names the link as in the file and, under the model's prefix, as in the scene.
  EXPECT_EQ(config.urdf_warnings[0].element, "link 'box' (the model's link 'b_box')");
  EXPECT_THAT(config.urdf_warnings[0].message,
              HasSubstr("mass 0.55 ignored: the link is welded to the world"));
}

TEST(SceneInputs, WorldRootedUrdfRefusesAMovingBase) {
  EXPECT_THAT(Loading(With(kModels, kModels + "    - {urdf: spinner.urdf, base: floating}\n")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("test.yaml: scene.models[1].urdf"),
                                             HasSubstr("the root link is 'world'"),
                                             HasSubstr("expected fixed"))));
}

TEST(SceneInputs, ContactNamesMustMatchGeometry) {
  // 'base' is a body of the acrobot without collision geometry: a filter naming it is a no-op.
  EXPECT_THAT(Loading(WithContact("{excluded_pairs: [[base, \"*\"]]}")),
              ThrowsMessage<FileError>(AllOf(
                  HasSubstr("test.yaml: scene.contact.excluded_pairs[0][0]"),
                  HasSubstr("body 'base' has no collision geometry"), HasSubstr("(line 10)"))));
  EXPECT_THAT(Loading(WithContact("{collision_groups: [[tip_ball, base]]}")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.contact.collision_groups[0][1]"),
                                             HasSubstr("body 'base' has no collision geometry"))));
  EXPECT_THAT(Loading(WithContact("{overrides: [{a: base, b: ground, stiffness: 10}]}")),
              ThrowsMessage<FileError>(HasSubstr("scene.contact.overrides[0].a")));
  // The bodies with geometry, the geometries and '*' are fine.
  EXPECT_NO_THROW(LoadText(WithContact("{excluded_pairs: [[lower_link, post], [\"*\", ground]]}")));
}

TEST(SceneInputs, CollisionGroupsNeedTwoNames) {
  EXPECT_THAT(Loading(WithContact("{collision_groups: [[tip_ball, post], [tip_ball]]}")),
              ThrowsMessage<FileError>(AllOf(HasSubstr("scene.contact.collision_groups[1]"),
                                             HasSubstr("is a list of 1 entry [tip_ball]"),
                                             HasSubstr("expected a list of at least two names"))));
}

TEST(SceneInputs, IncludedPairsMustMatchAPairThatCanTouch) {
  EXPECT_THAT(Loading(WithContact("{included_pairs: [[tip_ball, \"*\"], [ground, post]]}")),
              ThrowsMessage<FileError>(AllOf(
                  HasSubstr("scene.contact.included_pairs[1]"),
                  HasSubstr("[ground, post] matches no two geometries on different bodies"))));
  // Hinged neighbours can be included again explicitly.
  const ExampleConfig config = LoadText(WithContact("{included_pairs: [[tip_ball, elbow_ball]]}"));
  ASSERT_EQ(config.problem.contact.included_pairs.size(), 1u);
}

TEST(SceneInputs, OverridesMustChangeAnEvaluatedPair) {
  // Both on the world: never a pair.
  EXPECT_THAT(Loading(WithContact("{overrides: [{a: ground, b: post, stiffness: 10}]}")),
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("scene.contact.overrides[0]"),
                        HasSubstr("[ground, post] matches no contact pair that is evaluated"),
                        HasSubstr("it matches no two geometries on different bodies"))));
  // Left out by a filter, or by the hinge between the upper link and the world.
  for (const std::string& contact :
       {std::string("{excluded_pairs: [[tip_ball, ground]], "
                    "overrides: [{a: tip_ball, b: ground, stiffness: 10}]}"),
        std::string("{included_pairs: [[tip_ball, post]], "
                    "overrides: [{a: tip_ball, b: ground, stiffness: 10}]}"),
        std::string("{collision_groups: [[lower_link, ground]], "
                    "overrides: [{a: tip_ball, b: ground, stiffness: 10}]}"),
        std::string("{overrides: [{a: elbow_ball, b: \"*\", stiffness: 10}]}")}) {
    EXPECT_THAT(Loading(WithContact(contact)),
                ThrowsMessage<FileError>(
                    AllOf(HasSubstr("scene.contact.overrides[0]"),
                          HasSubstr("matches no contact pair that is evaluated"),
                          HasSubstr("every pair it matches is left out by scene.contact's "
                                    "excluded_pairs, included_pairs or collision_groups"))))
        << contact;
  }
  // Accepted: an override of evaluated pairs; and with contact off, nothing is evaluated at all.
  const ExampleConfig config =
      LoadText(WithContact("{overrides: [{a: tip_ball, b: \"*\", stiffness: 10}]}"));
  ASSERT_EQ(config.problem.contact.overrides.size(), 1u);
  EXPECT_NO_THROW(
      LoadText(WithContact("{excluded_pairs: [[tip_ball, ground]], overrides: "
                           "[{a: tip_ball, b: ground, stiffness: 10}]}",
                           "  enable_contact: false\n")));
}

TEST(SceneInputs, ExclusionsOfPairsThatNeverTouchAreAccepted) {
  // Excluding a pair that is never evaluated anyway (both on the world, or hinged neighbours)
  // loses nothing: what the file asks for holds.
  const ExampleConfig config = LoadText(WithContact(
      "{excluded_pairs: [[ground, post]], collision_groups: [[upper_link, lower_link]]}"));
  EXPECT_EQ(config.problem.contact.excluded_pairs.size(), 1u);
  EXPECT_EQ(config.problem.contact.collision_groups.size(), 1u);
}

}  // namespace
}  // namespace idto
