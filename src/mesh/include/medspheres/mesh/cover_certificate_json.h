#pragma once
/// \file
/// The certificate of surface coverage (cover_certificate.h) as JSON: the one writer of its
/// keys, for `eval`'s "surface_certificate" (of a mesh's set and of every robot link's) and
/// for a robot file's "outer_certificate" (which adds what it knows of the link's sets).

#include <string>

#include "medspheres/mesh/cover_certificate.h"

namespace medspheres {

/// The JSON object text (one line) of \p certificate: "certified", "triangles",
/// "uncertified_triangles", "proven_uncovered_triangles", "pieces_tested", "max_depth"; when
/// not certified also "worst_uncovered_distance", "worst_uncovered_point" ([x, y, z], the
/// mesh's frame) and "worst_uncovered_bound" (the mesh's units). Doubles round-trip exactly.
std::string cover_certificate_json(const CoverCertificate& certificate);

}  // namespace medspheres
