#pragma once
// The sets of a thin-shelled link baked on its filled solid (filled_solid.h): its inner set
// (`robot --fill`) and its covering set (`robot --fill-covers`).

#include <optional>
#include <string>

#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// shell_fraction of \p mesh (filled_solid.h) when \p request may be baked on a filled solid
/// (request.solid is kAuto), NaN otherwise (then nothing is filled).
double fill_fraction(const TriangleMesh& mesh, const MeshReport& report, const BakeRequest& request,
                     const std::string& name);

/// The bake of \p request on the filled solid of \p mesh, when request.solid is kAuto, the
/// request makes an inner (medial) set, and the mesh is a thin shell (is_thin_shell of
/// \p fraction, fill_fraction of the mesh: the volume of a mesh that is not closed and
/// outward wound is its signed volume about its box's centre, indicative: exact once its
/// gaps close); nothing otherwise. The set is recorded as a bake of the robust solid at the
/// filled solid's resolution and thickness (so `eval` measures it against the filled solid)
/// with "inner_solid": "filled" and "shell_fraction" (the volume over the filled solid's at
/// kFillProbeResolution, the test's figure).
std::optional<BakeOutcome> bake_filled_inner(const TriangleMesh& mesh, const MeshReport& report,
                                             const BakeRequest& request, const std::string& name,
                                             const std::string& sha256, double fraction);

/// The covering set of \p request (a BakeMethod::kCover request with solid kAuto) baked on
/// the filled solid of \p mesh at \p resolution (make_filled_solid), when the mesh is a thin
/// shell (is_thin_shell of \p fraction); nothing otherwise.
///
/// Why: a covering ball on thin material sticks out on both sides of it by about its
/// radius; on the filled solid the balls may sit in the cavity and stick out of the outside
/// only at the seams between them and by the filled solid's own excess over the link
/// (less than (1 + sqrt(3)/2 + sqrt(3)) L / resolution over its convex parts, robust_solid.h),
/// while across the cavity's opening they reach as far as the closing does.
///
/// Contract: the balls cover the filled solid's boundary (certified) and the mesh's own
/// triangles (certified on them by cover_input.h, balls grown where needed; the robust
/// solid contains the mesh's surface, so growth is seldom needed): the set covers the
/// link's real surface exactly as every covering set does. The returned cover's
/// certificate is that of the mesh's own triangles; its stats (protrusion, excess volume)
/// are measured against the filled solid. The record says "cover_solid": "filled" and
/// "shell_fraction".
std::optional<BakeOutcome> bake_filled_cover(const TriangleMesh& mesh, const MeshReport& report,
                                             const BakeRequest& request, const std::string& name,
                                             const std::string& sha256, double fraction,
                                             int resolution);

}  // namespace medspheres
