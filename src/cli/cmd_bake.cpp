// medspheres bake MESH: medial spheres of a mesh, written as a sphere-set file.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "cli_common.h"
#include "medspheres/bake.h"
#include "medspheres/bake_metadata.h"
#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/mesh_io.h"
#include "medspheres/union_volume.h"

namespace medspheres::cli {

namespace {

struct BakeArgs {
  std::string mesh;
  std::string out;
  int resolution = BakeOptions{}.resolution;
  double object_angle = BakeOptions{}.object_angle;
  double medial_tolerance = 0.0;
  std::optional<int> max_spheres;
  std::optional<double> target_error;
  int threads = 0;
  bool quiet = false;
};

std::string default_output(const std::string& mesh) {
  return std::filesystem::path(mesh).stem().string() + ".spheres.json";
}

int run_bake(const BakeArgs& args) {
  // Options first: nonsense is reported before any work is done.
  BakeOptions options;
  options.resolution = args.resolution;
  options.object_angle = args.object_angle;
  options.medial_tolerance = args.medial_tolerance;
  options.threads = args.threads;
  if (args.max_spheres && *args.max_spheres < 1)
    throw InputError("--max-spheres", "must be >= 1, got " + std::to_string(*args.max_spheres));
  if (args.target_error && !(*args.target_error > 0.0 && *args.target_error < 1.0))
    throw InputError("--target-error", "must be in (0, 1), got " + fmt(*args.target_error));
  const std::string out = args.out.empty() ? default_output(args.mesh) : args.out;

  const LoadedMesh loaded = load_mesh(args.mesh);
  if (!args.quiet)
    for (const std::string& w : loaded.warnings)
      std::cerr << "medspheres: warning: " << args.mesh << ": " << w << "\n";
  const bool exact_volume = loaded.report.is_closed_outward();
  if (args.target_error && !exact_volume)
    throw InputError("--target-error", args.mesh +
                                           " is not a closed, outward-wound mesh, so its "
                                           "volume and the error are not defined");

  ProgressBar bar(!args.quiet);
  options.progress = [&bar](const std::string& stage, std::size_t done, std::size_t total) {
    bar.update(stage, done, total);
  };
  const MeshQuery query(loaded.mesh);
  const double mesh_volume = loaded.report.signed_volume;
  auto nerr_of = [&](const SphereSet& s) {
    return (mesh_volume - measure_union(s.spheres).volume) / mesh_volume;
  };

  std::string mode = "resolution";
  double target = 0.0;
  BakeResult result;
  try {
    if (args.max_spheres) {
      mode = "max_spheres";
      target = *args.max_spheres;
      result = bake_max_spheres(query, static_cast<std::size_t>(*args.max_spheres), options);
    } else if (args.target_error) {
      mode = "target_error";
      target = *args.target_error;
      result = bake_target_error(query, *args.target_error, nerr_of, options);
    } else {
      result = bake(query, options);
    }
  } catch (const InputError& e) {
    // The library speaks of "the mesh"; the user knows it by its file name.
    if (e.source() == "mesh") throw InputError(args.mesh, e.problem());
    throw;
  }
  bar.finish();
  if (result.spheres.empty())
    throw InputError(args.mesh, "no medial sphere was found at resolution " +
                                    std::to_string(result.stats.resolution) +
                                    " with object angle " + fmt(args.object_angle) +
                                    "; try a higher --resolution or a smaller --object-angle");

  std::map<std::string, double> extra;
  std::map<std::string, std::string> extra_text;
  std::optional<UnionMeasures> measures;
  if (exact_volume) {
    measures = measure_union(result.spheres.spheres);
    extra["nerr"] = (mesh_volume - measures->volume) / mesh_volume;
    extra["mesh_volume"] = mesh_volume;
    extra["union_volume"] = measures->volume;
    extra_text["nerr_kind"] = "exact";  // baked spheres are inside the solid
  }
  MeshProvenance source{args.mesh, file_sha256(args.mesh), loaded.report};
  result.spheres.metadata_json =
      bake_metadata_json(source, options, result.stats, mode, target, extra, extra_text);
  save_sphere_set(result.spheres, out);

  if (!args.quiet) {
    const BakeStats& s = result.stats;
    std::cout << "baked " << args.mesh << " -> " << out << "\n"
              << "  mesh          " << loaded.report.triangles << " triangles, "
              << (loaded.report.closed ? "closed" : "open: baked against its winding-number solid")
              << "\n"
              << "  resolution    " << s.resolution << " (grid " << s.grid[0] << " x " << s.grid[1]
              << " x " << s.grid[2] << ", cell " << fmt(s.cell_size, 4) << ")";
    if (mode != "resolution") std::cout << ", chosen for " << mode << " " << fmt(target);
    std::cout << "\n"
              << "  spheres       " << s.spheres << ", radius " << fmt(s.min_radius, 4) << " .. "
              << fmt(s.max_radius, 4) << "\n";
    if (measures) {
      std::cout << "  volume        union " << fmt(measures->volume, 6) << " of mesh "
                << fmt(mesh_volume, 6) << ", nerr " << fmt(extra["nerr"], 4)
                << " (exact: the spheres are inside)\n";
    } else {
      std::cout << "  volume        not computed: the mesh is not a closed outward solid\n";
    }
    std::cout << "  work          " << s.closest_point_queries << " closest-point and "
              << s.winding_queries << " winding-number queries, " << fmt(s.seconds, 3) << " s\n";
  }
  return kExitOk;
}

}  // namespace

Runner register_bake(CLI::App& app) {
  auto a = std::make_shared<BakeArgs>();
  CLI::App* sub =
      app.add_subcommand("bake", "Bake medial spheres of a mesh into a sphere-set file");
  sub->add_option("mesh", a->mesh, "Mesh file (STL, OBJ, PLY, OFF, DAE, glTF, ...)")->required();
  sub->add_option("-o,--output", a->out,
                  "Output file (default: MESH's stem + .spheres.json, here)");
  sub->add_option("--resolution", a->resolution, "Grid cells along the bounding box's longest side")
      ->capture_default_str();
  sub->add_option("--object-angle", a->object_angle,
                  "Keep medial points with at least this object angle (rad)")
      ->capture_default_str();
  sub->add_option(
      "--medial-tolerance", a->medial_tolerance,
      "Stop the medial search within this distance (default: 1e-3 of the box's largest side)");
  auto* max = sub->add_option("--max-spheres", a->max_spheres,
                              "Choose the largest resolution giving at most N spheres");
  auto* err =
      sub->add_option("--target-error", a->target_error,
                      "Choose the smallest resolution whose normalized volume error is at most E");
  max->excludes(err);
  sub->add_option("--threads", a->threads, "Threads (default 0: all cores)")->capture_default_str();
  sub->add_flag("-q,--quiet", a->quiet, "No progress bar, warnings or summary");
  return [a] { return run_bake(*a); };
}

}  // namespace medspheres::cli
