// URDF input that used to be silently ignored or misread: misspelt attributes, text where URDF
// has attributes, repeated <mass>/<inertia>, a second top-level element, unchecked numbers on
// fixed joints, renamed duplicate collision names. Each is now an error naming the file, the
// element and what was found, or a warning when nothing the model uses is lost.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "idto/core/errors.hpp"
#include "idto/parsers/urdf.hpp"

namespace idto {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr const char* kInertial =
    "<inertial><mass value='1'/>"
    "<inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/></inertial>";

/// Two links 'a' and 'b' joined by joint 'j' of `type`, with `joint` inside the <joint> and
/// `link_b` inside link 'b' (after its <inertial>).
std::string TwoLinks(const std::string& type, const std::string& joint,
                     const std::string& link_b = "") {
  return std::string("<robot name='r'><link name='a'>") + kInertial + "</link><link name='b'>" +
         kInertial + link_b + "</link><joint name='j' type='" + type +
         "'><parent link='a'/><child link='b'/>" + joint + "</joint></robot>";
}

std::vector<UrdfWarning> WarningsOf(const std::string& xml) {
  std::vector<UrdfWarning> warnings;
  ParseUrdfString(xml, {}, "case.urdf", &warnings);
  return warnings;
}

bool Mentions(const std::vector<UrdfWarning>& warnings, const std::string& text) {
  for (const UrdfWarning& w : warnings) {
    if (w.ToString().find(text) != std::string::npos) return true;
  }
  return false;
}

struct Case {
  std::string xml;
  std::string element;   // "joint 'j'" or "link 'b'"
  std::string expected;  // in the message
};

void ExpectErrors(const std::vector<Case>& cases) {
  for (const Case& c : cases) {
    SCOPED_TRACE(c.xml);
    EXPECT_THAT([&] { ParseUrdfString(c.xml, {}, "case.urdf"); },
                ThrowsMessage<FileError>(
                    AllOf(HasSubstr("case.urdf: " + c.element), HasSubstr(c.expected))));
  }
}

// ------------------------------------------------------------------------------------------------
// Value elements: an unknown attribute was a misspelt optional one, silently at its default.

TEST(UrdfStrict, MisspeltAttributesAreErrors) {
  const std::string sphere = "<collision name='c'><geometry><sphere radius='0.1'/></geometry>";
  ExpectErrors({
      {TwoLinks("revolute", "<origin xyz='0 0 1' ryp='0 0 1.57'/>"), "joint 'j'",
       "<origin> (line 1) has an unknown attribute ryp=\"0 0 1.57\"; expected xyz, rpy"},
      {TwoLinks("revolute", "<axis xzy='0 1 0'/>"), "joint 'j'",
       "<axis> (line 1) has an unknown attribute xzy=\"0 1 0\"; expected xyz"},
      {TwoLinks("revolute", "<limit lowr='-1' upper='1'/>"), "joint 'j'",
       "unknown attribute lowr=\"-1\"; expected lower, upper, effort, velocity"},
      {TwoLinks("revolute", "<dynamics dampng='0.5'/>"), "joint 'j'",
       "unknown attribute dampng=\"0.5\"; expected damping, friction"},
      {std::string("<robot name='r'><link name='a'/><link name='b'>") + kInertial +
           "</link><joint name='j' type='fixed'><parent link='a'/><child link='b' name='x'/>"
           "</joint></robot>",
       "joint 'j'", "<child> (line 1) has an unknown attribute name=\"x\"; expected link"},
      {TwoLinks("revolute", "",
                sphere + "<origin xyz='0 0 1' rpy='0 0 0' xzy='1 0 0'/>" + "</collision>"),
       "link 'b'", "unknown attribute xzy=\"1 0 0\"; expected xyz, rpy"},
      {TwoLinks("revolute", "",
                "<collision><geometry><sphere radius='0.1' length='2'/></geometry></collision>"),
       "link 'b'", "<sphere> (line 1) has an unknown attribute length=\"2\"; expected radius"},
      {TwoLinks("revolute", "",
                "<collision><geometry><box size='1 1 1' sizes='2 2 2'/></geometry></collision>"),
       "link 'b'", "unknown attribute sizes"},
      {"<robot name='r'><link name='a'><inertial><origin xyz='0 0 1' ryp='1 0 0'/>"
       "<mass value='1'/><inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/></inertial>"
       "</link></robot>",
       "link 'a'", "unknown attribute ryp"},
      {"<robot name='r'><link name='a'><inertial><mass value='1' units='g'/>"
       "<inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/></inertial></link></robot>",
       "link 'a'", "<mass> (line 1) has an unknown attribute units=\"g\"; expected value"},
      {"<robot name='r'><link name='a'><inertial><mass value='1'/>"
       "<inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1' izy='0'/></inertial></link>"
       "</robot>",
       "link 'a'", "unknown attribute izy=\"0\"; expected ixx, ixy, ixz, iyy, iyz, izz"},
      // Visual geometry is not kept, but it is checked like the rest.
      {TwoLinks("revolute", "",
                "<visual><origin xyz='0 0 1' ryp='0 0 1'/><geometry><sphere radius='1'/>"
                "</geometry></visual>"),
       "link 'b'", "unknown attribute ryp"},
  });
}

TEST(UrdfStrict, TextAndElementsInValueElementsAreErrors) {
  ExpectErrors({
      {TwoLinks("revolute", "<origin>0 0 1</origin>"), "joint 'j'",
       "<origin> (line 1) holds the text \"0 0 1\"; expected none (URDF values are attributes)"},
      {TwoLinks("revolute", "<axis xyz='1 0 0'>0 0 1</axis>"), "joint 'j'",
       "holds the text \"0 0 1\""},
      {"<robot name='r'><link name='a'><inertial><mass value='1'>5</mass>"
       "<inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/></inertial></link></robot>",
       "link 'a'", "<mass> (line 1) holds the text \"5\""},
      {TwoLinks("revolute", "",
                "<collision><origin xyz='0 0 1'><origin xyz='1 1 1'/></origin>"
                "<geometry><sphere radius='1'/></geometry></collision>"),
       "link 'b'", "<origin> (line 1) holds an element <origin> (line 1); expected none"},
      {TwoLinks("revolute", "",
                "<collision><geometry><sphere radius='1'><x/></sphere></geometry>"
                "</collision>"),
       "link 'b'", "<sphere> (line 1) holds an element <x>"},
      // Text in a structural element is no URDF either.
      {TwoLinks("revolute", "", "oops"), "link 'b'", "<link> (line 1) holds the text \"oops\""},
      {TwoLinks("revolute", "<![CDATA[<axis xyz='0 0 1'/>]]>"), "joint 'j'",
       "<joint> (line 1) holds the text \"<axis xyz='0 0 1'/>\""},
  });
}

TEST(UrdfStrict, SeveralMassOrInertiaElementsAreErrors) {
  ExpectErrors({
      {"<robot name='r'><link name='a'><inertial><mass value='1'/><mass value='2'/>"
       "<inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/></inertial></link></robot>",
       "link 'a'", "several <mass> elements (lines 1 and 1); expected one"},
      {"<robot name='r'>\n<link name='a'><inertial><mass value='1'/>\n"
       "<inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/>\n"
       "<inertia ixx='2' ixy='0' ixz='0' iyy='2' iyz='0' izz='2'/></inertial></link></robot>",
       "link 'a'", "several <inertia> elements (lines 3 and 4)"},
  });
}

TEST(UrdfStrict, OneRobotAndNothingElseAtTheTopLevel) {
  const std::string robot =
      std::string("<robot name='r'><link name='a'>") + kInertial + "</link></robot>";
  EXPECT_NO_THROW(ParseUrdfString("<?xml version='1.0'?>\n<!-- a comment -->\n" + robot +
                                  "\n<!-- another -->\n"));
  ExpectErrors({
      {robot + "\n<robot name='s'><link name='b'/></robot>", "XML",
       "<robot> at the top level (line 2), besides the <robot> of line 1; expected one <robot> "
       "element and nothing else"},
      {robot + "<link name='b'/>", "XML", "<link> at the top level"},
      {"<link name='b'/>" + robot, "XML", "<link> at the top level (line 1)"},
  });
}

// ------------------------------------------------------------------------------------------------
// Structural elements: an unknown attribute loses nothing the model uses: a warning.

TEST(UrdfStrict, UnknownAttributesOfStructuralElementsWarn) {
  const std::string xml =
      "<robot name='r' version='1.0' xmlns:xacro='http://www.ros.org/wiki/xacro' colour='red'>"
      "<link name='a' type='rigid'>" +
      std::string(kInertial) +
      "<collision name='c' group='feet'><geometry shape='round'><sphere radius='0.1'/></geometry>"
      "</collision><visual name='v' alpha='1'><geometry><sphere radius='0.1'/></geometry>"
      "</visual></link></robot>";
  const std::vector<UrdfWarning> warnings = WarningsOf(xml);
  EXPECT_TRUE(Mentions(warnings,
                       "case.urdf: robot 'r': attribute colour=\"red\" of <robot> "
                       "(line 1) ignored (not a URDF attribute of <robot>; expected "
                       "name, version)"));
  EXPECT_TRUE(Mentions(warnings, "link 'a': attribute type=\"rigid\" of <link>"));
  EXPECT_TRUE(Mentions(warnings, "attribute group=\"feet\" of <collision>"));
  EXPECT_TRUE(Mentions(warnings, "attribute shape=\"round\" of <geometry>"));
  EXPECT_TRUE(Mentions(warnings, "attribute alpha=\"1\" of <visual>"));
  EXPECT_FALSE(Mentions(warnings, "attribute version"));
  EXPECT_FALSE(Mentions(warnings, "attribute xmlns"));
  const std::string joint =
      std::string("<robot name='r'><link name='a'/><link name='b'>") + kInertial +
      "</link><joint name='j' type='fixed' limit='1'><parent link='a'/><child link='b'/>"
      "</joint></robot>";
  EXPECT_TRUE(Mentions(WarningsOf(joint),
                       "joint 'j': attribute limit=\"1\" of <joint> (line 1) "
                       "ignored (not a URDF attribute of <joint>; expected "
                       "name, type)"));
}

// ------------------------------------------------------------------------------------------------
// Fixed joints: their <axis> and <limit> were not read at all; now checked, still no effect.

TEST(UrdfStrict, FixedJointNumbersAreChecked) {
  ExpectErrors({
      {TwoLinks("fixed", "<limit effort='1O'/>"), "joint 'j'",
       "<limit effort> is \"1O\"; expected a number"},
      {TwoLinks("fixed", "<axis xyz='x'/>"), "joint 'j'", "<axis xyz> is \"x\"; expected 3"},
      {TwoLinks("fixed", "<limit lower='1' upper='-1'/>"), "joint 'j'",
       "lower = 1 and upper = -1; expected lower <= upper"},
      {TwoLinks("fixed", "<limit velocity='-2'/>"), "joint 'j'", "<limit velocity> is -2"},
      {TwoLinks("floating", "<axis xyz='0 0 1' typo='1'/>"), "joint 'j'", "unknown attribute typo"},
  });
  // Well-formed, they have no effect and need no warning (a fixed joint does not move).
  std::vector<UrdfWarning> warnings;
  const Model model = ParseUrdfString(
      TwoLinks("fixed",
               "<axis xyz='0 0 1'/><limit lower='-1' upper='1' effort='5' velocity='2'/>"
               "<dynamics damping='0.1'/>"),
      {}, "case.urdf", &warnings);
  EXPECT_EQ(model.nv(), 0);
  for (const UrdfWarning& w : warnings) EXPECT_THAT(w.message, HasSubstr("mass")) << w.ToString();
}

// ------------------------------------------------------------------------------------------------
// Names.

TEST(UrdfStrict, RenamedDuplicateCollisionNamesWarn) {
  const std::string xml =
      TwoLinks("revolute", "<axis xyz='0 0 1'/>",
               "<collision name='c'><geometry><sphere radius='0.1'/></geometry></collision>"
               "<collision name='c'><geometry><sphere radius='0.2'/></geometry></collision>");
  std::vector<UrdfWarning> warnings;
  UrdfOptions options;
  options.prefix = "p_";
  const Model model = ParseUrdfString(xml, options, "case.urdf", &warnings);
  ASSERT_EQ(model.geometries().size(), 2u);
  EXPECT_EQ(model.geometries()[0].name, "p_c");
  EXPECT_EQ(model.geometries()[1].name, "p_c_1");
  EXPECT_TRUE(Mentions(warnings,
                       "case.urdf: link 'b' (the model's link 'p_b'): collision name 'p_c' is "
                       "already used in this model; this one is named 'p_c_1'"));
}

TEST(UrdfStrict, PrefixedWarningsNameTheModelsLinkOrJoint) {
  // One file, loaded without a prefix and under two: the warnings about its link, its joint and
  // its <robot> tell which copy of the model they are about; without a prefix they are as in
  // the file.
  const std::string xml = "<robot name='r' colour='red'>" +
                          TwoLinks("revolute", "<axis xyz='0 0 1'/><dynamics friction='0.1'/>")
                              .substr(std::string("<robot name='r'>").size());
  auto elements = [&](const std::string& prefix) {
    std::vector<UrdfWarning> warnings;
    UrdfOptions options;
    options.prefix = prefix;
    ParseUrdfString(xml, options, "case.urdf", &warnings);
    std::vector<std::string> out;
    for (const UrdfWarning& w : warnings) out.push_back(w.element);
    return out;
  };
  EXPECT_THAT(elements(""), ::testing::UnorderedElementsAre("robot 'r'", "link 'a'", "joint 'j'"));
  EXPECT_THAT(elements("left_"),
              ::testing::UnorderedElementsAre("robot 'r' (loaded with prefix 'left_')",
                                              "link 'a' (the model's link 'left_a')",
                                              "joint 'j' (the model's joint 'left_j')"));
}

// ------------------------------------------------------------------------------------------------
// The repository's own models still load, with no other warning than mass on a welded root.

TEST(UrdfStrict, RepositoryModelsLoadWithoutNewWarnings) {
  int files = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(IDTO_SOURCE_DIR) + "/models")) {
    if (entry.path().extension() != ".urdf") continue;
    SCOPED_TRACE(entry.path().string());
    ++files;
    std::vector<UrdfWarning> warnings;
    EXPECT_NO_THROW(ParseUrdfFile(entry.path().string(), {}, &warnings));
    for (const UrdfWarning& w : warnings) {
      EXPECT_THAT(w.message, HasSubstr("ignored: the link is welded to the world")) << w.ToString();
    }
  }
  EXPECT_GE(files, 10);
}

}  // namespace
}  // namespace idto
