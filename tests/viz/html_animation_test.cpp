// The viewer page without a browser: its content, the scene data, subsampling, contact forces,
// and bad input (sizes, non-finite values, unwritable paths: clear errors, nothing left behind).

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "idto/idto.hpp"
#include "idto/viz/html_animation.hpp"
#include "viz/mini_json.hpp"
#include "viz/viz_scene.hpp"

namespace idto {
namespace {

namespace fs = std::filesystem;
using test::Json;
using ::testing::HasSubstr;

class HtmlAnimationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("idto_viz_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // Files in dir_ (names only).
  std::vector<std::string> Files() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename());
    return names;
  }
  static std::string Read(const fs::path& path) {
    std::ifstream in(path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  fs::path dir_;
  Model model_ = test::VizScene();
};

TEST_F(HtmlAnimationTest, PageIsSelfContained) {
  HtmlAnimationOptions options;
  options.title = "ball <&> arm";
  options.contact = ContactOptions{};
  const std::string page = MakeHtmlAnimation(model_, test::VizFrames(model_, 100.0, true), options);
  // (find, not HasSubstr: a failure would print the whole page with three.js)
  const auto has = [&page](const std::string& text) {
    return page.find(text) != std::string::npos;
  };
  EXPECT_TRUE(has("default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'"));
  EXPECT_TRUE(has("var REVISION=\"111\""));  // three.js r111, inlined
  EXPECT_TRUE(has("exports.OrbitControls = OrbitControls"));
  EXPECT_TRUE(has("<title>ball &lt;&amp;&gt; arm</title>"));
  EXPECT_FALSE(has("<script src"));
  EXPECT_FALSE(has("<link"));
  EXPECT_FALSE(has("@IDTO_"));  // every marker filled
  const Json scene = test::SceneOfPage(page);
  EXPECT_EQ(scene["title"].string, "ball <&> arm");
  EXPECT_EQ(scene["bodies"].size(), static_cast<std::size_t>(model_.num_bodies()));
  EXPECT_EQ(scene["geometries"].size(), model_.geometries().size());
  // Two models (the ball, the arm) and the table welded to the world: three roots.
  EXPECT_EQ(scene["models"].size(), 3u);
  EXPECT_EQ(scene["animated"].size(), 3u);  // ball, upper, forearm
  EXPECT_EQ(scene["times"].size(), 121u);   // 100 Hz subsampled: one frame per 1/60 s
}

TEST_F(HtmlAnimationTest, SubsamplesToTheFrameRateKeepingFirstAndLast) {
  const Model many = test::ManyBodies(20);
  HtmlAnimationOptions options;
  const std::vector<AnimationFrame> frames = test::ManyBodyFrames(many, 10.0, 1000.0);
  ASSERT_EQ(frames.size(), 10001u);
  const Json scene = test::SceneOfPage(MakeHtmlAnimation(many, frames, options));
  const Json& times = scene["times"];
  EXPECT_EQ(times.size(), 601u);
  EXPECT_DOUBLE_EQ(times[0].number, 0.0);
  EXPECT_DOUBLE_EQ(times[times.size() - 1].number, 10.0);
  for (std::size_t k = 1; k < times.size(); ++k) {
    EXPECT_NEAR(times[k].number - times[k - 1].number, 1.0 / 60.0, 1.5e-3) << k;
  }
  EXPECT_EQ(scene["poses"][0].size(), 20u * 7u);
}

TEST_F(HtmlAnimationTest, PosesAreForwardKinematics) {
  HtmlAnimationOptions options;
  options.max_frame_rate = 1000.0;
  const std::vector<AnimationFrame> frames = test::VizFrames(model_, 100.0, true);
  const Json scene = test::SceneOfPage(MakeHtmlAnimation(model_, frames, options));
  ASSERT_EQ(scene["times"].size(), frames.size());
  Data data(model_);
  for (std::size_t k : {0u, 77u, 200u}) {
    for (bool ghost : {false, true}) {
      ForwardKinematics(model_, ghost ? frames[k].q_ghost : frames[k].q, &data);
      const Json& poses = scene[ghost ? "ghost" : "poses"][k];
      for (std::size_t slot = 0; slot < scene["animated"].size(); ++slot) {
        const int b = static_cast<int>(scene["animated"][slot].number);
        for (int i = 0; i < 3; ++i) {
          EXPECT_NEAR(poses[7 * slot + i].number, data.p_WB(b)(i), 1e-6);
        }
        const Eigen::Quaterniond Q(data.R_WB(b));
        const Eigen::Vector4d page(poses[7 * slot + 3].number, poses[7 * slot + 4].number,
                                   poses[7 * slot + 5].number, poses[7 * slot + 6].number);
        EXPECT_NEAR(std::abs(page.dot(Q.coeffs())), 1.0, 1e-5);
      }
    }
  }
}

TEST_F(HtmlAnimationTest, ContactForcesOnlyWithContact) {
  HtmlAnimationOptions options;
  options.max_frame_rate = 1000.0;
  options.contact = ContactOptions{};
  const std::vector<AnimationFrame> frames = test::VizFrames(model_, 100.0, false);
  const Json scene = test::SceneOfPage(MakeHtmlAnimation(model_, frames, options));
  const Json& contacts = scene["contacts"];
  // Ball high above the ground: nothing drawn.
  for (std::size_t k = 0; k <= 80; ++k) EXPECT_EQ(contacts[k].size(), 0u) << k;
  // Resting with 5 mm of penetration and sliding along +x: one contact, the ground pushing up
  // on the ball, friction against the motion.
  for (std::size_t k = 110; k <= 200; k += 30) {
    ASSERT_EQ(contacts[k].size(), 10u) << k;
    const Json& c = contacts[k];
    EXPECT_NEAR(c[2].number, -0.0025, 1e-3);  // midpoint of the witnesses
    EXPECT_GT(c[5].number, 5.0);              // normal force up, N
    EXPECT_LT(c[6].number, 0.0);              // friction along -x
    EXPECT_NEAR(c[9].number, -0.005, 1e-6);   // phi
  }
  // Just before landing: force at a distance (phi > 0), still drawn.
  bool at_distance = false;
  for (std::size_t k = 90; k < 100; ++k) {
    if (contacts[k].size() == 10u && contacts[k][9].number > 0.0) at_distance = true;
  }
  EXPECT_TRUE(at_distance);
  EXPECT_GT(scene["force_scale"].number, 0.0);

  // Without a contact model: no forces at all.
  const Json none = test::SceneOfPage(MakeHtmlAnimation(model_, frames, HtmlAnimationOptions{}));
  EXPECT_FALSE(none["has_contact_model"].boolean);
  for (const Json& c : none["contacts"].array) EXPECT_EQ(c.size(), 0u);
}

TEST_F(HtmlAnimationTest, ClosedLoopLogGivesTheGhost) {
  mpc::ClosedLoopLog log;
  const std::vector<AnimationFrame> source = test::VizFrames(model_, 10.0, true);
  for (const AnimationFrame& f : source) {
    log.t.push_back(f.t);
    log.q.push_back(f.q);
    log.v.push_back(f.v);
    log.q_plan.push_back(f.q_ghost);
  }
  const std::vector<AnimationFrame> frames = MakeAnimationFrames(log);
  ASSERT_EQ(frames.size(), source.size());
  EXPECT_EQ(frames[5].q_ghost, source[5].q_ghost);
  log.q_plan.clear();
  EXPECT_EQ(MakeAnimationFrames(log)[5].q_ghost.size(), 0);
  log.q.pop_back();
  EXPECT_THROW(MakeAnimationFrames(log), InvalidArgument);
}

TEST_F(HtmlAnimationTest, FramesFromATrajectory) {
  std::vector<Eigen::VectorXd> q(3, model_.NeutralConfiguration());
  std::vector<Eigen::VectorXd> v(2, Eigen::VectorXd::Zero(model_.nv()));
  const std::vector<AnimationFrame> frames = MakeAnimationFrames(q, v, 0.1, 1.0);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_DOUBLE_EQ(frames[2].t, 1.2);
  EXPECT_EQ(frames[2].v.size(), model_.nv());
  EXPECT_THAT([&] { MakeAnimationFrames(q, v, 0.0); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("time_step")));
  v.resize(1);
  EXPECT_THAT([&] { MakeAnimationFrames(q, v, 0.1); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("MakeAnimationFrames: v")));
}

// Each bad input names the argument; nothing is written (an existing file stays as it was).
TEST_F(HtmlAnimationTest, BadInputIsAClearErrorAndWritesNothing) {
  const fs::path path = dir_ / "page.html";
  std::ofstream(path) << "previous";
  const auto expect_error = [&](std::vector<AnimationFrame> frames, const std::string& what) {
    EXPECT_THAT([&] { WriteHtmlAnimation(model_, frames, HtmlAnimationOptions{}, path); },
                ::testing::ThrowsMessage<InvalidArgument>(HasSubstr(what)));
    EXPECT_EQ(Read(path), "previous");
    EXPECT_EQ(Files().size(), 1u);
  };
  const std::vector<AnimationFrame> good = test::VizFrames(model_, 10.0, true);
  expect_error({}, "WriteHtmlAnimation: frames is empty");
  std::vector<AnimationFrame> bad = good;
  bad[3].q.resize(model_.nq() - 1);
  expect_error(bad, "frames[3].q is of size 8; expected size 9");
  bad = good;
  bad[4].q(5) = std::nan("");
  expect_error(bad, "frames[4].q(5) is nan");
  bad = good;
  bad[2].v(0) = INFINITY;
  expect_error(bad, "frames[2].v(0) is inf");
  bad = good;
  bad[1].v.resize(3);
  expect_error(bad, "frames[1].v is of size 3");
  bad = good;
  bad[6].q_ghost.resize(2);
  expect_error(bad, "frames[6].q_ghost is of size 2");
  bad = good;
  bad[7].q.segment<4>(0).setZero();
  expect_error(bad, "quaternion of joint 'ball_free'");
  bad = good;
  bad[9].t = 0.1;
  expect_error(bad, "frames[9].t is 0.1");
  bad = good;
  bad[0].t = std::nan("");
  expect_error(bad, "frames[0].t is nan");

  HtmlAnimationOptions options;
  options.max_frame_rate = 0.0;
  EXPECT_THAT([&] { WriteHtmlAnimation(model_, good, options, path); },
              ::testing::ThrowsMessage<InvalidArgument>(HasSubstr("options.max_frame_rate")));
  EXPECT_EQ(Read(path), "previous");
}

TEST_F(HtmlAnimationTest, UnwritablePathIsAFileErrorAndLeavesNothing) {
  const std::vector<AnimationFrame> frames = test::VizFrames(model_, 10.0, false);
  const fs::path missing = dir_ / "no_such_folder" / "page.html";
  EXPECT_THAT([&] { WriteHtmlAnimation(model_, frames, {}, missing.string()); },
              ::testing::ThrowsMessage<FileError>(HasSubstr(missing.string())));
  // A folder where the page should go: the rename fails, the temporary file is removed.
  fs::create_directories(dir_ / "a_folder");
  const fs::path folder = dir_ / "a_folder";
  EXPECT_THROW(WriteHtmlAnimation(model_, frames, {}, folder.string()), FileError);
  EXPECT_EQ(Files(), std::vector<std::string>{"a_folder"});
  EXPECT_TRUE(fs::is_empty(folder));
}

TEST_F(HtmlAnimationTest, WritesAtomically) {
  const fs::path path = dir_ / "page.html";
  std::ofstream(path) << "previous";
  const std::vector<AnimationFrame> frames = test::VizFrames(model_, 10.0, false);
  WriteHtmlAnimation(model_, frames, {}, path.string());
  EXPECT_EQ(Files(), std::vector<std::string>{"page.html"});
  const std::string page = Read(path);
  EXPECT_EQ(page, MakeHtmlAnimation(model_, frames, {}));
  EXPECT_THAT(page, HasSubstr("</html>"));
}

TEST_F(HtmlAnimationTest, MissingThreeJsIsAFileError) {
  HtmlAnimationOptions options;
  options.three_js_dir = (dir_ / "nowhere").string();
  const fs::path path = dir_ / "page.html";
  EXPECT_THAT(
      [&] { WriteHtmlAnimation(model_, test::VizFrames(model_, 10.0, false), options, path); },
      ::testing::ThrowsMessage<FileError>(HasSubstr("nowhere/three.min.js")));
  EXPECT_TRUE(Files().empty());
}

}  // namespace
}  // namespace idto
