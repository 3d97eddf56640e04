#include "medspheres/bake_metadata.h"

#include <nlohmann/json.hpp>

#include "medspheres/version.h"

namespace medspheres {

std::string bake_metadata_json(const MeshProvenance& source, const BakeOptions& options,
                               const BakeStats& stats, const std::string& mode, double mode_target,
                               const std::map<std::string, double>& extra_stats,
                               const std::map<std::string, std::string>& extra_strings) {
  using Json = nlohmann::ordered_json;
  auto vec = [](const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); };
  Json meta;
  meta["source"] = {{"mesh", source.mesh},
                    {"sha256", source.sha256},
                    {"triangles", source.report.triangles},
                    {"closed", source.report.closed},
                    {"bbox_min", vec(source.report.bbox_min)},
                    {"bbox_max", vec(source.report.bbox_max)}};
  Json params = {{"resolution", stats.resolution},
                 {"object_angle", options.object_angle},
                 {"medial_tolerance", stats.medial_tolerance},
                 {"mode", mode}};
  if (mode != "resolution") params["target"] = mode_target;
  meta["generator"] = {
      {"method", "medial"}, {"version", MEDSPHERES_VERSION_STRING}, {"params", params}};
  Json st = {{"count", stats.spheres},
             {"resolution", stats.resolution},
             {"bake_seconds", stats.seconds},
             {"min_radius", stats.min_radius},
             {"max_radius", stats.max_radius},
             {"closest_point_queries", stats.closest_point_queries},
             {"winding_queries", stats.winding_queries}};
  for (const auto& [k, v] : extra_stats) st[k] = v;
  for (const auto& [k, v] : extra_strings) st[k] = v;
  meta["stats"] = st;
  return meta.dump();
}

}  // namespace medspheres
