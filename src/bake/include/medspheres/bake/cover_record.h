#pragma once
/// \file
/// What a covering set's file records (the provenance of bake_metadata.h, with the cover's
/// statistics): the record of a cover (cover.h) and of the certificate of its input's own
/// triangles (cover_input.h), and their JSON.

#include <string>

#include "medspheres/bake/bake_metadata.h"
#include "medspheres/cover/cover.h"
#include "medspheres/cover/cover_input.h"

namespace medspheres {

/// The BakeRecord of a cover: mode "cover_budget" ("cover_tighten" for tighten_cover),
/// target the budget, its search (cover_budget only: CoverResult::search), and the cover's
/// statistics (certified 1/0, the certificate's counts,
/// union and excess volume, max protrusion, the worst uncovered distance when not
/// certified) in extra_stats.
BakeRecord cover_bake_record(const MeshProvenance& source, const CoverResult& result);

/// bake_metadata_json(record) with generator.method "cover", the medial parameters
/// replaced by the budget (and the search's protrusion_allowance, protrusion_restarts and
/// balance_rounds when recorded), and "certified" and "surface_covered" written as booleans;
/// "interior_certified" is false (only the surface is certified).
std::string cover_metadata_json(const BakeRecord& record);

/// Records \p check in \p record's extra_stats: input_certified (1 or 0),
/// input_certificate_triangles, input_uncertified_triangles, input_repaired, and
/// input_uncovered_max (the worst distance found) when not certified; cover_metadata_json
/// then writes input_certified as a boolean.
void record_input_cover(const InputCoverCheck& check, BakeRecord& record);

}  // namespace medspheres
