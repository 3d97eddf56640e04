#pragma once
/// \file
/// The bake pipeline every tool calls (the CLI's bake, robot baking, batch baking):
/// validate the request, load the mesh, bake or search the resolution, dilate, measure,
/// and record the provenance. Nothing is printed and nothing is written.
///
/// Errors: InputError, named in the library's terms (fields of BakeRequest and
/// BakeOptions such as "max_spheres"; the mesh by the name the caller gives it):
/// kOutOfRange and kConflict for the request (before any mesh is read), the loader's
/// kinds for the file, kNoInterior for a mesh without volume, kUnsupported for an error
/// target on a mesh without a volume, kUnreachable for a budget or target no resolution
/// reaches and for a bake that finds no sphere.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/bake/bake.h"
#include "medspheres/bake/bake_metadata.h"
#include "medspheres/cover/cover.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/length.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/mesh/robust_solid.h"
#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// How the spheres are made: kMedial, the inner medial set S_D (to a budget: the best
/// max_spheres inner spheres, inner_budget.h), optionally dilated to S+; kCover, at most
/// max_spheres balls whose union contains the surface, certified (cover.h), or the balls of
/// cover_start made into such a cover (tighten_cover).
enum class BakeMethod { kMedial, kCover };

struct BakeRequest {
  BakeMethod method = BakeMethod::kMedial;
  BakeOptions medial;  ///< resolution, object angle, tolerance, threads, progress
  std::optional<std::size_t> max_spheres;  ///< at most K spheres (kCover: the budget)
  /// kCover only, instead of max_spheres: the caller's balls (in the mesh's frame), which
  /// tighten_cover (cover.h) makes into a certified cover of at most as many balls.
  std::vector<Sphere> cover_start;
  /// kCover with max_spheres only: where the cover should stick out less (CoverOptions::
  /// weights, protrusion_weights.h), in the mesh's frame.
  ProtrusionWeights cover_weights;
  /// kCover with max_spheres only: the search's trade and effort (CoverSearch: allowance,
  /// restarts, balancing rounds; out of range: kOutOfRange naming the field).
  CoverSearch cover_search;
  std::optional<double> target_error;  ///< nerr at most E, in (0, 1) (closed meshes only)
  bool dilate = false;                 ///< write S+ (implied by cover)
  /// Dilation lengths (DilateOptions): vertex_tolerance > 0, max_protrusion >= 0, cover > 0.
  std::optional<Length> vertex_tolerance, max_protrusion, cover;
  std::uint64_t seed = 1;  ///< of the dilation's random points
  bool measure = true;     ///< compute the volume, nerr and protrusion of the output
  /// Record the bake's wall-clock times in the file's stats; false makes the file a pure
  /// function of the mesh, its name and the request (batch bakes, caches).
  bool record_seconds = true;
  /// The solid baked (robust_solid.h). kAuto: the winding-number solid of a closed,
  /// outward mesh; for any other mesh the winding-number solid unless its bake finds no
  /// well-defined interior (kNoInterior), then the robust solid, with a warning.
  SolidKind solid = SolidKind::kAuto;
  /// Of the robust solid, when it is used. A bake escalates its thickness by default (walls
  /// that enclose nothing are thickened, robust_solid.h); a robust_thickness is kept as given.
  RobustSolidOptions robust{0, 0.0, true};
  std::optional<Length> robust_thickness;  ///< overrides robust.thickness (>= 0)
};

struct BakeOutcome {
  SphereSet spheres;  ///< what is to be written; metadata_json holds provenance and stats
  BakeRecord record;  ///< what metadata_json was made from
  BakeResult medial;  ///< the medial bake (its stats, the search)
  /// With measure, on a mesh with a volume: of the output, and of S_D when dilated.
  std::optional<VolumeError> volume, internal;
  std::size_t self_intersecting_pairs = 0;  ///< of the mesh's triangles
  std::optional<CoverResult> cover;         ///< kCover: the cover, its certificate and stats
  /// The solid baked, kWinding or kRobust (recorded as stats "solid" in the file); every
  /// measure and guarantee of the outcome is of that solid.
  SolidKind solid = SolidKind::kWinding;
  /// kRobust: the robust solid's wall thickness t (recorded as stats "robust_thickness"),
  /// and whether it was escalated beyond the one requested because the walls enclosed
  /// nothing there (recorded as "robust_thickness_requested", with a warning).
  double robust_thickness = 0.0;
  bool robust_thickness_escalated = false;
  /// One sentence each: a fallback to the robust solid, an escalated wall thickness.
  std::vector<std::string> warnings;
};

/// Bakes the solid of \p mesh that request.solid chooses (with its \p report, as
/// analyze_mesh or load_mesh gives it); \p name names it in errors and provenance,
/// \p sha256 is recorded as given (may be empty). The source recorded is \p mesh, also
/// when the robust solid is baked.
BakeOutcome bake_mesh(const TriangleMesh& mesh, const MeshReport& report,
                      const BakeRequest& request, const std::string& name,
                      const std::string& sha256 = "");

/// As bake_mesh above, on a mesh whose FitEvaluator \p fit is built already (from the same
/// mesh as \p report describes): requests on one mesh (an inner and a covering set) then
/// share its query, volume and self-intersections. A robust solid is built from the
/// evaluator's mesh.
BakeOutcome bake_mesh(const FitEvaluator& fit, const MeshReport& report, const BakeRequest& request,
                      const std::string& name, const std::string& sha256 = "");

/// Validates the request, loads \p path (mesh_io.h) and bakes it; the loader's and the
/// bake's warnings go to \p warnings (when given), one sentence each.
BakeOutcome bake_file(const std::string& path, const BakeRequest& request,
                      std::vector<std::string>* warnings = nullptr);

/// The request's first problem that needs no mesh (every option's range, conflicts).
/// \throws InputError of kind kOutOfRange or kConflict.
void validate(const BakeRequest& request);
/// The check of a request's cover_search alone (validate runs it): an out-of-range field
/// throws InputError naming it.
void validate(const CoverSearch& search);

}  // namespace medspheres
