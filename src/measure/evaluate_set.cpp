#include "medspheres/measure/evaluate_set.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "medspheres/error.h"
#include "medspheres/mesh/cover_certificate_json.h"
#include "medspheres/thread_option.h"

namespace medspheres {

namespace {

InputError out_of_range(const char* field, long long value, std::string problem) {
  return InputError::option(ErrorKind::kOutOfRange, field, std::to_string(value),
                            std::move(problem));
}

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

}  // namespace

FitOptions fit_options(long long samples, long long surface_samples, std::uint64_t seed,
                       int threads) {
  // The largest counts: the Monte-Carlo points' winding cells (one byte per 16 points) and
  // the surface points (24 bytes each) are held in memory.
  constexpr long long kMaxSamples = 10'000'000'000LL, kMaxSurfaceSamples = 100'000'000LL;
  if (samples < 1 || samples > kMaxSamples)
    throw out_of_range(
        "samples", samples,
        "must be 1 .. " + std::to_string(kMaxSamples) + ", got " + std::to_string(samples));
  if (surface_samples < 1 || surface_samples > kMaxSurfaceSamples)
    throw out_of_range("surface_samples", surface_samples,
                       "must be 1 .. " + std::to_string(kMaxSurfaceSamples) + ", got " +
                           std::to_string(surface_samples));
  check_threads_option(threads, "threads");
  FitOptions options;
  options.volume_samples = static_cast<std::size_t>(samples);
  options.surface_samples = static_cast<std::size_t>(surface_samples);
  options.seed = seed;
  options.threads = threads;
  return options;
}

SetEvaluation evaluate_sphere_set(const TriangleMesh& mesh, const SphereSet& set,
                                  const FitOptions& options, const std::string& set_name) {
  SetEvaluation out;
  try {
    out.fit = FitEvaluator(mesh, options.threads).evaluate(set.spheres, options);
    CoverCertificateOptions co;
    co.threads = options.threads;
    out.certificate = certify_cover(mesh, set.spheres, co);
  } catch (const InputError& e) {
    // The library speaks of "the sphere set"; the caller knows it by its own name.
    if (e.file() == "sphere set") throw e.with_file(set_name);
    throw;
  }
  return out;
}

MeshEvaluation evaluate_mesh_set(const LoadedMesh& loaded, const std::string& mesh_name,
                                 const SphereSet& set, const std::string& spheres_file,
                                 const FitOptions& options, const SolidRequest& solid) {
  MeshEvaluation out;
  out.mesh = mesh_name;
  out.spheres_file = spheres_file;
  out.longest = loaded.report.largest_side();
  out.solid = eval_solid(solid, out.longest, set.metadata_json);
  for (const std::string& w : loaded.warnings) out.warnings.push_back(mesh_name + ": " + w);
  if (out.solid.kind == SolidKind::kRobust)
    out.warnings.push_back(mesh_name + ": measured against its robust solid at resolution " +
                           std::to_string(out.solid.robust.resolution) + " (solid robust)");
  const TriangleMesh measured = solid_mesh(loaded.mesh, out.solid, mesh_name);
  out.evaluation = evaluate_sphere_set(measured, set, options, spheres_file);
  for (const std::string& w : out.evaluation.fit.warnings) out.warnings.push_back(w);
  return out;
}

std::string evaluation_json(const MeshEvaluation& evaluation) {
  const FitReport& r = evaluation.evaluation.fit;
  const CoverCertificate& cert = evaluation.evaluation.certificate;
  const VolumeError& v = r.volume;
  const MonteCarloError& mc = r.monte_carlo;
  nlohmann::ordered_json j;
  j["mesh"] = evaluation.mesh;
  j["spheres_file"] = evaluation.spheres_file;
  j["solid"] = to_string(evaluation.solid.kind);
  if (evaluation.solid.kind == SolidKind::kRobust) {
    j["robust_resolution"] = evaluation.solid.robust.resolution;
    j["robust_thickness"] = evaluation.solid.robust.thickness;
  }
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
  j["surface_certificate"] = nlohmann::ordered_json::parse(cover_certificate_json(cert));
  j["surface_samples"] = r.coverage.area_samples;
  j["vertices"] = r.coverage.vertices;
  j["bbox_largest_side"] = evaluation.longest;
  j["seconds"] = r.seconds.total;
  j["seconds_by_part"] = {{"union_volume", r.seconds.union_volume},
                          {"protrusion", r.seconds.protrusion},
                          {"grid", r.seconds.grid},
                          {"monte_carlo", r.seconds.monte_carlo},
                          {"coverage", r.seconds.coverage},
                          {"certificate", cert.seconds}};
  j["warnings"] = evaluation.warnings;
  return j.dump(2);
}

}  // namespace medspheres
