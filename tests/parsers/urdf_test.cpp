// URDF parser: structure, conventions, numbers (through the multibody algorithms) and errors.

#include "idto/parsers/urdf.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "idto/core/errors.hpp"
#include "idto/geometry/signed_distance.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/algorithms/kinematics.hpp"
#include "idto/multibody/data.hpp"
#include "support/eigen_matchers.hpp"

namespace idto {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kTol = 1e-12;
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string DataPath(const std::string& name) {
  return std::string(IDTO_TEST_DATA_DIR) + "/urdf/" + name;
}
std::string ModelPath(const std::string& name) {
  return std::string(IDTO_SOURCE_DIR) + "/models/" + name;
}

/// URDF rotation from roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Matrix3d Rpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Isometry3d Pose(const Eigen::Vector3d& p, const Eigen::Matrix3d& R) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R;
  X.translation() = p;
  return X;
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& c) {
  Eigen::Matrix3d S;
  S << 0, -c.z(), c.y(), c.z(), 0, -c.x(), -c.y(), c.x(), 0;
  return S;
}

// ------------------------------------------------------------------------------------------------
// Structure.

TEST(UrdfStructure, Arm7) {
  const Model model = ParseUrdfFile(ModelPath("arm7.urdf"));
  EXPECT_EQ(model.name(), "arm7");
  EXPECT_EQ(model.nq(), 7);
  EXPECT_EQ(model.nv(), 7);
  // world, base, link1..link7, tool.
  EXPECT_EQ(model.num_bodies(), 10);
  EXPECT_EQ(model.GetBodyIndex("base"), 1);
  EXPECT_EQ(model.GetBodyIndex("link7"), 8);
  EXPECT_EQ(model.GetBodyIndex("tool"), 9);
  EXPECT_EQ(model.joint_type(model.GetBodyIndex("base")), JointType::kFixed);
  EXPECT_EQ(model.joint_name(model.GetBodyIndex("base")), "base_root_joint");
  for (int i = 1; i <= 7; ++i) {
    const std::string joint = "joint" + std::to_string(i);
    EXPECT_EQ(model.GetPositionStart(joint), i - 1) << joint;
    EXPECT_EQ(model.GetVelocityStart(joint), i - 1) << joint;
    EXPECT_EQ(model.joint_type(model.GetJointIndex(joint)), JointType::kRevolute);
  }
  // Joint axes alternate z, y.
  EXPECT_EIGEN_NEAR(model.joint_axis(model.GetJointIndex("joint1")), Eigen::Vector3d::UnitZ(),
                    kTol);
  EXPECT_EIGEN_NEAR(model.joint_axis(model.GetJointIndex("joint2")), Eigen::Vector3d::UnitY(),
                    kTol);
  // The tool is welded to link7 but keeps its body, frame and geometry.
  const BodyIndex tool = model.GetBodyIndex("tool");
  EXPECT_EQ(model.mobilized_body(tool), model.GetBodyIndex("link7"));
  EXPECT_EQ(model.frame_body(model.GetFrameIndex("tool")), tool);
  EXPECT_EQ(model.joint_type(tool), JointType::kFixed);
  const GeometryInstance& ee = model.geometries()[model.GetGeometryIndex("ee_sphere")];
  EXPECT_EQ(ee.body, tool);
  ASSERT_TRUE(std::holds_alternative<Sphere>(ee.shape));
  EXPECT_DOUBLE_EQ(std::get<Sphere>(ee.shape).radius, 0.04);
  EXPECT_EIGEN_NEAR(ee.X_BG.translation(), Eigen::Vector3d(0, 0, 0.06), kTol);
  // Masses as written.
  const double masses[] = {4, 4, 3, 2.7, 1.7, 1.8, 0.3};
  for (int i = 1; i <= 7; ++i) {
    EXPECT_DOUBLE_EQ(model.body_mass(model.GetBodyIndex("link" + std::to_string(i))),
                     masses[i - 1]);
  }
  // Limits, efforts and damping.
  EXPECT_DOUBLE_EQ(model.lower_position_limits()(6), -3.05433);
  EXPECT_DOUBLE_EQ(model.upper_position_limits()(6), 3.05433);
  EXPECT_DOUBLE_EQ(model.effort_limits()(0), 320.0);
  EXPECT_DOUBLE_EQ(model.effort_limits()(6), 40.0);
  EXPECT_DOUBLE_EQ(model.damping()(0), 0.5);
  EXPECT_DOUBLE_EQ(model.damping()(6), 0.1);
  for (bool b : model.is_base_velocity()) EXPECT_FALSE(b);
}

TEST(UrdfStructure, DepthFirstInDocumentOrder) {
  // Joints are written z_slider, a_spin, m_weld, b_arm: the bodies follow the depth-first order
  // of the document, not the alphabetical order of the joint names.
  const Model model = ParseUrdfFile(DataPath("mixed.urdf"));
  ASSERT_EQ(model.num_bodies(), 6);
  const char* expected[] = {"world", "base", "carriage", "rotor", "sensor", "arm"};
  for (int b = 0; b < 6; ++b) EXPECT_EQ(model.body_name(b), expected[b]);
  EXPECT_EQ(model.parent(model.GetBodyIndex("arm")), model.GetBodyIndex("base"));
  EXPECT_EQ(model.parent(model.GetBodyIndex("sensor")), model.GetBodyIndex("rotor"));
  EXPECT_EQ(model.nq(), 3);
  EXPECT_EQ(model.nv(), 3);
  EXPECT_EQ(model.GetPositionStart("z_slider"), 0);
  EXPECT_EQ(model.GetPositionStart("a_spin"), 1);
  EXPECT_EQ(model.GetPositionStart("b_arm"), 2);
  EXPECT_EQ(model.joint_type(model.GetJointIndex("z_slider")), JointType::kPrismatic);
  EXPECT_EQ(model.joint_type(model.GetJointIndex("a_spin")), JointType::kContinuous);
  EXPECT_EQ(model.joint_type(model.GetJointIndex("m_weld")), JointType::kFixed);
  EXPECT_EQ(model.joint_type(model.GetJointIndex("b_arm")), JointType::kRevolute);
  EXPECT_EQ(model.mobilized_body(model.GetBodyIndex("sensor")), model.GetBodyIndex("rotor"));
}

TEST(UrdfStructure, AxesAreNormalized) {
  const Model model = ParseUrdfFile(DataPath("mixed.urdf"));
  EXPECT_EIGEN_NEAR(model.joint_axis(model.GetJointIndex("z_slider")), Eigen::Vector3d::UnitZ(),
                    kTol);
  EXPECT_EIGEN_NEAR(model.joint_axis(model.GetJointIndex("a_spin")),
                    Eigen::Vector3d(1, 1, 0).normalized(), kTol);
  const Model planar = ParseUrdfFile(DataPath("planar_floating.urdf"));
  EXPECT_EIGEN_NEAR(planar.joint_axis(planar.GetJointIndex("slide_plane")),
                    Eigen::Vector3d(0, -1, 0), kTol);
}

TEST(UrdfStructure, JointFrames) {
  const Model model = ParseUrdfFile(DataPath("mixed.urdf"));
  const Eigen::Isometry3d X_expected = Pose(Eigen::Vector3d(0, 0.2, 0), Rpy(0.3, -0.2, 0.1));
  EXPECT_EIGEN_NEAR(model.joint_frame_in_parent(model.GetJointIndex("a_spin")).matrix(),
                    X_expected.matrix(), 1e-12);
  EXPECT_EIGEN_NEAR(model.joint_frame_in_parent(model.GetJointIndex("m_weld")).matrix(),
                    Pose(Eigen::Vector3d(0, 0, 0.1), Rpy(0, 0.5, 0)).matrix(), 1e-12);
}

TEST(UrdfStructure, DampingAndLimits) {
  const Model model = ParseUrdfFile(DataPath("mixed.urdf"));
  const int slider = model.GetVelocityStart("z_slider");
  const int spin = model.GetVelocityStart("a_spin");
  const int arm = model.GetVelocityStart("b_arm");
  EXPECT_DOUBLE_EQ(model.damping()(slider), 2.0);
  EXPECT_DOUBLE_EQ(model.damping()(spin), 0.05);
  EXPECT_DOUBLE_EQ(model.damping()(arm), 0.0);
  EXPECT_DOUBLE_EQ(model.joint_damping(model.GetJointIndex("z_slider")), 2.0);
  EXPECT_DOUBLE_EQ(model.effort_limits()(slider), 100.0);
  EXPECT_DOUBLE_EQ(model.effort_limits()(spin), 5.0);
  EXPECT_DOUBLE_EQ(model.effort_limits()(arm), 10.0);
  EXPECT_DOUBLE_EQ(model.lower_position_limits()(model.GetPositionStart("z_slider")), -0.5);
  EXPECT_DOUBLE_EQ(model.upper_position_limits()(model.GetPositionStart("z_slider")), 0.5);
  // A continuous joint is unbounded.
  EXPECT_EQ(model.lower_position_limits()(model.GetPositionStart("a_spin")), -kInf);
  EXPECT_EQ(model.upper_position_limits()(model.GetPositionStart("a_spin")), kInf);
  EXPECT_DOUBLE_EQ(model.lower_position_limits()(model.GetPositionStart("b_arm")), -1.0);
  EXPECT_DOUBLE_EQ(model.upper_position_limits()(model.GetPositionStart("b_arm")), 2.0);
}

TEST(UrdfStructure, LimitWithoutLowerAndUpperIsUnbounded) {
  const std::string xml = R"(<robot name="r">
    <link name="a"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
    <link name="b"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
    <joint name="j" type="prismatic"><parent link="a"/><child link="b"/>
      <axis xyz="1 0 0"/><limit effort="0" velocity="1"/></joint></robot>)";
  const Model model = ParseUrdfString(xml);
  EXPECT_EQ(model.lower_position_limits()(0), -kInf);
  EXPECT_EQ(model.upper_position_limits()(0), kInf);
  EXPECT_EQ(model.effort_limits()(0), kInf);  // effort="0": no effort limit
}

TEST(UrdfStructure, CollisionGeometry) {
  const Model model = ParseUrdfFile(DataPath("mixed.urdf"));
  const BodyIndex sensor = model.GetBodyIndex("sensor");
  // Five shapes; unnamed ones are named after their element position.
  ASSERT_EQ(model.geometries().size(), 5u);

  const GeometryInstance& s0 = model.geometries()[model.GetGeometryIndex("sensor_collision_0")];
  EXPECT_EQ(s0.body, sensor);
  ASSERT_TRUE(std::holds_alternative<Sphere>(s0.shape));
  EXPECT_DOUBLE_EQ(std::get<Sphere>(s0.shape).radius, 0.02);
  EXPECT_EIGEN_NEAR(s0.X_BG.translation(), Eigen::Vector3d(0.01, 0.02, 0.03), kTol);

  const GeometryInstance& box = model.geometries()[model.GetGeometryIndex("probe")];
  ASSERT_TRUE(std::holds_alternative<Box>(box.shape));
  EXPECT_EIGEN_NEAR(std::get<Box>(box.shape).size, Eigen::Vector3d(0.01, 0.02, 0.03), kTol);
  EXPECT_EIGEN_NEAR(box.X_BG.matrix(), Pose(Eigen::Vector3d(0, 0, 0.05), Rpy(0.1, 0, 0)).matrix(),
                    1e-12);

  // A repeated <collision name> is made unique.
  const GeometryInstance& cyl = model.geometries()[model.GetGeometryIndex("probe_1")];
  ASSERT_TRUE(std::holds_alternative<Cylinder>(cyl.shape));
  EXPECT_DOUBLE_EQ(std::get<Cylinder>(cyl.shape).radius, 0.015);
  EXPECT_DOUBLE_EQ(std::get<Cylinder>(cyl.shape).length, 0.08);  // full length, along z
  EXPECT_EIGEN_NEAR(cyl.X_BG.translation(), Eigen::Vector3d(0, 0, -0.05), kTol);

  const GeometryInstance& c3 = model.geometries()[model.GetGeometryIndex("sensor_collision_3")];
  ASSERT_TRUE(std::holds_alternative<Capsule>(c3.shape));
  EXPECT_DOUBLE_EQ(std::get<Capsule>(c3.shape).radius, 0.005);
  EXPECT_DOUBLE_EQ(std::get<Capsule>(c3.shape).length, 0.04);
  EXPECT_EIGEN_NEAR(c3.X_BG.translation(), Eigen::Vector3d(0, 0, 0.1), kTol);

  const GeometryInstance& s4 = model.geometries()[model.GetGeometryIndex("sensor_collision_4")];
  ASSERT_TRUE(std::holds_alternative<Sphere>(s4.shape));
  EXPECT_DOUBLE_EQ(std::get<Sphere>(s4.shape).radius, 0.01);
  for (const GeometryInstance& g : model.geometries()) EXPECT_EQ(g.body, sensor);

  const Model pendulum = ParseUrdfFile(DataPath("pendulum.urdf"));
  ASSERT_EQ(pendulum.geometries().size(), 1u);
  EXPECT_EQ(pendulum.geometries()[0].name, "arm_collision_0");
  EXPECT_EQ(pendulum.geometries()[0].body, pendulum.GetBodyIndex("arm"));
}

/// Names of a model's geometries.
std::vector<std::string> GeometryNames(const Model& model) {
  std::vector<std::string> names;
  for (const GeometryInstance& g : model.geometries()) names.push_back(g.name);
  return names;
}

TEST(UrdfStructure, BoxInscribedSpheres) {
  // With UrdfOptions::box_inscribed_spheres the box "probe" of mixed.urdf becomes its inscribed
  // spheres "probe_sphere0".."probe_sphere8", posed in the link like the box; the other shapes
  // (including the cylinder also named "probe", made "probe_1") stay as they are.
  UrdfOptions options;
  options.box_inscribed_spheres = InscribedSpheresOptions{};
  const Model model = ParseUrdfFile(DataPath("mixed.urdf"), options);
  ASSERT_EQ(model.geometries().size(), 4u + 9u);
  EXPECT_THAT(GeometryNames(model), ::testing::Not(::testing::Contains("probe")));
  EXPECT_THAT(GeometryNames(model), ::testing::Contains("probe_1"));
  const std::vector<InscribedSphere> expected =
      InscribedSpheres(Box{Eigen::Vector3d(0.01, 0.02, 0.03)});
  ASSERT_EQ(expected.size(), 9u);
  const Eigen::Isometry3d X_BBox = Pose(Eigen::Vector3d(0, 0, 0.05), Rpy(0.1, 0, 0));
  for (std::size_t k = 0; k < expected.size(); ++k) {
    SCOPED_TRACE(k);
    const GeometryInstance& g =
        model.geometries()[model.GetGeometryIndex("probe_sphere" + std::to_string(k))];
    EXPECT_EQ(g.body, model.GetBodyIndex("sensor"));
    ASSERT_TRUE(std::holds_alternative<Sphere>(g.shape));
    EXPECT_DOUBLE_EQ(std::get<Sphere>(g.shape).radius, expected[k].sphere.radius);
    EXPECT_EIGEN_NEAR(g.X_BG.matrix(), (X_BBox * expected[k].X_BoxSphere).matrix(), kTol);
  }

  // The paper's box (models/box.urdf) with a prefix and other options: 26 grid spheres.
  options.base = BaseType::kFloating;
  options.prefix = "p_";
  options.box_inscribed_spheres = InscribedSpheresOptions{3, 0.2, false};
  const Model box = ParseUrdfFile(ModelPath("box.urdf"), options);
  ASSERT_EQ(box.geometries().size(), 26u);
  EXPECT_EQ(box.geometries()[0].name, "p_box_sphere0");
  EXPECT_EQ(box.geometries()[25].name, "p_box_sphere25");
  EXPECT_DOUBLE_EQ(std::get<Sphere>(box.geometries()[0].shape).radius, 0.2 * 0.15);

  // Without the option the box stays a box.
  const Model plain = ParseUrdfFile(ModelPath("box.urdf"));
  ASSERT_EQ(plain.geometries().size(), 1u);
  EXPECT_TRUE(std::holds_alternative<Box>(plain.geometries()[0].shape));
}

TEST(UrdfStructure, InertialFrameRotation) {
  const Model model = ParseUrdfFile(DataPath("mixed.urdf"));
  const BodyInertia& rotor = model.body_inertia(model.GetBodyIndex("rotor"));
  Eigen::Matrix3d I;
  I << 0.004, 0.0003, 0.0002, 0.0003, 0.005, -0.0001, 0.0002, -0.0001, 0.006;
  const Eigen::Matrix3d R = Rpy(0.4, 0.5, 0.6);
  EXPECT_DOUBLE_EQ(rotor.mass, 0.5);
  EXPECT_EIGEN_NEAR(rotor.p_BBcm, Eigen::Vector3d(0.01, 0.02, 0.03), kTol);
  EXPECT_EIGEN_NEAR(rotor.I_BBcm_B, R * I * R.transpose(), 1e-15);
}

TEST(UrdfStructure, ModelName) {
  EXPECT_EQ(ParseUrdfFile(DataPath("pendulum.urdf")).name(), "pendulum");
  UrdfOptions options;
  options.model_name = "custom";
  EXPECT_EQ(ParseUrdfFile(DataPath("pendulum.urdf"), options).name(), "custom");
}

// ------------------------------------------------------------------------------------------------
// Bases, prefixes, the world root, scenes.

TEST(UrdfBase, Floating) {
  UrdfOptions options;
  options.base = BaseType::kFloating;
  const Model model = ParseUrdfFile(ModelPath("quadruped.urdf"), options);
  EXPECT_EQ(model.nq(), 19);
  EXPECT_EQ(model.nv(), 18);
  // world, body, 4 x (abad, thigh, shank, foot).
  EXPECT_EQ(model.num_bodies(), 18);
  const JointIndex root = model.GetJointIndex("body_root_joint");
  EXPECT_EQ(root, model.GetBodyIndex("body"));
  EXPECT_EQ(model.joint_type(root), JointType::kFloating);
  EXPECT_EQ(model.GetPositionStart("FL_abad_joint"), 7);
  EXPECT_EQ(model.GetVelocityStart("FL_abad_joint"), 6);
  EXPECT_EQ(model.GetVelocityStart("HR_knee_joint"), 17);
  for (int i = 0; i < model.nv(); ++i) EXPECT_EQ(model.is_base_velocity()[i], i < 6) << i;
  EXPECT_NEAR(model.total_mass(), 3.3 + 4 * (0.54 + 0.634 + 0.064), 1e-12);
  int feet = 0;
  for (const char* leg : {"FL", "FR", "HL", "HR"}) {
    const std::string name = std::string(leg) + "_foot";
    const GeometryInstance& g = model.geometries()[model.GetGeometryIndex(name + "_sphere")];
    EXPECT_EQ(g.body, model.GetBodyIndex(name));
    EXPECT_EQ(model.mobilized_body(g.body), model.GetBodyIndex(std::string(leg) + "_shank"));
    EXPECT_DOUBLE_EQ(std::get<Sphere>(g.shape).radius, 0.02);
    ++feet;
  }
  EXPECT_EQ(feet, 4);
}

TEST(UrdfBase, Planar) {
  UrdfOptions options;
  options.base = BaseType::kPlanar;
  options.planar_normal = Eigen::Vector3d(0, -3, 0);
  const Model model = ParseUrdfFile(DataPath("pendulum.urdf"), options);
  EXPECT_EQ(model.nq(), 4);
  EXPECT_EQ(model.nv(), 4);
  const JointIndex root = model.GetJointIndex("base_root_joint");
  EXPECT_EQ(model.joint_type(root), JointType::kPlanar);
  EXPECT_EIGEN_NEAR(model.joint_axis(root), Eigen::Vector3d(0, -1, 0), kTol);
  EXPECT_EQ(model.GetPositionStart("pivot"), 3);
  const std::vector<bool> expected = {true, true, true, false};
  EXPECT_EQ(model.is_base_velocity(), expected);
}

TEST(UrdfBase, FixedAtPose) {
  UrdfOptions options;
  options.X_WB = Pose(Eigen::Vector3d(1, 2, 0.5), Rpy(0, 0, 0.7));
  const Model model = ParseUrdfFile(ModelPath("arm7.urdf"), options);
  EXPECT_EQ(model.nq(), 7);
  EXPECT_EIGEN_NEAR(model.joint_frame_in_parent(model.GetBodyIndex("base")).matrix(),
                    options.X_WB.matrix(), kTol);
}

TEST(UrdfBase, UrdfPlanarAndFloatingJoints) {
  const Model model = ParseUrdfFile(DataPath("planar_floating.urdf"));
  EXPECT_EQ(model.nq(), 10);
  EXPECT_EQ(model.nv(), 9);
  EXPECT_EQ(model.joint_type(model.GetJointIndex("slide_plane")), JointType::kPlanar);
  EXPECT_EQ(model.joint_type(model.GetJointIndex("free")), JointType::kFloating);
  EXPECT_EQ(model.GetPositionStart("free"), 3);
  EXPECT_EQ(model.GetVelocityStart("free"), 3);
  // Both hang from a base welded to the world: they are base velocities (unactuated).
  for (bool b : model.is_base_velocity()) EXPECT_TRUE(b);
  EXPECT_DOUBLE_EQ(model.damping()(0), 0.3);
  EXPECT_DOUBLE_EQ(model.damping()(2), 0.3);
}

TEST(UrdfBase, WorldRootIsTheWorld) {
  UrdfOptions options;
  options.X_WB = Pose(Eigen::Vector3d(0, 0, 1), Eigen::Matrix3d::Identity());
  // The URDF's world link attaches the model: a floating or planar base could not apply, and is
  // refused rather than dropped.
  for (BaseType base : {BaseType::kFloating, BaseType::kPlanar}) {
    UrdfOptions moving = options;
    moving.base = base;
    EXPECT_THAT([&] { ParseUrdfFile(DataPath("world_root.urdf"), moving); },
                ThrowsMessage<FileError>(
                    AllOf(HasSubstr("world_root.urdf"), HasSubstr("the root link is 'world'"),
                          HasSubstr("options.base"), HasSubstr("expected fixed"))));
  }
  const Model model = ParseUrdfFile(DataPath("world_root.urdf"), options);
  EXPECT_EQ(model.nq(), 1);
  EXPECT_EQ(model.num_bodies(), 3);  // world, cart, post
  EXPECT_EQ(model.parent(model.GetBodyIndex("cart")), kWorldBody);
  EXPECT_EQ(model.joint_type(model.GetJointIndex("rail")), JointType::kPrismatic);
  EXPECT_EIGEN_NEAR(model.joint_frame_in_parent(model.GetJointIndex("rail")).translation(),
                    Eigen::Vector3d(0, 0, 1.5), kTol);
  EXPECT_EQ(model.mobilized_body(model.GetBodyIndex("post")), kWorldBody);
  const GeometryInstance& floor = model.geometries()[model.GetGeometryIndex("floor")];
  EXPECT_EQ(floor.body, kWorldBody);
  EXPECT_EIGEN_NEAR(floor.X_BG.translation(), Eigen::Vector3d(0, 0, 0.95), kTol);
  const GeometryInstance& post = model.geometries()[model.GetGeometryIndex("post_collision_0")];
  EXPECT_EQ(post.body, model.GetBodyIndex("post"));
  EXPECT_EQ(std::get<Cylinder>(post.shape).length, 1.0);
}

TEST(UrdfBase, WorldRootWithPrefix) {
  ModelBuilder builder("scene");
  UrdfOptions options;
  options.prefix = "p_";
  options.X_WB = Pose(Eigen::Vector3d(2, 0, 0), Eigen::Matrix3d::Identity());
  EXPECT_EQ(AddUrdfFile(DataPath("world_root.urdf"), options, &builder), kWorldBody);
  const Model model = builder.Build();
  EXPECT_TRUE(model.HasBody("p_cart"));
  EXPECT_TRUE(model.HasJoint("p_rail"));
  EXPECT_FALSE(model.HasBody("p_world"));
  const FrameIndex f = model.GetFrameIndex("p_world");
  EXPECT_EQ(model.frame_body(f), kWorldBody);
  EXPECT_EIGEN_NEAR(model.X_BF(f).matrix(), options.X_WB.matrix(), kTol);
  EXPECT_EQ(model.geometries()[model.GetGeometryIndex("p_floor")].body, kWorldBody);
}

TEST(UrdfScene, PrefixesEveryName) {
  UrdfOptions options;
  options.prefix = "left_";
  options.base = BaseType::kFloating;
  const Model model = ParseUrdfFile(ModelPath("arm7.urdf"), options);
  EXPECT_EQ(model.nq(), 14);
  EXPECT_TRUE(model.HasBody("left_link7"));
  EXPECT_FALSE(model.HasBody("link7"));
  EXPECT_TRUE(model.HasJoint("left_joint1"));
  EXPECT_TRUE(model.HasJoint("left_tool_joint"));
  EXPECT_TRUE(model.HasJoint("left_base_root_joint"));
  EXPECT_TRUE(model.HasFrame("left_tool"));
  EXPECT_EQ(model.geometries()[model.GetGeometryIndex("left_ee_sphere")].body,
            model.GetBodyIndex("left_tool"));
  EXPECT_EQ(model.GetPositionStart("left_joint1"), 7);
}

TEST(UrdfScene, TwoArms) {
  ModelBuilder builder("bimanual");
  UrdfOptions left;
  left.prefix = "left_";
  left.X_WB = Pose(Eigen::Vector3d(0, 0.5, 0), Eigen::Matrix3d::Identity());
  UrdfOptions right = left;
  right.prefix = "right_";
  right.X_WB = Pose(Eigen::Vector3d(0, -0.5, 0), Eigen::Matrix3d::Identity());
  EXPECT_EQ(AddUrdfFile(ModelPath("arm7.urdf"), left, &builder), 1);
  EXPECT_EQ(AddUrdfFile(ModelPath("arm7.urdf"), right, &builder), 10);
  const Model model = builder.Build();
  EXPECT_EQ(model.name(), "bimanual");
  EXPECT_EQ(model.nq(), 14);
  EXPECT_EQ(model.GetPositionStart("right_joint1"), 7);
  EXPECT_EQ(model.geometries().size(), 4u);
}

TEST(UrdfScene, HandAndBall) {
  ModelBuilder builder("hand_ball");
  UrdfOptions hand;  // fixed palm
  UrdfOptions ball;
  ball.base = BaseType::kFloating;
  ball.X_WB = Pose(Eigen::Vector3d(0.06, 0, 0.1), Eigen::Matrix3d::Identity());
  AddUrdfFile(ModelPath("allegro_hand.urdf"), hand, &builder);
  const BodyIndex ball_body = AddUrdfFile(ModelPath("ball.urdf"), ball, &builder);
  const Model model = builder.Build();
  EXPECT_EQ(model.nv(), 22);
  EXPECT_EQ(model.nq(), 23);
  EXPECT_EQ(ball_body, model.GetBodyIndex("ball"));
  EXPECT_EQ(model.GetPositionStart("ball_root_joint"), 16);
  EXPECT_EQ(model.GetVelocityStart("ball_root_joint"), 16);
  EXPECT_EQ(model.GetPositionStart("index_joint0"), 0);
  EXPECT_EQ(model.GetPositionStart("middle_joint0"), 4);
  EXPECT_EQ(model.GetPositionStart("ring_joint0"), 8);
  EXPECT_EQ(model.GetPositionStart("thumb_joint0"), 12);
  for (int i = 0; i < model.nv(); ++i) EXPECT_EQ(model.is_base_velocity()[i], i >= 16) << i;
  EXPECT_NO_THROW(model.GetGeometryIndex("ball_sphere"));
  EXPECT_NO_THROW(model.GetGeometryIndex("thumb_tip_sphere"));
  EXPECT_NEAR(model.body_mass(ball_body), 0.05, 1e-15);
}

TEST(UrdfScene, DuplicateNamesAcrossModelsNameTheSecondFile) {
  ModelBuilder builder("twice");
  const std::string path = ModelPath("arm7.urdf");
  AddUrdfFile(path, {}, &builder);
  EXPECT_THAT([&] { AddUrdfFile(path, {}, &builder); },
              ThrowsMessage<FileError>(AllOf(HasSubstr(path), HasSubstr("link 'base'"))));
}

TEST(UrdfScene, AllModelsParse) {
  for (const char* name : {"arm7.urdf", "quadruped.urdf", "allegro_hand.urdf", "ball.urdf"}) {
    UrdfOptions options;
    if (std::string(name) == "quadruped.urdf" || std::string(name) == "ball.urdf") {
      options.base = BaseType::kFloating;
    }
    EXPECT_NO_THROW(ParseUrdfFile(ModelPath(name), options)) << name;
  }
  EXPECT_EQ(ParseUrdfFile(ModelPath("allegro_hand.urdf")).nv(), 16);
}

TEST(UrdfScene, JacoArmsAndBox) {
  // models/jaco_arm.urdf: 7 DoFs, three collision spheres near the end effector; two of them and
  // the box (floating, 9 inscribed spheres) make the 20-DoF bi-manual scene.
  const Model arm = ParseUrdfFile(ModelPath("jaco_arm.urdf"));
  EXPECT_EQ(arm.nq(), 7);
  EXPECT_EQ(arm.nv(), 7);
  EXPECT_THAT(GeometryNames(arm),
              ::testing::UnorderedElementsAre("wrist_sphere", "palm_sphere", "finger_sphere"));
  // Moving mass: links 1-6 and the hand (link 7), 5.33 kg.
  double moving_mass = 0.0;
  for (int i = 1; i <= 7; ++i) {
    moving_mass += arm.body_mass(arm.GetBodyIndex("link" + std::to_string(i)));
  }
  EXPECT_NEAR(moving_mass, 0.7477 + 2 * 0.8447 + 0.6763 + 2 * 0.463 + 0.787, 1e-12);
  // At q = 0 the arm stands straight up: the fingertip frame is D1 + D2 + D3 + D4 + D5 + D6 + D7
  // above the base.
  Data data(arm);
  ForwardKinematics(arm, Eigen::VectorXd::Zero(7), Eigen::VectorXd::Zero(7), &data);
  const FrameIndex ee = arm.GetFrameIndex("end_effector");
  const Eigen::Isometry3d X_WE = data.X_WB(arm.frame_body(ee)) * arm.X_BF(ee);
  EXPECT_EIGEN_NEAR(X_WE.translation(),
                    Eigen::Vector3d(0, 0, 0.2755 + 0.41 + 0.2073 + 0.10375 + 0.10375 + 0.16),
                    1e-12);

  ModelBuilder builder("bimanual");
  UrdfOptions left;
  left.prefix = "left_";
  UrdfOptions right;
  right.prefix = "right_";
  right.X_WB.translation() = Eigen::Vector3d(0, -0.8, 0);
  UrdfOptions box;
  box.base = BaseType::kFloating;
  box.box_inscribed_spheres = InscribedSpheresOptions{};
  AddUrdfFile(ModelPath("jaco_arm.urdf"), left, &builder);
  AddUrdfFile(ModelPath("jaco_arm.urdf"), right, &builder);
  AddUrdfFile(ModelPath("box.urdf"), box, &builder);
  const Model scene = builder.Build();
  EXPECT_EQ(scene.nv(), 20);
  EXPECT_EQ(scene.nq(), 21);
  EXPECT_EQ(scene.geometries().size(), 3u + 3u + 9u);
  EXPECT_NEAR(scene.body_inertia(scene.GetBodyIndex("box")).mass, 0.55, 1e-15);
}

// ------------------------------------------------------------------------------------------------
// Numbers through the multibody algorithms.

TEST(UrdfNumbers, Arm7ForwardKinematicsAtZero) {
  UrdfOptions options;
  options.X_WB = Pose(Eigen::Vector3d(1, 2, 0.5), Rpy(0, 0, 0.7));
  const Model model = ParseUrdfFile(ModelPath("arm7.urdf"), options);
  Data data(model);
  ForwardKinematics(model, Eigen::VectorXd::Zero(7), &data);
  const double height = 0.1575 + 0.2025 + 0.2045 + 0.2155 + 0.1845 + 0.2155 + 0.081;
  EXPECT_EIGEN_NEAR(data.X_WB(model.GetBodyIndex("link7")).translation(),
                    options.X_WB * Eigen::Vector3d(0, 0, height), 1e-12);
  EXPECT_EIGEN_NEAR(data.X_WB(model.GetBodyIndex("tool")).translation(),
                    options.X_WB * Eigen::Vector3d(0, 0, height + 0.045), 1e-12);
}

TEST(UrdfNumbers, PrismaticAxisIsNormalizedInKinematics) {
  const Model model = ParseUrdfFile(DataPath("mixed.urdf"));
  Data data(model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(3);
  q(model.GetPositionStart("z_slider")) = 0.3;
  ForwardKinematics(model, q, &data);
  // Axis "0 0 2" moves the carriage by q, not 2q.
  EXPECT_EIGEN_NEAR(data.X_WB(model.GetBodyIndex("carriage")).translation(),
                    Eigen::Vector3d(0.1, 0, 0.3), 1e-12);
}

TEST(UrdfNumbers, WeldedBodyKeepsItsFrame) {
  const Model model = ParseUrdfFile(DataPath("mixed.urdf"));
  Data data(model);
  const Eigen::VectorXd q = Eigen::Vector3d(0.1, 0.7, -0.4);
  ForwardKinematics(model, q, &data);
  const Eigen::Isometry3d X_RS = Pose(Eigen::Vector3d(0, 0, 0.1), Rpy(0, 0.5, 0));
  EXPECT_EIGEN_NEAR(data.X_WB(model.GetBodyIndex("sensor")).matrix(),
                    (data.X_WB(model.GetBodyIndex("rotor")) * X_RS).matrix(), 1e-12);
  // The continuous joint turns the rotor about the normalized axis in its joint frame.
  const Eigen::Isometry3d X_CJ = Pose(Eigen::Vector3d(0, 0.2, 0), Rpy(0.3, -0.2, 0.1));
  const Eigen::Isometry3d X_JR =
      Pose(Eigen::Vector3d::Zero(),
           Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix());
  EXPECT_EIGEN_NEAR(data.X_WB(model.GetBodyIndex("rotor")).matrix(),
                    (data.X_WB(model.GetBodyIndex("carriage")) * X_CJ * X_JR).matrix(), 1e-12);
}

TEST(UrdfNumbers, QuadrupedFootAtNeutral) {
  UrdfOptions options;
  options.base = BaseType::kFloating;
  const Model model = ParseUrdfFile(ModelPath("quadruped.urdf"), options);
  Data data(model);
  ForwardKinematics(model, model.NeutralConfiguration(), &data);
  EXPECT_EIGEN_NEAR(data.X_WB(model.GetBodyIndex("FL_foot")).translation(),
                    Eigen::Vector3d(0.19, 0.111, -0.418), 1e-12);
  EXPECT_EIGEN_NEAR(data.X_WB(model.GetBodyIndex("HR_foot")).translation(),
                    Eigen::Vector3d(-0.19, -0.111, -0.418), 1e-12);
}

/// A one-link URDF whose inertial frame is rotated and offset.
std::string OneLinkUrdf() {
  return R"(<robot name="one_link">
    <link name="body">
      <inertial>
        <origin xyz="0.1 -0.2 0.3" rpy="0.3 -0.7 1.1"/>
        <mass value="2.5"/>
        <inertia ixx="0.04" ixy="0.002" ixz="-0.003" iyy="0.05" iyz="0.001" izz="0.06"/>
      </inertial>
    </link></robot>)";
}

TEST(UrdfNumbers, RotatedInertialFrameMassMatrix) {
  UrdfOptions options;
  options.base = BaseType::kFloating;
  const Model model = ParseUrdfString(OneLinkUrdf(), options, "one_link.urdf");
  ASSERT_EQ(model.nv(), 6);
  Data data(model);
  const Eigen::MatrixXd& M = MassMatrix(model, model.NeutralConfiguration(), &data);

  const double m = 2.5;
  const Eigen::Vector3d c(0.1, -0.2, 0.3);
  Eigen::Matrix3d I;
  I << 0.04, 0.002, -0.003, 0.002, 0.05, 0.001, -0.003, 0.001, 0.06;
  const Eigen::Matrix3d R = Rpy(0.3, -0.7, 1.1);
  const Eigen::Matrix3d Ic = R * I * R.transpose();
  // v = [w; v_Bo], kinetic energy 1/2 m |v_Bo + w x c|^2 + 1/2 w' Ic w.
  Eigen::Matrix<double, 6, 6> expected;
  expected.topLeftCorner<3, 3>() = Ic + m * Skew(c).transpose() * Skew(c);
  expected.topRightCorner<3, 3>() = m * Skew(c);
  expected.bottomLeftCorner<3, 3>() = -m * Skew(c);
  expected.bottomRightCorner<3, 3>() = m * Eigen::Matrix3d::Identity();
  EXPECT_EIGEN_NEAR(M, expected, 1e-12);
}

TEST(UrdfNumbers, RotatedInertialFrameRevolute) {
  // The same link on a revolute joint with an unnormalized axis: M = a' (Ic + m [c]'[c]) a.
  const std::string xml = R"(<robot name="r">
    <link name="base"/>
    <link name="body">
      <inertial>
        <origin xyz="0.1 -0.2 0.3" rpy="0.3 -0.7 1.1"/>
        <mass value="2.5"/>
        <inertia ixx="0.04" ixy="0.002" ixz="-0.003" iyy="0.05" iyz="0.001" izz="0.06"/>
      </inertial>
    </link>
    <joint name="hinge" type="continuous"><parent link="base"/><child link="body"/>
      <axis xyz="1 2 -2"/></joint></robot>)";
  const Model model = ParseUrdfString(xml);
  Data data(model);
  const Eigen::MatrixXd& M = MassMatrix(model, Eigen::VectorXd::Zero(1), &data);
  const Eigen::Vector3d a = Eigen::Vector3d(1, 2, -2) / 3.0;
  const double m = 2.5;
  const Eigen::Vector3d c(0.1, -0.2, 0.3);
  Eigen::Matrix3d I;
  I << 0.04, 0.002, -0.003, 0.002, 0.05, 0.001, -0.003, 0.001, 0.06;
  const Eigen::Matrix3d R = Rpy(0.3, -0.7, 1.1);
  const double expected = a.dot((R * I * R.transpose() + m * Skew(c).transpose() * Skew(c)) * a);
  EXPECT_NEAR(M(0, 0), expected, 1e-12);
}

TEST(UrdfNumbers, PendulumInverseDynamics) {
  const Model model = ParseUrdfFile(DataPath("pendulum.urdf"));
  Data data(model);
  const double theta = 0.4, omega = 1.3, alpha = -0.7;
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, theta);
  const Eigen::VectorXd v = Eigen::VectorXd::Constant(1, omega);
  const Eigen::VectorXd a = Eigen::VectorXd::Constant(1, alpha);
  const Eigen::VectorXd& tau = InverseDynamics(model, q, v, a, &data);
  const double inertia = 1.0 * 0.25 + 0.001;
  const double expected = inertia * alpha + 1.0 * 9.81 * 0.5 * std::sin(theta) + 0.1 * omega;
  EXPECT_NEAR(tau(0), expected, 1e-12);
}

TEST(UrdfNumbers, HandBallSceneMassMatrixIsBlockDiagonal) {
  ModelBuilder builder("hand_ball");
  UrdfOptions ball;
  ball.base = BaseType::kFloating;
  AddUrdfFile(ModelPath("allegro_hand.urdf"), {}, &builder);
  AddUrdfFile(ModelPath("ball.urdf"), ball, &builder);
  const Model model = builder.Build();
  Data data(model);
  const Eigen::MatrixXd& M = MassMatrix(model, model.NeutralConfiguration(), &data);
  EXPECT_EIGEN_NEAR(M.topRightCorner(16, 6), Eigen::MatrixXd::Zero(16, 6), 0.0);
  Eigen::Matrix<double, 6, 6> ball_M = Eigen::Matrix<double, 6, 6>::Zero();
  ball_M.topLeftCorner<3, 3>() = 7.2e-5 * Eigen::Matrix3d::Identity();
  ball_M.bottomRightCorner<3, 3>() = 0.05 * Eigen::Matrix3d::Identity();
  EXPECT_EIGEN_NEAR(M.bottomRightCorner(6, 6), ball_M, 1e-15);
}

}  // namespace
}  // namespace idto
