// medspheres bake MESH: medial spheres of a mesh, written as a sphere-set file.
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_common.h"
#include "cmd_batch.h"
#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/error.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/io.h"
#include "medspheres/options/bake_flags.h"
#include "solid_flags.h"

namespace medspheres::cli {

namespace {

struct BakeArgs {
  std::vector<std::string> inputs;  ///< one mesh, or a batch's files and folders
  BatchFlags batch;
  std::string mesh;
  std::string out;
  BakeFlags flags;
  std::string cover_start, cover_start_link;  ///< a sphere file, and the link it names
  bool quiet = false;
};

std::string default_output(const std::string& mesh) {
  return std::filesystem::path(mesh).stem().string() + ".spheres.json";
}

// What the summary says of a nerr of this kind.
const char* nerr_note(NerrKind kind) {
  switch (kind) {
    case NerrKind::kExact:
      return "exact: the spheres are inside";
    case NerrKind::kLowerBound:
      return "a lower bound: spheres stick out";
    case NerrKind::kApproximate:
      return "approximate: the mesh intersects itself, and its volume counts overlaps";
    case NerrKind::kUndefined:
      break;
  }
  return "undefined";
}

// The mesh line of the summary: closed, or what makes the winding number define the solid.
std::string mesh_description(const BakeOutcome& o) {
  const MeshReport& report = o.record.source.report;
  const std::size_t self_intersecting_pairs = o.self_intersecting_pairs;
  const SolidKind solid = o.solid;
  std::vector<std::string> flaws;
  if (report.boundary_edges > 0)
    flaws.push_back("open (" + count_text(report.boundary_edges, "boundary edge") +
                    "; radii also respect the holes, capped)");
  if (report.nonmanifold_edges > 0)
    flaws.push_back("non-manifold (" + count_text(report.nonmanifold_edges, "edge") + ")");
  if (self_intersecting_pairs > 0 && solid != SolidKind::kRobust)
    flaws.push_back("self-intersecting (" + count_text(self_intersecting_pairs, "triangle pair") +
                    ")");
  if (solid == SolidKind::kRobust)
    flaws.push_back("baked against its robust solid" +
                    (o.robust_thickness_escalated
                         ? " (walls thickened to " +
                               number_text(o.robust_thickness / report.largest_side(), 3) +
                               "L: thinner ones enclosed nothing)"
                         : std::string()));
  if (flaws.empty()) return "closed";
  std::string out;
  for (const std::string& f : flaws) out += (out.empty() ? "" : ", ") + f;
  return solid == SolidKind::kRobust ? out : out + ": baked against its winding-number solid";
}

// The dilation line of the summary, and the protrusion of S+.
void print_dilation(const BakeOutcome& o) {
  const DilateStats& d = *o.record.dilation_stats;
  std::cout << "  dilated       " << count_text(o.spheres.size(), "sphere") << ": " << d.grown
            << " grown (by up to " << number_text(d.max_growth, 4) << "), " << d.added_vertex
            << " added at vertices";
  if (o.record.dilation_options->cover_tolerance >= 0.0)
    std::cout << ", " << d.added_cover << " added in " << count_text(d.cover_rounds, "cover round")
              << "; "
              << "uncovered " << number_text(d.uncovered_max, 4)
              << (d.cover_reached ? " (within --cover)" : " (caps reached before --cover)");
  std::cout << ", " << number_text(d.seconds, 3) << " s\n";
  if (o.volume)
    std::cout << "  protrusion    " << number_text(o.volume->max_protrusion, 4)
              << " (the most a sphere sticks out of the solid)\n";
}

// The summary of a covering set (method cover).
void print_cover_summary(const BakeArgs& args, const std::string& out, const BakeOutcome& o) {
  const CoverResult& r = *o.cover;
  std::cout << "baked " << args.mesh << " -> " << out << "\n"
            << "  mesh          " << count_text(o.record.source.report.triangles, "triangle")
            << ", " << mesh_description(o) << "\n"
            << "  cover         " << count_text(o.spheres.size(), "sphere") << " ("
            << (r.stats.start_spheres > 0 ? "from " : "budget ") << r.stats.budget
            << (r.stats.start_spheres > 0 ? " given" : "") << "), surface "
            << (r.stats.certified ? "certified covered" : "NOT certified") << " ("
            << count_text(r.certificate.pieces_tested, "piece") << ", depth "
            << r.certificate.max_depth_reached << ")\n"
            << "  fit           excess volume " << number_text(r.stats.excess_volume, 4)
            << " of the solid's, max protrusion " << number_text(r.stats.max_protrusion, 4) << ", "
            << number_text(r.stats.seconds, 3) << " s\n";
}

void print_summary(const BakeArgs& args, const std::string& out, const BakeOutcome& o) {
  if (o.cover) return print_cover_summary(args, out, o);
  const BakeStats& s = o.medial.stats;
  const BakeRecord& record = o.record;
  const std::string& mode = record.mode;
  const double target = record.mode_target;
  std::cout << "baked " << args.mesh << " -> " << out << "\n"
            << "  mesh          " << count_text(record.source.report.triangles, "triangle") << ", "
            << mesh_description(o) << "\n"
            << "  resolution    " << s.resolution << " (grid " << s.grid[0] << " x " << s.grid[1]
            << " x " << s.grid[2] << ", cell " << number_text(s.cell_size, 4) << ")";
  if (mode != "resolution")
    std::cout << ", chosen for " << mode << " " << number_text(target) << " among "
              << count_text(s.search.size(), "resolution") << " baked";
  // The set the error target was measured on: S_D when dilated, else the one written.
  const std::optional<VolumeError>& measured = o.internal ? o.internal : o.volume;
  if (mode == "target_error" && measured && measured->kind == NerrKind::kApproximate)
    std::cout << " (by an approximate nerr: the mesh intersects itself)";
  std::cout << "\n"
            << "  spheres       " << s.spheres << ", radius " << number_text(s.min_radius, 4)
            << " .. " << number_text(s.max_radius, 4) << "\n";
  if (record.dilation_stats) print_dilation(o);
  if (o.internal)
    std::cout << "  internal S_D  nerr " << number_text(o.internal->nerr, 4) << " ("
              << nerr_note(o.internal->kind) << ")"
              << (mode == "target_error"
                      ? ": --target-error " + number_text(target) +
                            " was met by this internal set; the written S+ is measured below"
                      : std::string())
              << "\n";
  if (o.volume) {
    std::cout << "  volume        " << (o.internal ? "S+: " : "") << "union "
              << number_text(o.volume->union_measures.volume, 6) << " of mesh "
              << number_text(*o.volume->mesh_volume, 6) << ", nerr "
              << number_text(o.volume->nerr, 4) << " (" << nerr_note(o.volume->kind) << ")\n";
  } else {
    std::cout << "  volume        not computed: the mesh is not a closed outward solid\n";
  }
  std::cout << "  work          " << s.closest_point_queries << " closest-point and "
            << s.winding_queries << " winding-number queries, " << number_text(s.seconds, 3)
            << " s";
  if (mode != "resolution")
    std::cout << " (the whole search: " << number_text(s.total_seconds, 3) << " s)";
  std::cout << "\n";
}

// bake writes one medspheres sphere set (JSON). An output named for another format (cuRobo's
// .yml, .sph, .xrdf, ...) would get JSON under that name, so it is refused before any work;
// a name no format claims (.txt) is taken as it is.
void check_bake_output(const std::string& out) {
  formats::SphereFormat format = formats::SphereFormat::kSphereSet;
  try {
    format = formats::sphere_format_of_path(out);
  } catch (const InputError&) {
    return;
  }
  if (format == formats::SphereFormat::kSphereSet) return;
  throw InputError::option(ErrorKind::kConflict, "output", out,
                           out + " is named for the " + formats::sphere_format_name(format) +
                               " format, but bake writes a medspheres sphere set (.json); bake "
                               "to a .json, then `medspheres convert` it");
}

int run_bake(BakeArgs& args) {
  // Options first, then the output path: both are reported before any work is done.
  if (!args.cover_start.empty())
    args.flags.cover_start = formats::one_set_of(formats::read_sphere_document(args.cover_start),
                                                 args.cover_start_link, "cover_start_link");
  BakeRequest request = bake_request(args.flags);
  const BatchCommand batch = mesh_batch(request);
  if (is_batch(args.inputs, args.batch, batch)) {
    if (!request.cover_start.empty())
      throw InputError::option(ErrorKind::kConflict, "cover_start", args.cover_start,
                               "starts the cover of one mesh, not of a batch");
    return run_batch(args.inputs, args.out, args.batch, batch, args.quiet);
  }
  args.mesh = args.inputs.front();
  const std::string out = args.out.empty() ? default_output(args.mesh) : args.out;
  check_bake_output(out);
  check_output_path(out);
  check_output_spares_inputs(out, {args.mesh, args.cover_start});

  ProgressBar bar(!args.quiet);
  request.medial.progress = [&bar](const std::string& stage, std::size_t done, std::size_t total) {
    bar.update(stage, done, total);
  };
  std::vector<std::string> warnings;
  auto warn = [&] {
    bar.finish();
    if (!args.quiet)
      for (const std::string& w : warnings)
        std::cerr << "medspheres: warning: " << args.mesh << ": " << w << "\n";
  };
  BakeOutcome outcome;
  try {
    outcome = bake_file(args.mesh, request, &warnings);
  } catch (const std::exception&) {
    warn();  // the loader's warnings may explain the failure
    throw;
  }
  warn();
  save_sphere_set(outcome.spheres, out);
  if (!args.quiet) print_summary(args, out, outcome);
  // A cover the certificate could not prove is written (it says so) but is a failure.
  return outcome.cover && !outcome.cover->stats.certified ? kExitFailure : kExitOk;
}

}  // namespace

Runner register_bake(CLI::App& app) {
  auto a = std::make_shared<BakeArgs>();
  CLI::App* sub =
      app.add_subcommand("bake", "Bake medial spheres of a mesh into a sphere-set file");
  sub->add_option("mesh", a->inputs,
                  "Mesh file (STL, OBJ, PLY, OFF, DAE, glTF, ...); several files or folders "
                  "bake a batch into the folder -o");
  sub->add_option("-o,--output", a->out,
                  "Output file (default: MESH's stem + .spheres.json, here); a batch's output "
                  "folder")
      ->check(non_empty);
  sub->add_option("--resolution", a->flags.resolution,
                  "Grid cells along the bounding box's longest side")
      ->capture_default_str();
  sub->add_option("--object-angle", a->flags.object_angle,
                  "Keep medial points with at least this object angle (rad)")
      ->capture_default_str();
  sub->add_option(
      "--medial-tolerance", a->flags.medial_tolerance,
      "Stop the medial search within this distance: at least 1e-9 of the box's largest side L "
      "and below the cell size (default: 1e-3 L, at most half a cell)");
  sub->add_option("--method", a->flags.method,
                  "medial: inner spheres (S_D; S+ with --dilate or --cover); cover: at most "
                  "--max-spheres spheres whose union contains the whole surface, certified")
      ->check(CLI::IsMember({"medial", "cover"}))
      ->capture_default_str();
  auto* max = sub->add_option("--max-spheres", a->flags.max_spheres,
                              "At most N spheres: the best N inner spheres, or the budget of a "
                              "cover");
  auto* err =
      sub->add_option("--target-error", a->flags.target_error,
                      "Choose the smallest resolution whose normalized volume error is at most E");
  max->excludes(err);
  sub->add_flag("--dilate", a->flags.dilation.dilate,
                "Dilate the spheres until they hug the surface (paper section 5.1); writes S+");
  sub->add_option("--vertex-tolerance", a->flags.dilation.vertex_tolerance,
                  "Dilation: cover every mesh vertex within this length, in the mesh's units or "
                  "a multiple of the box's largest side L written 0.005L (default: 0.005L)");
  sub->add_option("--max-protrusion", a->flags.dilation.max_protrusion,
                  "Dilation: let no grown or added sphere stick out of the solid by more than "
                  "this length, e.g. 0.002L (default: no cap, as in the paper)");
  sub->add_option("--cover", a->flags.dilation.cover,
                  "Dilate, then add spheres until no surface sample is farther than this "
                  "length outside, e.g. 0.003L (implies --dilate)");
  auto* start = sub->add_option(
      "--cover-start", a->cover_start,
      "Method cover: make these spheres (any sphere file convert reads, in the mesh's frame; "
      "a planner's own set need not cover) into a certified cover of at most as many spheres, "
      "each grown or shrunk to the surface nearest it, then tightened; instead of "
      "--max-spheres");
  start->excludes(max)->check(non_empty);
  sub->add_option("--cover-start-link", a->cover_start_link,
                  "The link of a per-link --cover-start file (cuRobo, XRDF, ...) to start from "
                  "(default: its only link)")
      ->needs(start);
  sub->add_option("--seed", a->flags.dilation.seed, "Dilation: seed of its random points")
      ->check(non_negative)
      ->capture_default_str();
  add_solid_flags(sub, a->flags.solid);
  add_cover_search_flags(sub, a->flags.cover_search, "Method cover");
  sub->add_option("--threads", a->flags.threads, "Threads, at most 1024 (default 0: all cores)")
      ->capture_default_str();
  sub->add_flag("-q,--quiet", a->quiet, "No progress bar, warnings or summary");
  add_batch_flags(*sub, a->batch, mesh_batch(BakeRequest{}));
  return [a] {
    if (a->inputs.empty() && a->batch.from_list.empty())
      throw std::invalid_argument("bake: no mesh given (a mesh file, folders, or --from-list)");
    return run_bake(*a);
  };
}

}  // namespace medspheres::cli
