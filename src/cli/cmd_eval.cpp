// medspheres eval MESH SPHERES: how well a sphere set fits a mesh (fit_metrics.h).
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bake_flags.h"
#include "cli_common.h"
#include "cmd_eval_robot.h"
#include "medspheres/bake/fit_metrics.h"
#include "medspheres/bake/solid_choice.h"
#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/threads.h"

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

// A number, or null where it is not defined (NaN).
nlohmann::ordered_json number(double v) {
  return std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(v);
}

nlohmann::ordered_json estimate_json(const Estimate95& e) {
  return {{"estimate", number(e.estimate)},
          {"lo", number(e.lo)},
          {"hi", number(e.hi)},
          {"sigma", number(e.sigma)}};
}

std::string percent_of(double v, double length) {
  return number_text(100.0 * v / length, 3) + "% of L";
}

// The certificate of surface coverage (cover_certificate.h), as JSON.
nlohmann::ordered_json certificate_json(const CoverCertificate& c) {
  nlohmann::ordered_json j = {{"certified", c.certified},
                              {"triangles", c.triangles},
                              {"uncertified_triangles", c.uncertified_triangles},
                              {"proven_uncovered_triangles", c.proven_uncovered_triangles},
                              {"pieces_tested", c.pieces_tested},
                              {"max_depth", c.max_depth_reached}};
  if (!c.certified) {
    j["worst_uncovered_distance"] = c.worst_distance;
    j["worst_uncovered_point"] = {c.worst_point.x(), c.worst_point.y(), c.worst_point.z()};
    j["worst_uncovered_bound"] = c.worst_bound;
  }
  return j;
}

void print_json(const EvalArgs& args, const FitReport& r, const CoverCertificate& cert,
                double longest, const std::vector<std::string>& warnings) {
  const VolumeError& v = r.volume;
  const MonteCarloError& mc = r.monte_carlo;
  nlohmann::ordered_json j;
  j["mesh"] = args.mesh;
  j["spheres_file"] = args.spheres;
  j["spheres"] = r.balls;
  j["mesh_closed"] = r.mesh_closed;
  j["mesh_volume"] = v.mesh_volume ? nlohmann::ordered_json(*v.mesh_volume) : nullptr;
  j["union_volume"] = v.union_measures.volume;
  j["union_area"] = v.union_measures.area;
  j["hidden_spheres"] = v.union_measures.hidden.size();
  j["duplicate_spheres"] = v.union_measures.duplicates.size();
  j["nerr"] = number(v.nerr);
  j["nerr_kind"] = to_string(v.kind);
  j["nerr_slack"] = v.nerr_slack;
  j["self_intersecting_pairs"] = v.self_intersecting_pairs;
  j["max_protrusion"] = v.max_protrusion;
  j["max_protrusion_sphere"] = v.max_protrusion_ball;
  j["protruding_spheres"] = v.protruding;
  j["protrusion_tolerance"] = v.protrusion_tolerance;
  nlohmann::ordered_json e = estimate_json(mc.error);
  e["interval"] = mc.normalized_by_volume ? "wilson" : "delta_method";
  e["normalized_by"] = mc.normalized_by_volume ? "mesh_volume" : "winding_solid_volume_estimate";
  e["samples"] = mc.samples;
  e["seed"] = mc.seed;
  e["outside_mesh_volume"] = mc.outside_volume;
  e["uncovered_mesh_volume"] = mc.uncovered_volume;
  e["winding_solid_volume"] = estimate_json(mc.solid_volume);
  e["multiply_covered_volume"] = mc.multiple_volume;
  e["multiply_covered_volume_sigma"] = mc.multiple_volume_sigma;
  j["mc_error"] = e;
  j["uncovered_max"] = r.coverage.max;
  j["uncovered_mean"] = r.coverage.mean;
  j["uncovered_p95"] = r.coverage.p95;
  j["uncovered_max_at"] = {r.coverage.max_at.x(), r.coverage.max_at.y(), r.coverage.max_at.z()};
  j["surface_certificate"] = certificate_json(cert);
  j["surface_samples"] = r.coverage.area_samples;
  j["vertices"] = r.coverage.vertices;
  j["bbox_largest_side"] = longest;
  j["seconds"] = r.seconds.total;
  j["seconds_by_part"] = {{"union_volume", r.seconds.union_volume},
                          {"protrusion", r.seconds.protrusion},
                          {"grid", r.seconds.grid},
                          {"monte_carlo", r.seconds.monte_carlo},
                          {"coverage", r.seconds.coverage},
                          {"certificate", cert.seconds}};
  j["warnings"] = warnings;
  std::cout << j.dump(2) << "\n";
}

void print_text(const EvalArgs& args, const LoadedMesh& loaded, const FitReport& r,
                const CoverCertificate& cert, double longest,
                const std::vector<std::string>& warnings) {
  const VolumeError& v = r.volume;
  const MonteCarloError& mc = r.monte_carlo;
  const CoverageStats& c = r.coverage;
  std::cout << "eval " << args.spheres << " against " << args.mesh << "\n";
  std::cout << "  mesh          " << loaded.report.triangles << " triangles, ";
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
            << v.protruding << " sphere(s) beyond the tolerance "
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
            << "; " << mc.samples << " points, seed " << mc.seed << ")\n"
            << "                volume of the spheres outside the mesh "
            << number_text(mc.outside_volume, 4) << ", of the mesh outside the spheres "
            << number_text(mc.uncovered_volume, 4) << "\n";
  std::cout << "  uncovered     surface outside the spheres by max " << number_text(c.max, 4)
            << " (" << percent_of(c.max, longest) << "), mean " << number_text(c.mean, 4)
            << ", p95 " << number_text(c.p95, 4) << " (" << percent_of(c.p95, longest) << ")\n"
            << "                over " << c.area_samples << " area-weighted points and "
            << c.vertices << " vertices (L = " << number_text(longest, 4) << ")\n";
  std::cout << "  certificate   surface "
            << (cert.certified ? "certified covered" : "NOT certified covered") << ": "
            << cert.pieces_tested << " pieces tested, depth " << cert.max_depth_reached << ", "
            << cert.uncertified_triangles << " of " << cert.triangles << " triangles uncertified";
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
  for (const std::string& w : warnings) std::cout << "  warning: " << w << "\n";
}

int run_eval(const EvalArgs& args) {
  // Options first: nonsense is reported before any work is done.
  auto out_of_range = [](const char* field, const std::string& value, std::string problem) {
    return InputError::option(ErrorKind::kOutOfRange, field, value, std::move(problem));
  };
  if (args.samples < 1)
    throw out_of_range("samples", std::to_string(args.samples),
                       "must be >= 1, got " + std::to_string(args.samples));
  if (args.surface_samples < 1)
    throw out_of_range("surface_samples", std::to_string(args.surface_samples),
                       "must be >= 1, got " + std::to_string(args.surface_samples));
  if (std::string problem = threads_problem(args.threads); !problem.empty())
    throw out_of_range("threads", std::to_string(args.threads), std::move(problem));
  FitOptions options;
  options.volume_samples = static_cast<std::size_t>(args.samples);
  options.surface_samples = static_cast<std::size_t>(args.surface_samples);
  options.seed = args.seed;
  options.threads = args.threads;
  if (is_robot_description(args.mesh))
    return run_eval_robot({args.mesh, args.spheres, args.packages, args.json, options});

  const LoadedMesh loaded = load_mesh(args.mesh);
  const SphereSet set = load_sphere_set(args.spheres);
  BakeRequest solid_request;
  set_solid(args.solid, solid_request);
  RobustSolidOptions robust = solid_request.robust;
  if (solid_request.robust_thickness)
    robust.thickness = solid_request.robust_thickness->in(loaded.report.largest_side());
  const bool robust_explicit = args.solid.robust_thickness ||
                               args.solid.robust_resolution != RobustSolidOptions{}.resolution;
  const SolidChoice choice =
      choose_solid(solid_request.solid, robust, robust_explicit, set.metadata_json);
  const TriangleMesh solid = solid_mesh(loaded.mesh, choice, args.mesh);
  FitReport report;
  CoverCertificate cert;
  try {
    report = FitEvaluator(solid, options.threads).evaluate(set.spheres, options);
    CoverCertificateOptions co;
    co.threads = args.threads;
    cert = certify_cover(solid, set.spheres, co);
  } catch (const InputError& e) {
    // The library speaks of "the sphere set"; the user knows it by its file name.
    if (e.file() == "sphere set") throw e.with_file(args.spheres);
    throw;
  }
  std::vector<std::string> warnings;
  for (const std::string& w : loaded.warnings) warnings.push_back(args.mesh + ": " + w);
  if (choice.kind == SolidKind::kRobust)
    warnings.push_back(args.mesh + ": measured against its robust solid at resolution " +
                       std::to_string(choice.robust.resolution) + " (solid robust)");
  for (const std::string& w : report.warnings) warnings.push_back(w);
  const double longest = loaded.report.largest_side();
  if (args.json)
    print_json(args, report, cert, longest, warnings);
  else
    print_text(args, loaded, report, cert, longest, warnings);
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
      ->check([](const std::string& s) {
        return s.rfind('-', 0) == 0 ? std::string("must be an integer >= 0, got " + s)
                                    : std::string();
      })
      ->capture_default_str();
  sub->add_option("--threads", a->threads, "Threads, at most 1024 (default 0: all cores)")
      ->capture_default_str();
  sub->add_option("--package", a->packages, "Robots: PKG=DIR for package:// (repeatable)");
  add_solid_flags(sub, a->solid);
  return [a] { return run_eval(*a); };
}

}  // namespace medspheres::cli
