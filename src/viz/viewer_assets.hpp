#pragma once

// Internal to the viewer: the page template and its script, embedded at build time from
// src/viz/viewer.html and src/viz/viewer.js (cmake/IdtoViewerAssets.cmake).

namespace idto::viz_internal {

/// The page (HTML and CSS) with the markers /*@IDTO_THREE_JS@*/, /*@IDTO_ORBIT_CONTROLS_JS@*/,
/// /*@IDTO_VIEWER_JS@*/, /*@IDTO_SCENE_JSON@*/ and @IDTO_TITLE@.
extern const char kViewerHtml[];
/// The viewer script (reads the scene JSON, builds the three.js scene, drives the controls).
extern const char kViewerJs[];

}  // namespace idto::viz_internal
