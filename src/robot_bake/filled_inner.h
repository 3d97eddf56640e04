#pragma once
// The inner set of a thin-shelled link, baked on its filled solid (filled_solid.h).

#include <optional>
#include <string>

#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// The bake of \p request on the filled solid of \p mesh, when request.solid is kAuto, the
/// request makes an inner (medial) set, and the mesh is a thin shell (is_thin_shell of its
/// volume and its filled solid's; the volume of a mesh that is not closed and outward wound
/// is its signed volume about its box's centre, indicative: exact once its gaps close);
/// nothing otherwise. The set is recorded as a bake of the robust solid at the filled solid's
/// resolution and thickness (so `eval` measures it against the filled solid) with
/// "inner_solid": "filled" and "shell_fraction" (the volume over the filled solid's at
/// kFillProbeResolution, the test's figure).
std::optional<BakeOutcome> bake_filled_inner(const TriangleMesh& mesh, const MeshReport& report,
                                             const BakeRequest& request, const std::string& name,
                                             const std::string& sha256);

}  // namespace medspheres
