// medspheres info MESH [--json]: what the loader and the validator found in a mesh.
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "medspheres/measure/self_intersection.h"
#include "medspheres/mesh/mesh_io.h"

namespace medspheres::cli {

namespace {

struct InfoArgs {
  std::string mesh;
  bool json = false;
};

nlohmann::ordered_json vec_json(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

int run_info(const InfoArgs& args) {
  const LoadedMesh loaded = load_mesh(args.mesh);
  const MeshReport& r = loaded.report;
  const SelfIntersections self = find_self_intersections(loaded.mesh);
  if (args.json) {
    nlohmann::ordered_json j = {
        {"file", args.mesh},
        {"triangles", r.triangles},
        {"vertices", r.vertices},
        {"unreferenced_vertices", r.unreferenced_vertices},
        {"edges", r.edges},
        {"components", r.components},
        {"boundary_edges", r.boundary_edges},
        {"nonmanifold_edges", r.nonmanifold_edges},
        {"degenerate_triangles", r.degenerate_triangles},
        {"inconsistent_edges", r.inconsistent_edges},
        {"self_intersecting_pairs", self.count()},
        {"closed", r.closed},
        {"volume", r.signed_volume},
        {"bbox_min", vec_json(r.bbox_min)},
        {"bbox_max", vec_json(r.bbox_max)},
        {"triangles_flipped_for_consistency",
         loaded.orientation_fix.triangles_flipped_for_consistency},
        {"components_flipped_outward", loaded.orientation_fix.components_flipped_outward}};
    auto comps = nlohmann::ordered_json::array();
    for (const ComponentReport& c : r.component_reports) {
      comps.push_back({{"triangles", c.triangles},
                       {"closed", c.closed},
                       {"orientation", to_string(c.orientation)},
                       {"signed_volume", c.signed_volume}});
    }
    j["component_details"] = comps;
    j["warnings"] = loaded.warnings;
    std::cout << j.dump(2) << "\n";
    return kExitOk;
  }

  std::size_t closed = 0, outward = 0;
  for (const ComponentReport& c : r.component_reports) {
    closed += c.closed;
    outward += c.orientation == Orientation::kOutward;
  }
  std::cout << args.mesh << "\n"
            << "  triangles           " << r.triangles << "\n"
            << "  vertices            " << r.vertices << "\n"
            << "  components          " << r.components << " (" << closed << " closed, " << outward
            << " wound outward)\n"
            << "  boundary edges      " << r.boundary_edges << "\n"
            << "  non-manifold edges  " << r.nonmanifold_edges << "\n"
            << "  degenerate          " << r.degenerate_triangles << "\n"
            << "  self-intersecting   "
            << (self.any() ? count_text(self.count(), "triangle pair") +
                                 (self.count() == 1 ? " meets" : " meet") +
                                 " other than at a shared vertex or edge"
                           : std::string("no"))
            << "\n"
            << "  closed              " << (r.closed ? "yes" : "no") << "\n"
            << "  volume              " << number_text(r.signed_volume)
            << (!r.is_closed_outward() ? "  (not a closed outward solid: indicative only)"
                : self.any()
                    ? "  (the surface intersects itself: overlaps may count more than once)"
                    : "")
            << "\n"
            << "  bbox                [" << number_text(r.bbox_min.x()) << ", "
            << number_text(r.bbox_min.y()) << ", " << number_text(r.bbox_min.z()) << "] .. ["
            << number_text(r.bbox_max.x()) << ", " << number_text(r.bbox_max.y()) << ", "
            << number_text(r.bbox_max.z()) << "]\n";
  for (const std::string& w : loaded.warnings) std::cout << "  warning: " << w << "\n";
  return kExitOk;
}

}  // namespace

Runner register_info(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* sub = app.add_subcommand("info", "Load a mesh, validate it and report what was found");
  sub->add_option("mesh", args->mesh, "Mesh file (STL, OBJ, PLY, OFF, DAE, glTF, ...)")->required();
  sub->add_flag("--json", args->json, "Print one JSON object instead of text");
  return [args] { return run_info(*args); };
}

}  // namespace medspheres::cli
