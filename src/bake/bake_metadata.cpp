#include "medspheres/bake/bake_metadata.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "medspheres/version.h"

namespace medspheres {

namespace {

using Json = nlohmann::ordered_json;

Json vec(const Eigen::Vector3d& v) {
  return Json::array({v.x(), v.y(), v.z()});
}

// generator.params: the bake's resolution, mode and, for a dilated set, the dilation's.
Json params_json(const BakeRecord& r) {
  Json params = {{"resolution", r.stats.resolution},
                 {"object_angle", r.options.object_angle},
                 {"medial_tolerance", r.stats.medial_tolerance},
                 {"mode", r.mode}};
  if (r.mode != "resolution") params["target"] = r.mode_target;
  if (r.dilation_options && r.dilation_stats) {
    const DilateOptions& o = *r.dilation_options;
    Json d = {{"vertex_tolerance", r.dilation_stats->vertex_tolerance},
              {"max_protrusion", std::isfinite(o.max_protrusion) ? Json(o.max_protrusion) : Json()},
              {"seed", o.seed}};
    if (o.cover_tolerance >= 0.0) {
      d["cover_tolerance"] = o.cover_tolerance;
      d["cover_samples"] = o.cover_samples;
      d["cover_max_rounds"] = o.cover_max_rounds;
      d["cover_max_added"] = o.cover_max_added;
    }
    params["dilation"] = d;
  }
  return params;
}

// stats.dilation: what the dilation grew and added.
Json dilation_json(const BakeRecord& r) {
  const DilateStats& s = *r.dilation_stats;
  Json d = {{"input_spheres", s.input_spheres},
            {"v_points", s.v_points},
            {"edge_points", s.edge_points},
            {"grown", s.grown},
            {"max_growth", s.max_growth},
            {"capped_points", s.capped_points},
            {"added_vertex", s.added_vertex},
            {"added_cover", s.added_cover},
            {"seconds", s.seconds}};
  if (r.dilation_options && r.dilation_options->cover_tolerance >= 0.0) {
    d["cover_rounds"] = s.cover_rounds;
    d["cover_reached"] = s.cover_reached;
    d["uncovered_max"] = s.uncovered_max;
  }
  return d;
}

// stats.search: the resolutions a resolution search baked, their counts and errors.
Json search_json(const BakeRecord& r) {
  Json resolutions = Json::array(), spheres = Json::array(), errors = Json::array();
  for (const SearchStep& step : r.stats.search) {
    resolutions.push_back(step.resolution);
    spheres.push_back(step.spheres);
    errors.push_back(std::isfinite(step.error) ? Json(step.error) : Json());
  }
  Json search = {{"resolutions", resolutions}, {"spheres", spheres}};
  if (r.mode == "target_error") search["errors"] = errors;
  return search;
}

Json stats_json(const BakeRecord& r) {
  Json st = {
      {"count", r.dilation_stats
                    ? r.dilation_stats->input_spheres + r.dilation_stats->added_vertex +
                          r.dilation_stats->added_cover
                    : r.stats.spheres},
      {"resolution", r.stats.resolution},
      {"bake_seconds", r.stats.total_seconds > 0.0 ? r.stats.total_seconds : r.stats.seconds},
      {"min_radius", r.stats.min_radius},
      {"max_radius", r.stats.max_radius},
      {"closest_point_queries", r.stats.closest_point_queries},
      {"winding_queries", r.stats.winding_queries}};
  if (r.dilation_stats) st["dilation"] = dilation_json(r);
  if (!r.stats.search.empty()) {
    // A resolution search: bake_seconds above is the whole search; what it baked.
    st["final_bake_seconds"] = r.stats.seconds;
    st["search"] = search_json(r);
  }
  // Non-finite numbers (a nerr that is not defined) are written as null.
  for (const auto& [k, v] : r.extra_stats) st[k] = std::isfinite(v) ? Json(v) : Json();
  for (const auto& [k, v] : r.extra_strings) st[k] = v;
  if (!r.record_seconds) {
    st.erase("bake_seconds");
    st.erase("final_bake_seconds");
    if (st.contains("dilation")) st["dilation"].erase("seconds");
  }
  return st;
}

}  // namespace

std::string bake_metadata_json(const BakeRecord& r) {
  Json meta;
  meta["source"] = {{"mesh", r.source.mesh},
                    {"sha256", r.source.sha256},
                    {"triangles", r.source.report.triangles},
                    {"closed", r.source.report.closed},
                    {"bbox_min", vec(r.source.report.bbox_min)},
                    {"bbox_max", vec(r.source.report.bbox_max)}};
  meta["generator"] = {{"method", r.dilation_stats ? "medial+dilation" : "medial"},
                       {"version", MEDSPHERES_VERSION_STRING},
                       {"params", params_json(r)}};
  meta["stats"] = stats_json(r);
  return meta.dump();
}

}  // namespace medspheres
