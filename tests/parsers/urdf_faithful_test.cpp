// URDF without silent loss: files in the style of the reference implementation load with every
// collision shape, what idto cannot represent fails loudly (or warns, for visuals, when asked),
// numbers are read strictly, joint limits reach the Model, and nesting depth is bounded.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/data.hpp"
#include "idto/parsers/urdf.hpp"
#include "support/eigen_matchers.hpp"

namespace idto {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string DataPath(const std::string& name) {
  return std::string(IDTO_TEST_DATA_DIR) + "/urdf/" + name;
}

int CountShapes(const Model& model, BodyIndex body) {
  int n = 0;
  for (const GeometryInstance& g : model.geometries()) n += g.body == body ? 1 : 0;
  return n;
}

template <typename T>
const T& ShapeOf(const Model& model, const std::string& name) {
  const Shape& shape = model.geometries()[model.GetGeometryIndex(name)].shape;
  EXPECT_TRUE(std::holds_alternative<T>(shape)) << name;
  return std::get<T>(shape);
}

double MassMatrixAtZero(const Model& model) {
  Data data(model);
  return MassMatrix(model, Eigen::VectorXd::Zero(model.nq()), &data)(0, 0);
}

bool Mentions(const std::vector<UrdfWarning>& warnings, const std::string& text) {
  for (const UrdfWarning& w : warnings) {
    if (w.ToString().find(text) != std::string::npos) return true;
  }
  return false;
}

// ------------------------------------------------------------------------------------------------
// Files in the style of the reference implementation.

TEST(UrdfReference, PendulumImplicitWorldNoLimitPointMass) {
  std::vector<UrdfWarning> warnings;
  const Model model = ParseUrdfFile(DataPath("reference/pendulum.urdf"), {}, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front().ToString();
  ASSERT_EQ(model.nq(), 1);
  EXPECT_EQ(model.joint_type(model.GetJointIndex("theta")), JointType::kRevolute);
  // No <limit>: unbounded, no velocity or effort limit.
  EXPECT_EQ(model.position_lower_limits()(0), -kInf);
  EXPECT_EQ(model.position_upper_limits()(0), kInf);
  EXPECT_EQ(model.velocity_limits()(0), kInf);
  EXPECT_EQ(model.effort_limits()(0), kInf);
  // The bob: a 1 kg point mass 1 m from the axis.
  EXPECT_NEAR(MassMatrixAtZero(model), 1.0, 1e-12);
  ASSERT_EQ(model.geometries().size(), 1u);
  EXPECT_EQ(model.geometries()[0].name, "bob");
  EXPECT_EQ(model.geometries()[0].body, model.GetBodyIndex("rod"));
  // The implicit world: "base" is welded to the world body at z = 2.
  EXPECT_EQ(model.mobilized_body(model.GetBodyIndex("base")), kWorldBody);
  EXPECT_DOUBLE_EQ(model.joint_frame_in_parent(model.GetJointIndex("weld")).translation().z(), 2.0);
}

TEST(UrdfReference, HopperKeepsEveryCollisionShape) {
  std::vector<UrdfWarning> warnings;
  const Model model = ParseUrdfFile(DataPath("reference/hopper.urdf"), {}, &warnings);
  EXPECT_EQ(model.nq(), 4);
  // Five shapes, each where the file puts it (urdfdom would lose the capsules and every shape
  // after them in the same link, among them both foot spheres).
  ASSERT_EQ(model.geometries().size(), 5u);
  EXPECT_EQ(CountShapes(model, model.GetBodyIndex("body")), 1);
  EXPECT_EQ(CountShapes(model, model.GetBodyIndex("thigh")), 1);
  EXPECT_EQ(CountShapes(model, model.GetBodyIndex("shin")), 3);
  EXPECT_DOUBLE_EQ(ShapeOf<Capsule>(model, "body_capsule").radius, 0.1);
  EXPECT_DOUBLE_EQ(ShapeOf<Capsule>(model, "body_capsule").length, 0.2);
  EXPECT_DOUBLE_EQ(ShapeOf<Capsule>(model, "thigh_capsule").length, 0.4);  // <drake:capsule>
  EXPECT_DOUBLE_EQ(ShapeOf<Capsule>(model, "shin_capsule").radius, 0.03);
  EXPECT_DOUBLE_EQ(ShapeOf<Sphere>(model, "foot_front").radius, 0.04);
  EXPECT_DOUBLE_EQ(ShapeOf<Sphere>(model, "foot_back").radius, 0.04);
  // Ignored by design, with a warning naming the file and the element.
  EXPECT_TRUE(Mentions(warnings, "hopper.urdf: link 'body': collision 'body_capsule'"));
  EXPECT_TRUE(Mentions(warnings, "<drake:proximity_properties>"));
  EXPECT_TRUE(Mentions(warnings, "<transmission> 'knee_transmission'"));
  // Limits.
  const int x = model.GetPositionStart("base_x");
  const int knee = model.GetPositionStart("knee");
  const int hip = model.GetPositionStart("hip");
  EXPECT_EQ(model.position_lower_limits()(x), -10.0);
  EXPECT_EQ(model.velocity_limits()(model.GetVelocityStart("base_x")), 5.0);
  EXPECT_EQ(model.effort_limits()(model.GetVelocityStart("base_x")), kInf);  // effort="0"
  EXPECT_EQ(model.position_lower_limits()(knee), -2.5);
  EXPECT_EQ(model.position_upper_limits()(knee), 0.0);
  EXPECT_EQ(model.velocity_limits()(model.GetVelocityStart("knee")), 10.0);
  EXPECT_EQ(model.effort_limits()(model.GetVelocityStart("knee")), 40.0);
  EXPECT_EQ(model.position_lower_limits()(hip), -kInf);
  EXPECT_EQ(model.effort_limits()(model.GetVelocityStart("hip")), kInf);
  // The massless slider between the two base joints is fine: M is positive definite.
  Data data(model);
  const Eigen::MatrixXd M = MassMatrix(model, model.NeutralConfiguration(), &data);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues()(0), 0.0);
}

TEST(UrdfReference, MassOnTheWorldIsIgnoredWithAWarning) {
  for (const char* file : {"reference/world_mass.urdf", "world_with_mass.urdf"}) {
    SCOPED_TRACE(file);
    std::vector<UrdfWarning> warnings;
    const Model model = ParseUrdfFile(DataPath(file), {}, &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0].file, DataPath(file));
    EXPECT_EQ(warnings[0].element, "link 'world'");
    EXPECT_THAT(warnings[0].message, HasSubstr("mass 1 ignored"));
  }
  const Model model = ParseUrdfFile(DataPath("reference/world_mass.urdf"));
  EXPECT_EQ(model.geometries()[model.GetGeometryIndex("ground")].body, kWorldBody);
  EXPECT_NEAR(MassMatrixAtZero(model), 2.0 * 0.25, 1e-12);  // point mass 0.5 m from the axis
  EXPECT_EQ(model.velocity_limits()(0), 4.0);
  EXPECT_EQ(model.effort_limits()(0), 3.0);
  EXPECT_EQ(model.position_lower_limits()(0), -kInf);  // continuous
}

TEST(UrdfReference, FixedRootMassGivesANote) {
  std::vector<UrdfWarning> warnings;
  ParseUrdfFile(DataPath("pendulum.urdf"), {}, &warnings);
  const Model model = ParseUrdfFile(DataPath("point_mass.urdf"), {}, &warnings);
  EXPECT_TRUE(Mentions(warnings, "link 'base': mass 1 ignored: the link is welded to the world"));
  EXPECT_NEAR(MassMatrixAtZero(model), 0.25, 1e-12);
}

TEST(UrdfReference, RevoluteWithoutLimitIsUnbounded) {
  const Model model = ParseUrdfFile(DataPath("revolute_without_limit.urdf"));
  EXPECT_EQ(model.position_lower_limits()(0), -kInf);
  EXPECT_EQ(model.position_upper_limits()(0), kInf);
  EXPECT_EQ(model.effort_limits()(0), kInf);
  EXPECT_EQ(model.velocity_limits()(0), kInf);
}

// ------------------------------------------------------------------------------------------------
// Unsupported elements.

TEST(UrdfUnsupported, VisualMeshCanBeDowngradedToAWarning) {
  const std::string path = DataPath("errors/visual_mesh.urdf");
  UrdfOptions options;
  options.unsupported_visuals_as_warnings = true;
  std::vector<UrdfWarning> warnings;
  const Model model = ParseUrdfFile(path, options, &warnings);
  EXPECT_EQ(model.geometries().size(), 1u);
  // The mesh, and the note that the fixed root's mass does not move.
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0].file, path);
  EXPECT_EQ(warnings[0].element, "link 'shell'");
  EXPECT_THAT(warnings[0].message, HasSubstr("<mesh filename=\"shell.stl\">"));
  EXPECT_THAT(warnings[1].message, HasSubstr("mass 1 ignored"));
  // Without a place to put the warnings, the option is refused.
  EXPECT_THAT([&] { ParseUrdfFile(path, options); },
              ThrowsMessage<InvalidArgument>(HasSubstr("unsupported_visuals_as_warnings")));
  // Without the option: an error that says how to downgrade it.
  EXPECT_THAT([&] { ParseUrdfFile(path); },
              ThrowsMessage<FileError>(AllOf(HasSubstr(path), HasSubstr("link 'shell'"),
                                             HasSubstr("unsupported_visuals_as_warnings"))));
}

TEST(UrdfUnsupported, CollisionMeshIsNeverDowngraded) {
  UrdfOptions options;
  options.unsupported_visuals_as_warnings = true;
  std::vector<UrdfWarning> warnings;
  EXPECT_THAT([&] { ParseUrdfFile(DataPath("errors/collision_mesh.urdf"), options, &warnings); },
              ThrowsMessage<FileError>(AllOf(HasSubstr("link 'foot'"), HasSubstr("<mesh"))));
}

TEST(UrdfUnsupported, EveryElementIsUsedOrReported) {
  const std::string link = R"(<link name="a"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>)";
  struct Case {
    std::string body;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {link + "<collision><geometry/></collision></link>", "<geometry> is empty"},
      {link + "<collision><geometry><sphere radius='1'/><box size='1 1 1'/></geometry>"
              "</collision></link>",
       "expected exactly one shape"},
      {link + "<collision><geometry><drake:ellipsoid a='1' b='1' c='1'/></geometry></collision>"
              "</link>",
       "<drake:ellipsoid> is not supported"},
      {link + "<collision><geometry><sphere radius='1'/></geometry><surface/></collision></link>",
       "unsupported element <surface>"},
      {link + "<inertial><mass value='1'/><inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' "
              "izz='1'/></inertial></link>",
       "several <inertial>"},
      {link + "</link><drake:collision_filter_group name='g'/>", "collision_filter_group"},
      {link + "</link><frame name='tip'/>", "unsupported element <frame>"},
      {R"(<link name="a"><inertial><mass value="1"/></inertial></link>)", "no <inertia"},
      {R"(<link name="a"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1"
          iyz="0"/></inertial></link>)",
       "<inertia izz> is missing"},
      {link + "<collision><geometry><sphere radius='1'/></geometry></collision>"
              "<collision><geometry><capsule radius='1'/></geometry></collision></link>",
       "<capsule length> is missing"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.body);
    EXPECT_THAT([&] { ParseUrdfString("<robot name='r'>" + c.body + "</robot>", {}, "case.urdf"); },
                ThrowsMessage<FileError>(AllOf(HasSubstr("case.urdf"), HasSubstr(c.expected))));
  }
}

// ------------------------------------------------------------------------------------------------
// Numbers.

TEST(UrdfNumbers, ReadStrictly) {
  auto robot = [](const std::string& mass, const std::string& radius) {
    return "<robot name='r'><link name='a'><inertial><mass value='" + mass +
           "'/><inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/></inertial>"
           "<collision name='c'><geometry><sphere radius='" +
           radius + "'/></geometry></collision></link></robot>";
  };
  EXPECT_NO_THROW(ParseUrdfString(robot("+1.5", " 1e-2 ")));
  const Model model = ParseUrdfString(robot("1.5", "1e-2"));
  EXPECT_DOUBLE_EQ(model.body_mass(1), 1.5);
  EXPECT_DOUBLE_EQ(ShapeOf<Sphere>(model, "c").radius, 0.01);
  EXPECT_THAT([&] { ParseUrdfString(robot("1 2", "1")); },
              ThrowsMessage<FileError>(HasSubstr("<mass value> is \"1 2\"; expected a number")));
  EXPECT_THAT([&] { ParseUrdfString(robot("", "1")); },
              ThrowsMessage<FileError>(HasSubstr("<mass value> is \"\"")));
  EXPECT_THAT([&] { ParseUrdfString(robot("-inf", "1")); },
              ThrowsMessage<FileError>(HasSubstr("mass is -inf")));
  EXPECT_THAT([&] { ParseUrdfString(robot("1", "nan")); },
              ThrowsMessage<FileError>(HasSubstr("<sphere radius> is nan")));
  EXPECT_THAT([&] { ParseUrdfString(robot("1", "1e999")); },
              ThrowsMessage<FileError>(HasSubstr("<sphere radius> is inf")));
}

TEST(UrdfNumbers, NanMassIsReportedAsNan) {
  EXPECT_THAT([] { ParseUrdfFile(DataPath("errors/nan_mass.urdf")); },
              ThrowsMessage<FileError>(AllOf(HasSubstr("link 'arm'"), HasSubstr("mass is nan"),
                                             ::testing::Not(HasSubstr("mass is 0")))));
}

// ------------------------------------------------------------------------------------------------
// Limits.

TEST(UrdfLimits, SizesAndValues) {
  const std::string xml = R"(<robot name="r">
    <link name="a"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
    <link name="b"><inertial><origin xyz="1 0 0"/><mass value="1"/>
      <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
    <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
      <limit lower="-0.5" upper="1.5" velocity="3" effort="7"/></joint></robot>)";
  UrdfOptions options;
  options.base = BaseType::kFloating;
  const Model model = ParseUrdfString(xml, options);
  ASSERT_EQ(model.position_lower_limits().size(), 8);
  ASSERT_EQ(model.position_upper_limits().size(), 8);
  ASSERT_EQ(model.velocity_limits().size(), 7);
  ASSERT_EQ(model.effort_limits().size(), 7);
  EXPECT_TRUE((model.position_lower_limits().head(7).array() == -kInf).all());
  EXPECT_TRUE((model.velocity_limits().head(6).array() == kInf).all());
  EXPECT_EQ(model.position_lower_limits()(7), -0.5);
  EXPECT_EQ(model.position_upper_limits()(7), 1.5);
  EXPECT_EQ(model.velocity_limits()(6), 3.0);
  EXPECT_EQ(model.effort_limits()(6), 7.0);
  EXPECT_EQ(model.lower_position_limits(), model.position_lower_limits());

  const std::string limit = R"(<limit lower="-0.5" upper="1.5" velocity="3" effort="7"/>)";
  for (const char* bad : {R"(<limit velocity="-1"/>)", R"(<limit effort="nan"/>)",
                          R"(<limit lower="2" upper="1"/>)", R"(<limit lower="0,5"/>)"}) {
    std::string text = xml;
    text.replace(text.find(limit), limit.size(), bad);
    EXPECT_THAT([&] { ParseUrdfString(text, {}, "limits.urdf"); },
                ThrowsMessage<FileError>(AllOf(HasSubstr("limits.urdf"), HasSubstr("joint 'j'"))))
        << bad;
  }
}

TEST(UrdfLimits, ModelBuilderSetsThem) {
  ModelBuilder builder;
  JointSpec joint;
  joint.name = "slide";
  joint.type = JointType::kPrismatic;
  joint.lower_limit = -1.0;
  joint.upper_limit = 2.0;
  joint.velocity_limit = 0.5;
  joint.effort_limit = 9.0;
  BodyInertia point;
  point.mass = 1.0;  // a point mass on a prismatic joint: M = 1
  builder.AddBody("cart", point, kWorldBody, joint);
  const Model model = builder.Build();
  EXPECT_EQ(model.position_lower_limits()(0), -1.0);
  EXPECT_EQ(model.position_upper_limits()(0), 2.0);
  EXPECT_EQ(model.velocity_limits()(0), 0.5);
  EXPECT_EQ(model.effort_limits()(0), 9.0);
  joint.name = "bad";
  joint.velocity_limit = 0.0;
  EXPECT_THAT([&] { builder.AddBody("bad", point, kWorldBody, joint); },
              ThrowsMessage<InvalidArgument>(HasSubstr("velocity limit of joint \"bad\" is 0")));
}

// ------------------------------------------------------------------------------------------------
// Nesting depth.

TEST(UrdfDepth, DeepNestingIsAFileErrorNotACrash) {
  const int depth = 200000;
  std::string xml = "<robot name='r'><link name='a'>";
  xml.reserve(static_cast<size_t>(depth) * 8 + 64);
  for (int i = 0; i < depth; ++i) xml += "<a>";
  for (int i = 0; i < depth; ++i) xml += "</a>";
  xml += "</link></robot>";
  EXPECT_THAT([&] { ParseUrdfString(xml, {}, "bomb.urdf"); },
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("bomb.urdf"), HasSubstr("nested more than 256 deep"))));
  // Comments, CDATA, declarations, self-closing tags and quoted '>' do not count: the depth is
  // fine, and the parse goes on to the next problem (the CDATA is text in <robot>).
  std::string fine = "<?xml version='1.0'?><!DOCTYPE robot><robot name='r'><!-- <a><a> -->";
  for (int i = 0; i < 300; ++i) fine += "<link name='l" + std::to_string(i) + "' x='>'/>";
  fine += "<![CDATA[<a><a><a>]]></robot>";
  EXPECT_THAT(
      [&] { ParseUrdfString(fine); },
      ThrowsMessage<FileError>(AllOf(HasSubstr("<robot> (line 1) holds the text"),
                                     HasSubstr("<a><a><a>"), ::testing::Not(HasSubstr("nested")))));
  fine.replace(fine.find("<![CDATA["), std::string("<![CDATA[<a><a><a>]]>").size(), "");
  EXPECT_THAT([&] { ParseUrdfString(fine); },
              ThrowsMessage<FileError>(HasSubstr("several root links")));
}

}  // namespace
}  // namespace idto
