#pragma once
/// \file
/// view_html(): one self-contained HTML page that shows a Scene in a browser with
/// three.js (inlined: the page needs no network and opens from disk). Orbit controls;
/// toggles for the mesh, the inner and the outer spheres and, for a robot, each link; the
/// sphere under the mouse with its index (in its link's set), centre and radius.
///
/// Uncovered surface is coloured as certify_cover decides it, per part against the part's
/// own spheres: the triangle pieces it does not certify as inside the union of the balls
/// (split at most `cover_depth` times) are drawn red, so every point outside red is
/// certainly covered. With the
/// outer set shown the colouring is the outer set's, else the inner set's.
///
/// The page reports itself in `document.body.dataset.status`: "ok: ..." once drawn,
/// "error: ..." when something failed (no WebGL, a script error).

#include <string>

#include "medspheres/render/scene.h"

namespace medspheres::render {

struct ViewOptions {
  std::string title = "medspheres";
  std::string warning;  ///< shown on the page when not empty (a mismatch warning)
  int cover_depth = 5;  ///< certify_cover's max_depth, 0 .. 10
  int threads = 0;      ///< for certify_cover (threads.h)
};

/// The page's text (UTF-8). \throws std::invalid_argument for cover_depth out of range
///   or a bad thread count; InputError as certify_cover for an invalid sphere.
std::string view_html(const Scene& scene, const ViewOptions& options = {});

}  // namespace medspheres::render
