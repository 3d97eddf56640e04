// The provenance of a covering set (cover_record.h): a BakeRecord and its JSON.
#include "medspheres/bake/cover_record.h"

#include <algorithm>

#include <nlohmann/json.hpp>

namespace medspheres {

BakeRecord cover_bake_record(const MeshProvenance& source, const CoverResult& result) {
  const CoverStats& s = result.stats;
  const CoverCertificate& c = result.certificate;
  BakeRecord r;
  r.source = source;
  r.mode = s.start_spheres > 0 ? "cover_tighten" : "cover_budget";
  r.mode_target = static_cast<double>(s.budget);
  if (s.start_spheres == 0) r.cover_search = result.search;
  r.stats.spheres = s.spheres;
  r.stats.seconds = s.seconds;
  r.stats.total_seconds = s.seconds;
  if (!result.spheres.empty()) {
    const auto [lo, hi] =
        std::minmax_element(result.spheres.spheres.begin(), result.spheres.spheres.end(),
                            [](const Sphere& a, const Sphere& b) { return a.radius < b.radius; });
    r.stats.min_radius = lo->radius;
    r.stats.max_radius = hi->radius;
  }
  auto& x = r.extra_stats;
  x["certified"] = s.certified ? 1.0 : 0.0;
  x["certificate_triangles"] = static_cast<double>(c.triangles);
  x["certificate_pieces_tested"] = static_cast<double>(c.pieces_tested);
  x["certificate_max_depth"] = static_cast<double>(c.max_depth_reached);
  x["certificate_uncertified_triangles"] = static_cast<double>(c.uncertified_triangles);
  if (!c.certified) x["uncovered_max"] = c.worst_distance;
  x["union_volume"] = s.union_volume;
  if (s.mesh_volume) x["mesh_volume"] = *s.mesh_volume;
  x["excess_volume"] = s.excess_volume;  // null without a volume
  x["max_protrusion"] = s.max_protrusion;
  x["elements"] = static_cast<double>(s.elements);
  x["interior_points"] = static_cast<double>(s.interior_points);
  x["repaired"] = static_cast<double>(s.repaired);
  return r;
}

std::string cover_metadata_json(const BakeRecord& record) {
  using Json = nlohmann::ordered_json;
  Json meta = Json::parse(bake_metadata_json(record));
  Json& gen = meta["generator"];
  gen["method"] = "cover";
  gen["params"] = {{"mode", record.mode}, {"budget", record.mode_target}};
  if (record.cover_search) {
    gen["params"]["protrusion_allowance"] = record.cover_search->protrusion_allowance;
    gen["params"]["protrusion_restarts"] = record.cover_search->protrusion_restarts;
    gen["params"]["balance_rounds"] = record.cover_search->balance_rounds;
  }
  Json& st = meta["stats"];
  for (const char* medial : {"resolution", "closest_point_queries", "winding_queries"})
    st.erase(medial);
  const bool certified = st.value("certified", 0.0) == 1.0;
  st["certified"] = certified;
  st["surface_covered"] = certified;
  st["interior_certified"] = false;
  // A cover of a robust solid: the input's own triangles certified too (cover_input.h).
  if (st.contains("input_certified")) st["input_certified"] = st["input_certified"] == 1.0;
  return meta.dump();
}

void record_input_cover(const InputCoverCheck& check, BakeRecord& record) {
  const CoverCertificate& c = check.certificate;
  auto& x = record.extra_stats;
  x["input_certified"] = c.certified ? 1.0 : 0.0;
  x["input_certificate_triangles"] = static_cast<double>(c.triangles);
  x["input_uncertified_triangles"] = static_cast<double>(c.uncertified_triangles);
  x["input_repaired"] = static_cast<double>(check.repaired);
  if (!c.certified) x["input_uncovered_max"] = c.worst_distance;
}

}  // namespace medspheres
