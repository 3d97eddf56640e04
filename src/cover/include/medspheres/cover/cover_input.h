#pragma once
/// \file
/// A covering set baked on a solid built around an input surface (the robust solid of a
/// mesh, robust_solid.h) is certified on that solid's boundary; the input's own triangles,
/// which lie inside the solid, are certified here too.
///
/// Method: certify_cover on the input's triangles; every piece it cannot certify is held by
/// growing the ball that needs the least growth to hold the piece's corners (plus a slack
/// of 1e-9 L and rounding), and the certificate runs again on the triangles still
/// uncertified, for at most 64 rounds; the certificate kept is of every input triangle,
/// run once more when a ball grew. Balls only grow, so the solid's certificate stays true; the
/// cover's union volume, excess volume and protrusion are measured again when a ball grew. A set
/// that still fails is reported uncertified, never covered. Frames and units: those of the meshes,
/// which must agree.

#include <cstddef>
#include <vector>

#include "medspheres/cover/cover.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

struct InputCoverCheck {
  CoverCertificate certificate;  ///< of the input's triangles, for the final balls
  std::size_t repaired = 0;      ///< balls grown, counted per growth
  int rounds = 0;                ///< certify rounds run (the final full one not counted)
};

/// Certifies that \p cover's balls contain every triangle of \p input, growing balls when
/// they do not (file comment); \p solid is the evaluator of the solid the cover was baked
/// on, against which its stats are measured again.
/// \throws std::invalid_argument as certify_cover does.
InputCoverCheck certify_input_cover(const TriangleMesh& input, const FitEvaluator& solid,
                                    CoverResult& cover, const CoverOptions& options);

}  // namespace medspheres
