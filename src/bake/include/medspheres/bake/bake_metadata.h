#pragma once
/// \file
/// The provenance a baked sphere-set file carries (the "source", "generator" and
/// "stats" keys of the format in io.h), so that every tool that bakes writes the same.

#include <map>
#include <optional>
#include <string>

#include "medspheres/bake/bake.h"
#include "medspheres/bake/dilate.h"
#include "medspheres/cover/cover.h"
#include "medspheres/mesh/mesh_report.h"

namespace medspheres {

/// Where a sphere set came from.
struct MeshProvenance {
  std::string mesh;    ///< file name as given by the user
  std::string sha256;  ///< of the file's bytes
  MeshReport report;   ///< of the mesh as baked
};

/// Everything a baked file records.
struct BakeRecord {
  MeshProvenance source;
  BakeOptions options;
  BakeStats stats;
  std::string mode = "resolution";                ///< "resolution", "max_spheres" or "target_error"
  double mode_target = 0.0;                       ///< the budget or the error target of the mode
  std::optional<DilateOptions> dilation_options;  ///< set when the spheres were dilated
  std::optional<DilateStats> dilation_stats;
  std::optional<CoverSearch> cover_search;           ///< set for a covering set baked to a budget
  std::map<std::string, double> extra_stats;         ///< numbers, such as nerr
  std::map<std::string, std::string> extra_strings;  ///< such as nerr_kind
  bool record_seconds = true;  ///< false: no wall-clock time is written (every "*seconds")
};

/// The JSON object text for SphereSet::metadata_json:
/// - "source": mesh, sha256, triangles, closed, bbox_min, bbox_max;
/// - "generator": method ("medial", or "medial+dilation"), version, params (resolution,
///   object_angle, medial_tolerance, mode and its target; "dilation" with the dilation
///   options when dilated);
/// - "stats": count, resolution, bake_seconds (BakeStats::total_seconds: for a
///   resolution search the whole search), min_radius, max_radius, the query counts,
///   for a search "final_bake_seconds" (the chosen resolution's bake) and "search"
///   ({"resolutions": [...], "spheres": [...]} in the order baked, plus "errors" for an
///   error target), "dilation" with the dilation statistics when dilated, and every extra
///   entry (a non-finite number is written as null). Without record_seconds, the three
///   times (bake_seconds, final_bake_seconds, the dilation's seconds) are left out.
std::string bake_metadata_json(const BakeRecord& record);

}  // namespace medspheres
