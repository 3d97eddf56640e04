// medspheres bake MESH: medial spheres of a mesh, written as a sphere-set file.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "cli_common.h"
#include "medspheres/bake/bake.h"
#include "medspheres/bake/bake_metadata.h"
#include "medspheres/bake/cover.h"
#include "medspheres/bake/dilate.h"
#include "medspheres/bake/fit_metrics.h"
#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/mesh/mesh_io.h"

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
  std::optional<int> cover_budget;
  bool dilate = false;
  // Lengths: a number in the mesh's units, or a number followed by L (see Length).
  std::optional<std::string> vertex_tolerance;
  std::optional<std::string> max_protrusion;
  std::optional<std::string> cover;
  std::uint64_t seed = DilateOptions{}.seed;
  int threads = 0;
  bool quiet = false;
};

// A length option: a number in the mesh's units, or a number followed by "L", a multiple
// of the largest side of the mesh's bounding box (0.003L is 0.3% of it).
struct Length {
  double value = 0.0;
  bool relative = false;
  double in(double longest) const { return relative ? value * longest : value; }
};

// \p text as a Length that satisfies \p ok (described by \p range), or InputError naming
// \p flag.
Length parse_length(const std::string& text, const char* flag, bool (*ok)(double),
                    const char* range) {
  Length l;
  std::string number = text;
  if (!number.empty() && (number.back() == 'L' || number.back() == 'l')) {
    l.relative = true;
    number.pop_back();
  }
  std::size_t used = 0;
  try {
    l.value = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (number.empty() || used != number.size() || !ok(l.value))
    throw InputError(flag, std::string("must be ") + range +
                               ": a length in the mesh's units, or a multiple of the bounding "
                               "box's largest side written with an L (0.003L), got '" +
                               text + "'");
  return l;
}

bool positive(double x) {
  return x > 0.0 && std::isfinite(x);
}
bool non_negative(double x) {
  return x >= 0.0 && std::isfinite(x);
}

// The dilation options, checked before any work is done; lengths are set once the mesh's
// box is known (resolve_lengths).
struct Dilation {
  DilateOptions options;
  std::optional<Length> vertex_tolerance, max_protrusion, cover;

  void resolve_lengths(double longest) {
    if (vertex_tolerance) options.vertex_tolerance = vertex_tolerance->in(longest);
    if (max_protrusion) options.max_protrusion = max_protrusion->in(longest);
    if (cover) options.cover_tolerance = cover->in(longest);
  }
};

std::optional<Dilation> dilation_options(const BakeArgs& a) {
  if (!a.dilate && !a.cover) {
    if (a.vertex_tolerance)
      throw InputError("--vertex-tolerance", "applies only with --dilate or --cover");
    if (a.max_protrusion)
      throw InputError("--max-protrusion", "applies only with --dilate or --cover");
    return std::nullopt;
  }
  Dilation d;
  d.options.seed = a.seed;
  d.options.threads = a.threads;
  if (a.vertex_tolerance)
    d.vertex_tolerance =
        parse_length(*a.vertex_tolerance, "--vertex-tolerance", positive, "a finite length > 0");
  if (a.max_protrusion)
    d.max_protrusion =
        parse_length(*a.max_protrusion, "--max-protrusion", non_negative, "a finite length >= 0");
  if (a.cover) d.cover = parse_length(*a.cover, "--cover", positive, "a finite length > 0");
  return d;
}

std::string default_output(const std::string& mesh) {
  return std::filesystem::path(mesh).stem().string() + ".spheres.json";
}

// The flag of a BakeOptions field: "object_angle" is --object-angle.
std::string flag_of(std::string field) {
  std::replace(field.begin(), field.end(), '_', '-');
  return "--" + field;
}

// The numeric options whose range does not depend on the mesh. The library's
// bake_options_problem holds the ranges of BakeOptions; the CLI names its flags.
BakeOptions bake_options(const BakeArgs& a) {
  BakeOptions o;
  o.resolution = a.resolution;
  o.object_angle = a.object_angle;
  o.medial_tolerance = a.medial_tolerance;
  o.threads = a.threads;
  if (const std::optional<OptionProblem> p = bake_options_problem(o))
    throw InputError(flag_of(p->option), p->problem);
  if (a.max_spheres && *a.max_spheres < 1)
    throw InputError("--max-spheres", "must be >= 1, got " + std::to_string(*a.max_spheres));
  if (a.target_error && !(*a.target_error > 0.0 && *a.target_error < 1.0))
    throw InputError("--target-error", "must be in (0, 1), got " + number_text(*a.target_error));
  return o;
}

// An explicit --medial-tolerance against the mesh's box: at least 1e-9 L, below the cell
// of the finest resolution that will be baked.
void check_medial_tolerance(const BakeArgs& a, const MeshReport& report) {
  const bool search = a.max_spheres || a.target_error;
  const int finest = search ? kMaxSearchResolution : a.resolution;
  const double longest = report.largest_side();
  const std::optional<std::string> problem =
      medial_tolerance_problem(a.medial_tolerance, longest, finest);
  if (!problem) return;
  const std::string where =
      search ? a.mesh + " (a search may bake up to resolution " + std::to_string(finest) + ")"
             : a.mesh;
  throw InputError("--medial-tolerance", "for " + where + ", " + *problem);
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
std::string mesh_description(const MeshReport& report, std::size_t self_intersecting_pairs) {
  std::vector<std::string> flaws;
  if (report.boundary_edges > 0)
    flaws.push_back("open (" + std::to_string(report.boundary_edges) +
                    " boundary edges; radii also respect the holes, capped)");
  if (report.nonmanifold_edges > 0)
    flaws.push_back("non-manifold (" + std::to_string(report.nonmanifold_edges) + " edges)");
  if (self_intersecting_pairs > 0)
    flaws.push_back("self-intersecting (" + std::to_string(self_intersecting_pairs) +
                    " triangle pairs)");
  if (flaws.empty()) return "closed";
  std::string out;
  for (const std::string& f : flaws) out += (out.empty() ? "" : ", ") + f;
  return out + ": baked against its winding-number solid";
}

// bake --cover-budget K: a certified covering set of at most K spheres (cover.h).
int run_cover_bake(const BakeArgs& args, const std::string& out) {
  if (*args.cover_budget < 1)
    throw InputError("--cover-budget", "must be >= 1, got " + std::to_string(*args.cover_budget));
  if (args.dilate || args.cover)
    throw InputError("--cover-budget", "makes a covering set itself; drop --dilate and --cover");
  const LoadedMesh loaded = load_mesh(args.mesh);
  const FitEvaluator fit(loaded.mesh, args.threads);
  CoverOptions options;
  options.threads = args.threads;
  const CoverResult r =
      bake_cover(fit.query(), static_cast<std::size_t>(*args.cover_budget), options);
  SphereSet output = r.spheres;
  output.metadata_json =
      cover_metadata_json(cover_bake_record({args.mesh, file_sha256(args.mesh), loaded.report}, r));
  save_sphere_set(output, out);
  if (!args.quiet)
    std::cout << "baked " << args.mesh << " -> " << out << "\n  cover         " << output.size()
              << " spheres (budget " << *args.cover_budget << "), surface "
              << (r.stats.certified ? "certified covered" : "NOT certified") << " ("
              << r.certificate.pieces_tested << " pieces, depth " << r.certificate.max_depth_reached
              << "), excess volume " << number_text(r.stats.excess_volume, 4)
              << " of the solid's, max protrusion " << number_text(r.stats.max_protrusion, 4) << ", "
              << number_text(r.stats.seconds, 3) << " s\n";
  return r.stats.certified ? kExitOk : kExitFailure;
}

int run_bake(const BakeArgs& args) {
  // Options first: nonsense is reported before any work is done, and so is an output
  // path that cannot be written.
  BakeOptions options = bake_options(args);
  std::optional<Dilation> dilation = dilation_options(args);
  const std::string out = args.out.empty() ? default_output(args.mesh) : args.out;
  check_output_path(out);
  if (args.cover_budget) return run_cover_bake(args, out);

  const LoadedMesh loaded = load_mesh(args.mesh);
  if (!args.quiet)
    for (const std::string& w : loaded.warnings)
      std::cerr << "medspheres: warning: " << args.mesh << ": " << w << "\n";
  check_medial_tolerance(args, loaded.report);
  if (dilation) dilation->resolve_lengths(loaded.report.largest_side());
  // Orients (a no-op after the loader), builds the mesh query and computes the volume.
  const FitEvaluator fit(loaded.mesh, args.threads);
  if (args.target_error && !fit.volume())
    throw InputError("--target-error", args.mesh +
                                           " is not a closed, outward-wound mesh, so its "
                                           "volume and the error are not defined");

  ProgressBar bar(!args.quiet);
  options.progress = [&bar](const std::string& stage, std::size_t done, std::size_t total) {
    bar.update(stage, done, total);
  };
  const MeshQuery& query = fit.query();
  auto nerr_of = [&](const SphereSet& s) { return fit.volume_error(s.spheres, args.threads).nerr; };

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
    // The library speaks of "the mesh"; the user knows it by its file name. A search that
    // finds no resolution for its option names the option and the mesh.
    if (e.source() == "mesh") throw InputError(args.mesh, e.problem());
    if (e.source() == "--max-spheres" || e.source() == "--target-error")
      throw InputError(e.source(), "for " + args.mesh + ", " + e.problem());
    throw;
  }
  bar.finish();
  if (result.spheres.empty())
    throw InputError(args.mesh, "no medial sphere was found at resolution " +
                                    std::to_string(result.stats.resolution) +
                                    " with object angle " + number_text(args.object_angle) +
                                    "; try a higher --resolution or a smaller --object-angle");

  BakeRecord record;
  record.source = {args.mesh, file_sha256(args.mesh), loaded.report};
  record.options = options;
  record.stats = result.stats;
  record.mode = mode;
  record.mode_target = target;
  SphereSet output = result.spheres;
  std::optional<VolumeError> internal;  // S_D's, when dilated
  if (dilation) {
    if (fit.volume()) internal = fit.volume_error(result.spheres.spheres, args.threads);
    const DilateResult dilated = dilate(query, result.spheres, dilation->options);
    output = dilated.spheres;
    record.dilation_options = dilation->options;
    record.dilation_stats = dilated.stats;
    double lo = output.spheres.front().radius, hi = lo;
    for (const Sphere& sp : output.spheres) {
      lo = std::min(lo, sp.radius);
      hi = std::max(hi, sp.radius);
    }
    record.extra_stats["min_radius"] = lo;
    record.extra_stats["max_radius"] = hi;
  }
  std::optional<VolumeError> volume;
  if (fit.volume()) {
    volume = fit.volume_error(output.spheres, args.threads);
    record.extra_stats["nerr"] = volume->nerr;
    record.extra_stats["mesh_volume"] = *fit.volume();
    record.extra_stats["union_volume"] = volume->union_measures.volume;
    record.extra_stats["max_protrusion"] = volume->max_protrusion;
    record.extra_strings["nerr_kind"] = to_string(volume->kind);
  } else {
    // Written as null: the volume of an open mesh, and so nerr, is not defined.
    record.extra_stats["nerr"] = std::numeric_limits<double>::quiet_NaN();
    record.extra_strings["nerr_kind"] = to_string(NerrKind::kUndefined);
  }
  if (internal) {
    // The internal set S_D, before dilation: what --target-error was met by.
    record.extra_stats["nerr_internal"] = internal->nerr;
    record.extra_strings["nerr_internal_kind"] = to_string(internal->kind);
  }
  output.metadata_json = bake_metadata_json(record);
  save_sphere_set(output, out);

  if (!args.quiet) {
    const BakeStats& s = result.stats;
    std::cout << "baked " << args.mesh << " -> " << out << "\n"
              << "  mesh          " << loaded.report.triangles << " triangles, "
              << mesh_description(loaded.report, fit.self_intersections().count()) << "\n"
              << "  resolution    " << s.resolution << " (grid " << s.grid[0] << " x " << s.grid[1]
              << " x " << s.grid[2] << ", cell " << number_text(s.cell_size, 4) << ")";
    if (mode != "resolution")
      std::cout << ", chosen for " << mode << " " << number_text(target) << " among "
                << s.search.size() << " resolutions baked";
    // The set the error target was measured on: S_D when dilated, else the one written.
    const std::optional<VolumeError>& measured = internal ? internal : volume;
    if (mode == "target_error" && measured && measured->kind == NerrKind::kApproximate)
      std::cout << " (by an approximate nerr: the mesh intersects itself)";
    std::cout << "\n"
              << "  spheres       " << s.spheres << ", radius " << number_text(s.min_radius, 4)
              << " .. " << number_text(s.max_radius, 4) << "\n";
    if (record.dilation_stats) {
      const DilateStats& d = *record.dilation_stats;
      std::cout << "  dilated       " << output.size() << " spheres: " << d.grown
                << " grown (by up to " << number_text(d.max_growth, 4) << "), " << d.added_vertex
                << " added at vertices";
      if (dilation->options.cover_tolerance >= 0.0)
        std::cout << ", " << d.added_cover << " added in " << d.cover_rounds << " cover round(s); "
                  << "uncovered " << number_text(d.uncovered_max, 4)
                  << (d.cover_reached ? " (within --cover)" : " (caps reached before --cover)");
      std::cout << ", " << number_text(d.seconds, 3) << " s\n";
      if (volume)
        std::cout << "  protrusion    " << number_text(volume->max_protrusion, 4)
                  << " (the most a sphere sticks out of the solid)\n";
    }
    if (internal)
      std::cout << "  internal S_D  nerr " << number_text(internal->nerr, 4) << " ("
                << nerr_note(internal->kind) << ")"
                << (mode == "target_error"
                        ? ": --target-error " + number_text(target) +
                              " was met by this internal set; the written S+ is measured below"
                        : std::string())
                << "\n";
    if (volume) {
      std::cout << "  volume        " << (internal ? "S+: " : "") << "union "
                << number_text(volume->union_measures.volume, 6) << " of mesh "
                << number_text(*fit.volume(), 6) << ", nerr " << number_text(volume->nerr, 4)
                << " (" << nerr_note(volume->kind) << ")\n";
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
      "Stop the medial search within this distance: at least 1e-9 of the box's largest side L "
      "and below the cell size (default: 1e-3 L, at most half a cell)");
  auto* max = sub->add_option("--max-spheres", a->max_spheres,
                              "Choose the largest resolution giving 1 to N spheres");
  auto* err =
      sub->add_option("--target-error", a->target_error,
                      "Choose the smallest resolution whose normalized volume error is at most E");
  max->excludes(err);
  sub->add_option("--cover-budget", a->cover_budget,
                  "Bake a covering set instead: at most K spheres whose union contains the "
                  "whole surface, certified")
      ->excludes(max)
      ->excludes(err);
  sub->add_flag("--dilate", a->dilate,
                "Dilate the spheres until they hug the surface (paper section 5.1); writes S+");
  sub->add_option("--vertex-tolerance", a->vertex_tolerance,
                  "Dilation: cover every mesh vertex within this length, in the mesh's units or "
                  "a multiple of the box's largest side L written 0.005L (default: 0.005L)");
  sub->add_option("--max-protrusion", a->max_protrusion,
                  "Dilation: let no grown or added sphere stick out of the solid by more than "
                  "this length, e.g. 0.002L (default: no cap, as in the paper)");
  sub->add_option("--cover", a->cover,
                  "Dilate, then add spheres until no surface sample is farther than this "
                  "length outside, e.g. 0.003L (implies --dilate)");
  sub->add_option("--seed", a->seed, "Dilation: seed of its random points")->capture_default_str();
  sub->add_option("--threads", a->threads, "Threads, at most 1024 (default 0: all cores)")
      ->capture_default_str();
  sub->add_flag("-q,--quiet", a->quiet, "No progress bar, warnings or summary");
  return [a] { return run_bake(*a); };
}

}  // namespace medspheres::cli
