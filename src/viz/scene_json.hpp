#pragma once

// Internal to the viewer: the page's scene data (JSON) from a model and its frames.

#include <string>
#include <vector>

#include "idto/viz/html_animation.hpp"

namespace idto::viz_internal {

/// Indices of the frames displayed: at most max_frame_rate per simulated second, the first and
/// the last always kept.
std::vector<int> SelectFrames(const std::vector<AnimationFrame>& frames, double max_frame_rate);

/// The scene as JSON (the page's data block; see viewer.js for the layout). `frames` are
/// checked by the caller.
std::string MakeSceneJson(const Model& model, const std::vector<AnimationFrame>& frames,
                          const std::vector<int>& selected, const HtmlAnimationOptions& options);

/// JSON string literal of `text`, with '<', '>' and '&' escaped so that it is safe inside a
/// <script> element.
std::string JsonQuote(const std::string& text);

}  // namespace idto::viz_internal
