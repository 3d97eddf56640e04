#pragma once
/// \file
/// The provenance a baked sphere-set file carries (the "source", "generator" and
/// "stats" keys of the format in io.h), so that every tool that bakes writes the same.

#include <map>
#include <string>

#include "medspheres/bake.h"
#include "medspheres/mesh_report.h"

namespace medspheres {

/// Where a sphere set came from.
struct MeshProvenance {
  std::string mesh;    ///< file name as given by the user
  std::string sha256;  ///< of the file's bytes
  MeshReport report;   ///< of the mesh as baked
};

/// The JSON object text for SphereSet::metadata_json:
/// - "source": mesh, sha256, triangles, closed, bbox_min, bbox_max;
/// - "generator": method "medial", version, params (resolution, object_angle,
///   medial_tolerance, and `mode` with its target: "resolution", "max_spheres" or
///   "target_error");
/// - "stats": count, resolution, bake_seconds, min_radius, max_radius, the query
///   counts, and every entry of \p extra_stats (numbers, such as nerr) and
///   \p extra_strings (such as nerr_kind).
std::string bake_metadata_json(const MeshProvenance& source, const BakeOptions& options,
                               const BakeStats& stats, const std::string& mode, double mode_target,
                               const std::map<std::string, double>& extra_stats = {},
                               const std::map<std::string, std::string>& extra_strings = {});

}  // namespace medspheres
