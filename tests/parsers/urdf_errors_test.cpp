// URDF parser errors: every message names the file and the element (structure, conventions
// and numbers are in urdf_test.cpp).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Core>

#include "idto/core/errors.hpp"
#include "idto/multibody/algorithms/dynamics.hpp"
#include "idto/multibody/data.hpp"
#include "idto/parsers/urdf.hpp"

namespace idto {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

std::string DataPath(const std::string& name) {
  return std::string(IDTO_TEST_DATA_DIR) + "/urdf/" + name;
}
std::string ErrorPath(const std::string& name) { return DataPath("errors/" + name); }
std::string ModelPath(const std::string& name) {
  return std::string(IDTO_SOURCE_DIR) + "/models/" + name;
}

struct ErrorCase {
  const char* file;
  const char* element;  // expected in what() and element()
  const char* problem;  // expected in what()
};

std::ostream& operator<<(std::ostream& out, const ErrorCase& c) { return out << c.file; }

class UrdfError : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(UrdfError, NamesFileAndElement) {
  const ErrorCase& c = GetParam();
  const std::string path = ErrorPath(c.file);
  UrdfOptions options;
  EXPECT_THAT(
      [&] { ParseUrdfFile(path, options); },
      ThrowsMessage<FileError>(AllOf(HasSubstr(path), HasSubstr(c.element), HasSubstr(c.problem))));
  try {
    ParseUrdfFile(path, options);
  } catch (const FileError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_THAT(e.element(), HasSubstr(c.element));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Files, UrdfError,
    ::testing::Values(
        ErrorCase{"malformed_xml.urdf", "XML", "malformed XML"},
        ErrorCase{"no_robot.urdf", "robot", "no <robot> element"},
        ErrorCase{"unknown_joint_type.urdf", "joint 'weird_joint'", "unknown joint type 'hinge'"},
        ErrorCase{"zero_axis.urdf", "joint 'bad_axis_joint'", "<axis xyz>"},
        ErrorCase{"negative_mass.urdf", "link 'heavy_link'", "mass is -1"},
        ErrorCase{"zero_mass.urdf", "link 'ghost_link'", "positive mass"},
        ErrorCase{"no_inertial.urdf", "link 'empty_link'", "no <inertial>"},
        ErrorCase{"indefinite_inertia.urdf", "link 'odd_link'", "not positive semi-definite"},
        ErrorCase{"point_on_axis.urdf", "joint 'spin'", "not positive definite"},
        ErrorCase{"two_roots.urdf", "link 'stray_link'", "several root links"},
        ErrorCase{"cycle.urdf", "robot 'cycle_robot'", "no root link"},
        ErrorCase{"detached_cycle.urdf", "link 'c_link'", "not connected to the root link"},
        ErrorCase{"duplicate_link.urdf", "link 'twin_link'", "duplicate link name"},
        ErrorCase{"duplicate_joint.urdf", "joint 'twin_joint'", "duplicate joint name"},
        ErrorCase{"two_parents.urdf", "link 'shared_link'", "child of two joints"},
        ErrorCase{"undefined_link.urdf", "joint 'dangling_joint'", "'nowhere' is not defined"},
        ErrorCase{"bad_origin.urdf", "joint 'short_origin_joint'",
                  "<origin xyz> is \"1 2\"; expected 3 numbers"},
        ErrorCase{"negative_damping.urdf", "joint 'leaky_joint'", "damping"},
        ErrorCase{"inverted_limits.urdf", "joint 'backwards_joint'", "lower <= upper"},
        ErrorCase{"bad_sphere.urdf", "link 'base'", "flat_ball"},
        // Elements idto cannot represent, and values urdfdom would stop reading a link at.
        ErrorCase{"collision_mesh.urdf", "link 'foot'",
                  "collision 'sole' (line 8): <mesh filename=\"package://robot/sole.obj\"> is "
                  "not supported"},
        ErrorCase{"visual_mesh.urdf", "link 'shell'", "<mesh filename=\"shell.stl\">"},
        ErrorCase{"unknown_link_element.urdf", "link 'camera_link'",
                  "unsupported element <sensor>"},
        ErrorCase{"mimic.urdf", "joint 'right_finger'", "<mimic>"},
        ErrorCase{"nan_box.urdf", "link 'block'", "<box size> is (nan, 1, 1)"},
        ErrorCase{"typo_radius.urdf", "link 'hand'", "<sphere radius> is \"0.O5\""},
        ErrorCase{"nan_mass.urdf", "link 'arm'", "<inertial> mass is nan"},
        ErrorCase{"welded_mass_typo.urdf", "link 'payload'", "<mass value> is \"1O\""}),
    [](const ::testing::TestParamInfo<ErrorCase>& param_info) {
      std::string name = param_info.param.file;
      name = name.substr(0, name.find('.'));
      return name;
    });

TEST(UrdfErrors, MissingFileNamesThePath) {
  const std::string path = DataPath("no_such_file.urdf");
  EXPECT_THAT([&] { ParseUrdfFile(path); },
              ThrowsMessage<FileError>(AllOf(HasSubstr(path), HasSubstr("not found"))));
  ModelBuilder builder;
  EXPECT_THAT([&] { AddUrdfFile(path, {}, &builder); }, ThrowsMessage<FileError>(HasSubstr(path)));
  EXPECT_THAT([&] { ParseUrdfFile(IDTO_TEST_DATA_DIR); },
              ThrowsMessage<FileError>(HasSubstr("not a regular file")));
}

TEST(UrdfErrors, StringSourceNameAppearsInMessages) {
  EXPECT_THAT([] { ParseUrdfString("<robot name='x'><link name='a'/>", {}, "my_source.urdf"); },
              ThrowsMessage<FileError>(HasSubstr("my_source.urdf")));
  EXPECT_THAT([] { ParseUrdfString(""); }, ThrowsMessage<FileError>(HasSubstr("<urdf string>")));
}

TEST(UrdfErrors, UrdfdomMessagesAreNotPrinted) {
  // urdfdom (the cross-check) refuses these files and logs why; nothing may be printed.
  ::testing::internal::CaptureStderr();
  ::testing::internal::CaptureStdout();
  EXPECT_NO_THROW(ParseUrdfFile(DataPath("revolute_without_limit.urdf")));
  EXPECT_NO_THROW(ParseUrdfFile(DataPath("reference/hopper.urdf")));
  EXPECT_THROW(ParseUrdfFile(ErrorPath("bad_origin.urdf")), FileError);
  const std::string err = ::testing::internal::GetCapturedStderr();
  const std::string out = ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(err, "");
  EXPECT_EQ(out, "");
}

TEST(UrdfErrors, BadOptions) {
  UrdfOptions options;
  options.base = BaseType::kPlanar;
  options.planar_normal.setZero();
  EXPECT_THROW(ParseUrdfFile(DataPath("pendulum.urdf"), options), InvalidArgument);
  EXPECT_THROW(AddUrdfFile(DataPath("pendulum.urdf"), {}, nullptr), InvalidArgument);
  // A plane normal without a planar base would not be used.
  for (BaseType base : {BaseType::kFixed, BaseType::kFloating}) {
    UrdfOptions unused;
    unused.base = base;
    unused.planar_normal = Eigen::Vector3d(0, 1, 0);
    EXPECT_THAT([&] { ParseUrdfFile(DataPath("pendulum.urdf"), unused); },
                ThrowsMessage<InvalidArgument>(
                    AllOf(HasSubstr("options.planar_normal is (0, 1, 0)"),
                          HasSubstr("unless options.base is BaseType::kPlanar"))));
  }
}

TEST(UrdfErrors, BadInscribedSpheresOptions) {
  UrdfOptions options;
  options.box_inscribed_spheres = InscribedSpheresOptions{2, 0.6, true};
  EXPECT_THAT([&] { ParseUrdfFile(ModelPath("box.urdf"), options); },
              ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("box_inscribed_spheres"), HasSubstr("radius_fraction"))));
  options.box_inscribed_spheres = InscribedSpheresOptions{1, 0.25, true};
  EXPECT_THAT([&] { ParseUrdfFile(ModelPath("box.urdf"), options); },
              ThrowsMessage<InvalidArgument>(
                  AllOf(HasSubstr("box_inscribed_spheres"), HasSubstr("num_per_axis"))));
}

TEST(UrdfErrors, MovingRootWithoutMassNamesTheLink) {
  // A root link without <inertial> is fine on a fixed base and an error on a floating one.
  const std::string xml = R"(<robot name="r"><link name="massless_root"/></robot>)";
  EXPECT_NO_THROW(ParseUrdfString(xml));
  UrdfOptions options;
  options.base = BaseType::kFloating;
  EXPECT_THAT([&] { ParseUrdfString(xml, options, "massless.urdf"); },
              ThrowsMessage<FileError>(
                  AllOf(HasSubstr("massless.urdf"), HasSubstr("link 'massless_root'"))));
}

TEST(UrdfErrors, WeldedChildGivesMassToAMovingLink) {
  // A moving link without <inertial> is fine when a welded child carries the mass.
  const std::string xml = R"(<robot name="r">
    <link name="base"/>
    <link name="holder"/>
    <link name="weight"><inertial><origin xyz="0 0 -0.3"/><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
    <joint name="hinge" type="continuous"><parent link="base"/><child link="holder"/>
      <axis xyz="0 1 0"/></joint>
    <joint name="weld" type="fixed"><parent link="holder"/><child link="weight"/>
      <origin xyz="0 0 -0.2"/></joint></robot>)";
  const Model model = ParseUrdfString(xml);
  EXPECT_EQ(model.nv(), 1);
  Data data(model);
  EXPECT_NEAR(MassMatrix(model, Eigen::VectorXd::Zero(1), &data)(0, 0), 0.25 + 0.01, 1e-12);
}

TEST(UrdfErrors, ConcurrentParsesKeepTheirOwnMessages) {
  std::vector<std::thread> threads;
  std::vector<int> ok(8, 0);
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([t, &ok] {
      for (int k = 0; k < 10; ++k) {
        try {
          if (t % 2 == 0) {
            ParseUrdfFile(ModelPath("arm7.urdf"));
            ++ok[static_cast<size_t>(t)];
          } else {
            ParseUrdfFile(ErrorPath("typo_radius.urdf"));
          }
        } catch (const FileError& e) {
          const std::string what = e.what();
          if (what.find("0.O5") != std::string::npos &&
              what.find("typo_radius.urdf") != std::string::npos) {
            ++ok[static_cast<size_t>(t)];
          }
        }
      }
    });
  }
  for (std::thread& th : threads) th.join();
  for (int t = 0; t < 8; ++t) EXPECT_EQ(ok[static_cast<size_t>(t)], 10) << t;
}

}  // namespace
}  // namespace idto
