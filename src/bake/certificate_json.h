// The certificate of surface coverage (cover_certificate.h) as JSON, shared by the
// evaluations of a mesh's set and of a robot's sets (not installed).
#pragma once

#include <nlohmann/json.hpp>

#include "medspheres/mesh/cover_certificate.h"

namespace medspheres {

/// "certified", "triangles", "uncertified_triangles", "proven_uncovered_triangles",
/// "pieces_tested", "max_depth"; when not certified also the worst uncovered distance,
/// point and bound.
nlohmann::ordered_json certificate_json(const CoverCertificate& c);

}  // namespace medspheres
