#pragma once
/// \file
/// The solid an evaluation measures against: the one a sphere set's file says it was baked
/// from (the "stats" keys bake_mesh writes: "solid", "robust_resolution",
/// "robust_thickness"), or the one the caller names.

#include <optional>
#include <string>

#include "medspheres/mesh/length.h"
#include "medspheres/mesh/robust_solid.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

struct SolidChoice {
  SolidKind kind = SolidKind::kWinding;  ///< kWinding or kRobust
  RobustSolidOptions robust;             ///< for kRobust
};

/// What \p metadata_json (SphereSet::metadata_json) records; kWinding when it names no
/// solid or is not a JSON object (files of other tools).
SolidChoice recorded_solid(const std::string& metadata_json);

/// The solid \p requested names for evaluating spheres of \p metadata_json against
/// \p mesh: kAuto takes recorded_solid(); kRobust keeps \p robust's options, unless
/// \p robust_explicit is false and the file records robust ones.
SolidChoice choose_solid(SolidKind requested, const RobustSolidOptions& robust,
                         bool robust_explicit, const std::string& metadata_json);

/// The solid a caller asks `eval` to measure against (the CLI's and Python's solid options,
/// parsed by medspheres/options/bake_flags.h).
struct SolidRequest {
  SolidKind kind = SolidKind::kAuto;       ///< kAuto: the one the file records
  RobustSolidOptions robust;               ///< of the robust solid, when it is measured
  std::optional<Length> robust_thickness;  ///< overrides robust.thickness (>= 0)
};

/// Checks \p request as eval_solid does, before any work, whether or not the robust solid
/// is then made.
/// \throws InputError (kOutOfRange, field "robust_resolution") for a resolution that is
///   neither 0 nor in [8, 1024]; (field "robust_thickness") for a thickness that is not
///   finite or is negative.
void check_solid_request(const SolidRequest& request);

/// The solid `eval` measures spheres of \p metadata_json against, as \p request names it
/// ("auto": the recorded one): choose_solid, where the robust options count as explicit
/// when a thickness, or a resolution or thickness other than the default, is given; a
/// thickness in L is taken of \p longest (L of the mesh, its units). Python's evaluate and
/// the CLI's eval both choose here.
/// \throws InputError as check_solid_request.
SolidChoice eval_solid(const SolidRequest& request, double longest,
                       const std::string& metadata_json);

/// \p mesh itself for kWinding, its robust solid's boundary for kRobust (errors:
/// make_robust_solid, naming \p name).
TriangleMesh solid_mesh(const TriangleMesh& mesh, const SolidChoice& choice,
                        const std::string& name);

}  // namespace medspheres
