#pragma once
/// \file
/// The solid an evaluation measures against: the one a sphere set's file says it was baked
/// from (the "stats" keys bake_mesh writes: "solid", "robust_resolution",
/// "robust_thickness"), or the one the caller names.

#include <string>

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

/// \p mesh itself for kWinding, its robust solid's boundary for kRobust (errors:
/// make_robust_solid, naming \p name).
TriangleMesh solid_mesh(const TriangleMesh& mesh, const SolidChoice& choice,
                        const std::string& name);

}  // namespace medspheres
