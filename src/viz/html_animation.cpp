#include "idto/viz/html_animation.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "idto/core/errors.hpp"
#include "scene_json.hpp"
#include "viewer_assets.hpp"

namespace idto {
namespace {

constexpr const char* kWhere = "WriteHtmlAnimation";

std::string Indexed(const char* name, std::size_t k, const char* member) {
  return std::string(name) + "[" + std::to_string(k) + "]." + member;
}

// Throws InvalidArgument unless every frame has the model's sizes, finite entries, non-zero
// quaternions and times in non-decreasing order.
void CheckFrames(const Model& model, const std::vector<AnimationFrame>& frames) {
  if (frames.empty()) ThrowInvalidArgument(kWhere, "frames", "empty", "at least one frame");
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const AnimationFrame& f = frames[k];
    CheckFinite(kWhere, Indexed("frames", k, "t"), f.t);
    if (k > 0 && f.t < frames[k - 1].t) {
      ThrowInvalidArgument(kWhere, Indexed("frames", k, "t"), FormatValue(f.t),
                           "at least frames[" + std::to_string(k - 1) +
                               "].t = " + FormatValue(frames[k - 1].t) + " (times in order)");
    }
    CheckSize(kWhere, Indexed("frames", k, "q"), f.q.size(), model.nq(), "the model's nq");
    CheckFinite(kWhere, Indexed("frames", k, "q"), f.q);
    if (f.v.size() != 0) {
      CheckSize(kWhere, Indexed("frames", k, "v"), f.v.size(), model.nv(), "the model's nv");
      CheckFinite(kWhere, Indexed("frames", k, "v"), f.v);
    }
    if (f.q_ghost.size() != 0) {
      CheckSize(kWhere, Indexed("frames", k, "q_ghost"), f.q_ghost.size(), model.nq(),
                "the model's nq, or 0 for no ghost");
      CheckFinite(kWhere, Indexed("frames", k, "q_ghost"), f.q_ghost);
    }
    const auto check_quaternions = [&](const Eigen::VectorXd& q, const char* member) {
      for (JointIndex j : model.floating_joints()) {
        const int i = model.position_start(j);
        if (q.segment<4>(i).norm() < 1e-12) {
          ThrowInvalidArgument(kWhere,
                               Indexed("frames", k, member) + ".segment(" + std::to_string(i) +
                                   ", 4) (quaternion of joint '" + model.joint_name(j) + "')",
                               "zero", "a non-zero quaternion");
        }
      }
    };
    check_quaternions(f.q, "q");
    if (f.q_ghost.size() != 0) check_quaternions(f.q_ghost, "q_ghost");
  }
}

void CheckOptions(const HtmlAnimationOptions& options) {
  CheckPositive(kWhere, "options.max_frame_rate", options.max_frame_rate);
  CheckNonNegative(kWhere, "options.force_scale", options.force_scale);
  CheckFinite(kWhere, "options.min_force", options.min_force);
  CheckPositive(kWhere, "options.playback_speed", options.playback_speed);
  if (options.contact) options.contact->parameters.Validate("WriteHtmlAnimation: options.contact");
}

std::string ThreeJsDir(const HtmlAnimationOptions& options) {
  if (!options.three_js_dir.empty()) return options.three_js_dir;
  const char* env = std::getenv("IDTO_THREE_JS_DIR");
  if (env != nullptr && env[0] != '\0') return env;
  return "/usr/share/javascript/three";
}

std::string ReadScript(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (in) text << in.rdbuf();
  if (!in || text.str().empty()) {
    ThrowFileError(path, "",
                   "cannot read three.js (install Debian's libjs-three, e.g. with "
                   "scripts/setup-deps, or set IDTO_THREE_JS_DIR or "
                   "HtmlAnimationOptions::three_js_dir)");
  }
  // Keep the script inside its <script> element.
  std::string s = text.str();
  for (std::size_t at = s.find("</"); at != std::string::npos; at = s.find("</", at + 3)) {
    s.replace(at, 2, "<\\/");
  }
  return s;
}

std::string HtmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// Replaces the first occurrence of `marker` at or after *at in *page by `text`; *at moves past
// the inserted text (so that inserted text is never searched for later markers).
void Fill(const std::string& marker, const std::string& text, std::string* page, std::size_t* at) {
  const std::size_t found = page->find(marker, *at);
  if (found == std::string::npos) return;
  page->replace(found, marker.size(), text);
  *at = found + text.size();
}

}  // namespace

std::vector<AnimationFrame> MakeAnimationFrames(const std::vector<Eigen::VectorXd>& q,
                                                const std::vector<Eigen::VectorXd>& v,
                                                double time_step, double start_time) {
  static constexpr const char* kFramesWhere = "MakeAnimationFrames";
  CheckPositive(kFramesWhere, "time_step", time_step);
  CheckFinite(kFramesWhere, "start_time", start_time);
  if (q.empty()) ThrowInvalidArgument(kFramesWhere, "q", "empty", "at least one configuration");
  if (!v.empty() && v.size() != q.size() && v.size() + 1 != q.size()) {
    ThrowInvalidArgument(kFramesWhere, "v", "of length " + std::to_string(v.size()),
                         "length " + std::to_string(q.size()) + " or " +
                             std::to_string(q.size() - 1) + " (that of q, or one fewer), or 0");
  }
  std::vector<AnimationFrame> frames(q.size());
  for (std::size_t k = 0; k < q.size(); ++k) {
    frames[k].t = start_time + static_cast<double>(k) * time_step;
    frames[k].q = q[k];
    if (!v.empty()) frames[k].v = v[std::min(k, v.size() - 1)];
  }
  return frames;
}

std::vector<AnimationFrame> MakeAnimationFrames(const mpc::ClosedLoopLog& log) {
  static constexpr const char* kFramesWhere = "MakeAnimationFrames";
  if (log.q.size() != log.t.size() || (!log.v.empty() && log.v.size() != log.t.size())) {
    ThrowInvalidArgument(
        kFramesWhere, "log.q / log.v",
        "of lengths " + std::to_string(log.q.size()) + " / " + std::to_string(log.v.size()),
        "the length of log.t, " + std::to_string(log.t.size()));
  }
  const bool ghost = log.q_plan.size() == log.t.size();
  std::vector<AnimationFrame> frames(log.t.size());
  for (std::size_t k = 0; k < log.t.size(); ++k) {
    frames[k].t = log.t[k];
    frames[k].q = log.q[k];
    if (!log.v.empty()) frames[k].v = log.v[k];
    if (ghost) frames[k].q_ghost = log.q_plan[k];
  }
  return frames;
}

std::string MakeHtmlAnimation(const Model& model, const std::vector<AnimationFrame>& frames,
                              const HtmlAnimationOptions& options) {
  CheckFrames(model, frames);
  CheckOptions(options);
  const std::string dir = ThreeJsDir(options);
  const std::string three = ReadScript(dir + "/three.min.js");
  const std::string orbit = ReadScript(dir + "/examples/js/controls/OrbitControls.js");
  const std::vector<int> selected = viz_internal::SelectFrames(frames, options.max_frame_rate);
  std::string scene = viz_internal::MakeSceneJson(model, frames, selected, options);

  // The markers in the order they appear in the template.
  std::string page = viz_internal::kViewerHtml;
  std::size_t at = 0;
  const std::string title = HtmlEscape(options.title);
  Fill("@IDTO_TITLE@", title, &page, &at);
  Fill("@IDTO_TITLE@", title, &page, &at);
  Fill("/*@IDTO_THREE_JS@*/", three, &page, &at);
  Fill("/*@IDTO_ORBIT_CONTROLS_JS@*/", orbit, &page, &at);
  Fill("/*@IDTO_SCENE_JSON@*/", scene, &page, &at);
  Fill("/*@IDTO_VIEWER_JS@*/", viz_internal::kViewerJs, &page, &at);
  return page;
}

void CheckHtmlAnimationPath(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) ThrowInvalidArgument(kWhere, "path", "empty", "a file name");
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    ThrowFileError(path, "", "cannot write the viewer page: no folder " + folder.string());
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    ThrowFileError(path, "",
                   "cannot write the viewer page: folder " + folder.string() + " is not writable");
  }
  if (fs::is_directory(target, ec)) {
    ThrowFileError(path, "", "cannot write the viewer page: it is a folder");
  }
}

void WriteHtmlAnimation(const Model& model, const std::vector<AnimationFrame>& frames,
                        const HtmlAnimationOptions& options, const std::string& path) {
  if (path.empty()) ThrowInvalidArgument(kWhere, "path", "empty", "a file name");
  const std::string page = MakeHtmlAnimation(model, frames, options);

  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string temp = (folder / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
  const int fd = mkstemp(temp.data());
  if (fd < 0) {
    ThrowFileError(path, "",
                   std::string("WriteHtmlAnimation: cannot write path: ") + std::strerror(errno));
  }
  std::size_t written = 0;
  while (written < page.size()) {
    const ssize_t n = ::write(fd, page.data() + written, page.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    written += static_cast<std::size_t>(n);
  }
  const int write_errno = errno;
  const bool ok = written == page.size() && ::fchmod(fd, 0644) == 0;
  if (::close(fd) != 0 || !ok) {
    std::remove(temp.c_str());
    ThrowFileError(path, "",
                   std::string("WriteHtmlAnimation: cannot write path: ") +
                       std::strerror(ok ? errno : write_errno));
  }
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) {
    std::remove(temp.c_str());
    ThrowFileError(path, "", "WriteHtmlAnimation: cannot write path: " + ec.message());
  }
}

}  // namespace idto
