#pragma once

/// @file
/// The viewer: a self-contained HTML page (three.js r111 inlined, scene data as JSON) that
/// animates a Model along a trajectory, with its collision geometry coloured per model, contact
/// forces evaluated by the ContactEngine at every displayed frame, an optional translucent
/// "ghost" configuration (e.g. the MPC plan in force), body frames, world axes, an orbit camera
/// with Z up, play/pause, a time slider, playback speed and a checkbox per overlay.
///
/// The viewer sits at the top of the stack: it reads models, trajectories and contact results;
/// nothing in idto includes it.
///
///   std::vector<idto::AnimationFrame> frames = idto::MakeAnimationFrames(q, v, dt);
///   idto::HtmlAnimationOptions options;
///   options.contact = problem.contact;  // draw contact forces
///   idto::WriteHtmlAnimation(model, frames, options, "plan.html");

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "idto/contact/contact_engine.hpp"
#include "idto/mpc/closed_loop.hpp"
#include "idto/multibody/model.hpp"

namespace idto {

/// One instant of an animation.
struct AnimationFrame {
  double t{0.0};            ///< time, s (frames in non-decreasing time order)
  Eigen::VectorXd q;        ///< configuration (nq)
  Eigen::VectorXd v;        ///< velocity (nv), or empty for zero (contact forces then have no
                            ///< dissipation or friction)
  Eigen::VectorXd q_ghost;  ///< configuration drawn as a translucent ghost (nq), or empty
};

/// Options of MakeHtmlAnimation / WriteHtmlAnimation.
struct HtmlAnimationOptions {
  /// Page title, shown in the page's corner.
  std::string title{"idto"};
  /// When set, contact is evaluated at every displayed frame (ContactEngine at q, v) and each
  /// contact's normal and friction forces are drawn as arrows. Unset: no forces.
  std::optional<ContactOptions> contact;
  /// Frames are subsampled to at most this many per simulated second (> 0), always keeping the
  /// first and the last: a 10 s run logged at 1 kHz becomes 601 displayed frames.
  double max_frame_rate{60.0};
  /// Arrow length per newton (m/N); 0 (default): the largest drawn force gets an arrow of a
  /// quarter of the scene's size.
  double force_scale{0.0};
  /// Contacts whose force is below this (N) are not drawn; negative (default): 1e-3 times the
  /// model's weight (total mass times |gravity|; 1e-3 N when that is zero).
  double min_force{-1.0};
  /// Initial playback speed (1 = real time); the page offers 0.1x to 4x.
  double playback_speed{1.0};
  /// Initial state of the overlays' checkboxes.
  bool show_forces{true};
  bool show_ghost{true};
  bool show_frames{false};
  /// Folder of Debian's libjs-three (three.min.js and examples/js/controls/OrbitControls.js),
  /// read when the page is made. Empty: $IDTO_THREE_JS_DIR, else /usr/share/javascript/three.
  std::string three_js_dir;
};

/// Frames of a trajectory sampled every `time_step` seconds from `start_time`: q[k] (nq each)
/// and v[k] (nv each; v may be empty, or have one entry fewer than q, the last frame then
/// reusing the last velocity). Throws InvalidArgument naming the argument on size mismatches or
/// a non-positive time step; entries are checked by MakeHtmlAnimation.
std::vector<AnimationFrame> MakeAnimationFrames(const std::vector<Eigen::VectorXd>& q,
                                                const std::vector<Eigen::VectorXd>& v,
                                                double time_step, double start_time = 0.0);

/// Frames of a closed-loop run: the plant's logged q, v, with log.q_plan (the configuration the
/// plan in force asked for at each logged time) as the ghost when it was recorded.
std::vector<AnimationFrame> MakeAnimationFrames(const mpc::ClosedLoopLog& log);

/// The HTML page (one self-contained document). Throws InvalidArgument naming the argument
/// ("frames[k].q(i)", "options.max_frame_rate", ...) when frames is empty, out of time order,
/// of the wrong size or not finite, or when a quaternion of q is zero; FileError when three.js
/// cannot be read (naming the file).
std::string MakeHtmlAnimation(const Model& model, const std::vector<AnimationFrame>& frames,
                              const HtmlAnimationOptions& options);

/// Writes MakeHtmlAnimation's page to `path` atomically (a temporary file in the same folder,
/// then renamed over `path`): a failure leaves neither a partial page nor a temporary file, and
/// an existing file at `path` untouched. Throws as MakeHtmlAnimation (before anything is
/// written), and FileError naming `path` when it cannot be written.
void WriteHtmlAnimation(const Model& model, const std::vector<AnimationFrame>& frames,
                        const HtmlAnimationOptions& options, const std::string& path);

/// Throws FileError naming `path` unless its folder exists and is writable and `path` is not a
/// folder: a check before a long run whose page WriteHtmlAnimation will write. Creates nothing.
void CheckHtmlAnimationPath(const std::string& path);

}  // namespace idto
