#pragma once
// How the viewer page carries a scene part's geometry (web/viewer.js decodes it): typed
// arrays as base64 of their little-endian bytes, vertex positions and the corners of
// uncovered pieces quantized to 16 bits per coordinate over the part's mesh box, triangles
// indexed with 16-bit indices when the part has at most 65536 vertices, whole uncovered
// triangles as one bit each. The keys of a part's object:
//   name, triangle_count, vertex_count;
//   box: [x0, y0, z0, x1, y1, z1], the mesh's box (doubles); coordinate k of a point is
//     box[k] + q (box[k + 3] - box[k]) / 65535 for its 16-bit q, within half that step
//     (kQuantSteps) of the point;
//   positions: uint16 x 3 per vertex; triangles: uint16 or uint32 (index_bytes 2 or 4) x 3;
//   inner, outer: float32 x 4 per sphere (x, y, z, r);
//   uncovered_inner, uncovered_outer: {whole: one bit per triangle (bit t % 8 of byte
//     t / 8: triangle t is uncertified as a whole), pieces: uint16 x 9 per smaller piece
//     (its three corners, quantized)}.

#include <string>

#include <nlohmann/json.hpp>

#include "medspheres/render/scene.h"
#include "medspheres/render/view_html.h"

namespace medspheres::render::detail {

/// The steps of the quantization: 2^16 - 1 over the box's side.
inline constexpr double kQuantSteps = 65535.0;

/// RFC 4648 base64 of \p bytes.
std::string base64(const std::string& bytes);

/// The part's object (file comment); the uncovered pieces as certify_cover decides them
/// with options.cover_depth and options.threads.
nlohmann::json part_data(const ScenePart& part, const ViewOptions& options);

}  // namespace medspheres::render::detail
