// medspheres eval MESH SPHERES: how well a sphere set fits a mesh (fit_metrics.h).
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "cli_common.h"
#include "cmd_eval_robot.h"
#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/measure/evaluate_set.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/measure/solid_choice.h"
#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/options/bake_flags.h"
#include "solid_flags.h"

namespace medspheres::cli {

namespace {

struct EvalArgs {
  std::string mesh;
  std::string spheres;
  bool json = false;
  long long samples = static_cast<long long>(FitOptions{}.volume_samples);
  long long surface_samples = static_cast<long long>(FitOptions{}.surface_samples);
  std::uint64_t seed = FitOptions{}.seed;
  int threads = 0;
  std::vector<std::string> packages;  // robots: PKG=DIR
  SolidFlags solid;
};

std::string percent_of(double v, double length) {
  return number_text(100.0 * v / length, 3) + "% of L";
}

void print_text(const EvalArgs& args, const LoadedMesh& loaded, const MeshEvaluation& e) {
  const FitReport& r = e.evaluation.fit;
  const CoverCertificate& cert = e.evaluation.certificate;
  const double longest = e.longest;
  const VolumeError& v = r.volume;
  const MonteCarloError& mc = r.monte_carlo;
  const CoverageStats& c = r.coverage;
  std::cout << "eval " << args.spheres << " against " << args.mesh << "\n";
  std::cout << "  mesh          " << count_text(loaded.report.triangles, "triangle") << ", ";
  if (v.mesh_volume)
    std::cout << "closed, volume " << number_text(*v.mesh_volume) << "\n";
  else
    std::cout << "open: its volume, and so nerr, is not defined\n";
  std::cout << "  spheres       " << r.balls << " (" << v.union_measures.hidden.size()
            << " hidden, " << v.union_measures.duplicates.size() << " duplicate), union volume "
            << number_text(v.union_measures.volume) << ", area "
            << number_text(v.union_measures.area) << "\n";
  std::cout << "  protrusion    max " << number_text(v.max_protrusion, 4) << " (sphere "
            << v.max_protrusion_ball << ", " << percent_of(v.max_protrusion, longest) << "); "
            << count_text(v.protruding, "sphere") << " beyond the tolerance "
            << number_text(v.protrusion_tolerance, 3) << "\n";
  std::cout << "  nerr          ";
  switch (v.kind) {
    case NerrKind::kExact:
      std::cout << number_text(v.nerr, 5) << " (exact: no sphere sticks out)\n";
      break;
    case NerrKind::kLowerBound:
      std::cout << ">= " << number_text(v.nerr, 5) << " (lower bound: spheres stick out)\n";
      break;
    case NerrKind::kApproximate:
      std::cout << "~ " << number_text(v.nerr, 5) << " (approximate: the mesh intersects itself)\n";
      break;
    case NerrKind::kUndefined:
      std::cout << "not defined\n";
      break;
  }
  std::cout << "  Monte Carlo   error " << number_text(mc.error.estimate, 5) << ", 95% interval ["
            << number_text(mc.error.lo, 5) << ", " << number_text(mc.error.hi, 5) << "] ("
            << (mc.normalized_by_volume
                    ? "Wilson, of vol(mesh)"
                    : "delta method, of the winding-number solid's estimated volume " +
                          number_text(mc.solid_volume.estimate, 5))
            << "; " << count_text(mc.samples, "point") << ", seed " << mc.seed << ")\n"
            << "                volume of the spheres outside the mesh "
            << number_text(mc.outside_volume, 4) << ", of the mesh outside the spheres "
            << number_text(mc.uncovered_volume, 4) << "\n";
  std::cout << "  uncovered     surface outside the spheres by max " << number_text(c.max, 4)
            << " (" << percent_of(c.max, longest) << "), mean " << number_text(c.mean, 4)
            << ", p95 " << number_text(c.p95, 4) << " (" << percent_of(c.p95, longest) << ")\n"
            << "                over " << count_text(c.area_samples, "area-weighted point")
            << " and " << count_text(c.vertices, "vertex", "vertices")
            << " (L = " << number_text(longest, 4) << ")\n";
  std::cout << "  certificate   surface "
            << (cert.certified ? "certified covered" : "NOT certified covered") << ": "
            << count_text(cert.pieces_tested, "piece") << " tested, depth "
            << cert.max_depth_reached << ", " << cert.uncertified_triangles << " of "
            << count_text(cert.triangles, "triangle") << " uncertified";
  if (!cert.certified)
    std::cout << "; worst point found " << number_text(cert.worst_distance, 4) << " outside ("
              << percent_of(cert.worst_distance, longest) << ") at ("
              << number_text(cert.worst_point.x()) << ", " << number_text(cert.worst_point.y())
              << ", " << number_text(cert.worst_point.z()) << ")";
  std::cout << "\n";
  const FitSeconds& s = r.seconds;
  std::cout << "  time          " << number_text(s.total, 3) << " s: union "
            << number_text(s.union_volume, 3) << ", protrusion " << number_text(s.protrusion, 3)
            << ", grid " << number_text(s.grid, 3) << ", Monte Carlo "
            << number_text(s.monte_carlo, 3) << ", coverage " << number_text(s.coverage, 3) << "\n";
  for (const std::string& w : e.warnings) std::cout << "  warning: " << w << "\n";
}

// A robot's links are measured against their winding-number solids: a solid flag would go
// unheard.
void check_no_solid_flags(const SolidFlags& flags) {
  const SolidFlags defaults;
  std::string field, value;
  if (flags.solid != defaults.solid) {
    field = "solid";
    value = flags.solid;
  } else if (flags.robust_resolution != defaults.robust_resolution) {
    field = "robust_resolution";
    value = std::to_string(flags.robust_resolution);
  } else if (flags.robust_thickness) {
    field = "robust_thickness";
    value = *flags.robust_thickness;
  } else {
    return;
  }
  throw InputError::option(ErrorKind::kConflict, field, value,
                           "applies to the eval of a mesh: a robot's links are measured "
                           "against their winding-number solids");
}

int run_eval(const EvalArgs& args) {
  // Options first: nonsense is reported before any work is done.
  const FitOptions options =
      fit_options(args.samples, args.surface_samples, args.seed, args.threads);
  if (is_robot_description(args.mesh)) {
    check_no_solid_flags(args.solid);
    return run_eval_robot({args.mesh, args.spheres, args.packages, args.json, options});
  }
  const SolidRequest solid = solid_request(args.solid);
  const LoadedMesh loaded = load_mesh(args.mesh);
  const SphereSet set = load_sphere_set(args.spheres);
  const MeshEvaluation e = evaluate_mesh_set(loaded, args.mesh, set, args.spheres, options, solid);
  if (args.json)
    std::cout << evaluation_json(e) << "\n";
  else
    print_text(args, loaded, e);
  return kExitOk;
}

}  // namespace

Runner register_eval(CLI::App& app) {
  auto a = std::make_shared<EvalArgs>();
  CLI::App* sub = app.add_subcommand(
      "eval",
      "Measure how well a sphere set fits a mesh: nerr, protrusion, coverage (sampled, and "
      "certified for the surface)");
  sub->add_option("mesh", a->mesh, "Mesh file (STL, OBJ, PLY, OFF, DAE, glTF, ...)")->required();
  sub->add_option("spheres", a->spheres, "Sphere-set file (medspheres JSON)")->required();
  sub->add_flag("--json", a->json, "Print one JSON object instead of text");
  sub->add_option("--samples", a->samples, "Monte-Carlo points for the volume error")
      ->capture_default_str();
  sub->add_option("--surface-samples", a->surface_samples,
                  "Area-weighted surface points for coverage (every vertex is added)")
      ->capture_default_str();
  sub->add_option("--seed", a->seed, "Seed of the Monte-Carlo and surface points")
      ->check(non_negative)
      ->capture_default_str();
  sub->add_option("--threads", a->threads, "Threads, at most 1024 (default 0: all cores)")
      ->capture_default_str();
  sub->add_option("--package", a->packages, "Robots: PKG=DIR for package:// (repeatable)");
  add_solid_flags(sub, a->solid);
  return [a] { return run_eval(*a); };
}

}  // namespace medspheres::cli
