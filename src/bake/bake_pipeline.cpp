#include "medspheres/bake/bake_pipeline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "medspheres/bake/cover_record.h"
#include "medspheres/bake/dilate.h"
#include "medspheres/bake/inner_budget.h"
#include "medspheres/cover/cover_input.h"
#include "medspheres/error.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/number_text.h"
#include "medspheres/sha256.h"

namespace medspheres {

namespace {

InputError request_error(ErrorKind kind, std::string field, std::string value, std::string problem,
                         std::vector<std::string> related = {}) {
  return InputError::option(kind, std::move(field), std::move(value), std::move(problem), {},
                            std::move(related));
}

bool dilating(const BakeRequest& r) {
  return r.dilate || r.cover.has_value();
}

// An explicit medial_tolerance against the mesh's box and the finest resolution baked.
void check_medial_tolerance(const BakeRequest& r, double longest, const std::string& name) {
  const bool search = r.max_spheres || r.target_error;
  const int finest = search ? kMaxSearchResolution : r.medial.resolution;
  std::optional<InputError> problem =
      medial_tolerance_problem(r.medial.medial_tolerance, longest, finest);
  if (!problem) return;
  if (search)
    problem = InputError::option(problem->kind(), problem->field(), problem->value(),
                                 "a search may bake up to resolution " + std::to_string(finest) +
                                     ", so it " + problem->problem());
  throw problem->with_file(name);
}

DilateOptions dilate_options(const BakeRequest& r, double longest) {
  DilateOptions o;
  o.seed = r.seed;
  o.threads = r.medial.threads;
  if (r.vertex_tolerance) o.vertex_tolerance = r.vertex_tolerance->in(longest);
  if (r.max_protrusion) o.max_protrusion = r.max_protrusion->in(longest);
  if (r.cover) o.cover_tolerance = r.cover->in(longest);
  return o;
}

// The medial bake of the request's mode, with the mode recorded; errors of the library's
// "mesh" name the mesh as the caller does.
BakeResult bake_medial(const FitEvaluator& fit, const BakeRequest& r, const std::string& name,
                       BakeRecord& record) {
  const int threads = r.medial.threads;
  auto nerr_of = [&](const SphereSet& s) { return fit.volume_error(s.spheres, threads).nerr; };
  try {
    if (r.max_spheres) {
      record.mode = "max_spheres";
      record.mode_target = static_cast<double>(*r.max_spheres);
      return bake_inner_budget(fit.query(), *r.max_spheres, r.medial);
    }
    if (r.target_error) {
      record.mode = "target_error";
      record.mode_target = *r.target_error;
      return bake_target_error(fit.query(), *r.target_error, nerr_of, r.medial);
    }
    return bake(fit.query(), r.medial);
  } catch (const InputError& e) {
    if (e.file().empty() || e.file() == "mesh") throw e.with_file(name);
    throw;
  }
}

std::pair<double, double> radius_range(const SphereSet& set) {
  double lo = set.spheres.front().radius, hi = lo;
  for (const Sphere& s : set.spheres) {
    lo = std::min(lo, s.radius);
    hi = std::max(hi, s.radius);
  }
  return {lo, hi};
}

// S_D grown to S+, recorded.
void dilate_output(const FitEvaluator& fit, const BakeRequest& r, double longest,
                   BakeOutcome& out) {
  const DilateOptions options = dilate_options(r, longest);
  if (r.measure && fit.volume())
    out.internal = fit.volume_error(out.medial.spheres.spheres, r.medial.threads);
  DilateResult dilated = dilate(fit.query(), out.medial.spheres, options);
  out.spheres = std::move(dilated.spheres);
  out.record.dilation_options = options;
  out.record.dilation_stats = dilated.stats;
  const auto [lo, hi] = radius_range(out.spheres);
  out.record.extra_stats["min_radius"] = lo;
  out.record.extra_stats["max_radius"] = hi;
}

// The volume, nerr and protrusion of the output, in the outcome and the record.
void measure_output(const FitEvaluator& fit, const BakeRequest& r, BakeOutcome& out) {
  BakeRecord& record = out.record;
  if (fit.volume()) {
    out.volume = fit.volume_error(out.spheres.spheres, r.medial.threads);
    record.extra_stats["nerr"] = out.volume->nerr;
    record.extra_stats["mesh_volume"] = *fit.volume();
    record.extra_stats["union_volume"] = out.volume->union_measures.volume;
    record.extra_stats["max_protrusion"] = out.volume->max_protrusion;
    record.extra_strings["nerr_kind"] = to_string(out.volume->kind);
  } else {
    // Written as null: the volume of an open mesh, and so nerr, is not defined.
    record.extra_stats["nerr"] = std::numeric_limits<double>::quiet_NaN();
    record.extra_strings["nerr_kind"] = to_string(NerrKind::kUndefined);
  }
  if (out.internal) {
    // The internal set S_D, before dilation: what target_error was met by.
    record.extra_stats["nerr_internal"] = out.internal->nerr;
    record.extra_strings["nerr_internal_kind"] = to_string(out.internal->kind);
  }
}

// A cover to a budget: the budget is max_spheres, or the count of cover_start; nothing of
// S_D's options applies.
void validate_cover(const BakeRequest& r) {
  if (!r.max_spheres && r.cover_start.empty())
    throw request_error(ErrorKind::kConflict, "method", "cover",
                        "a covering set needs a budget (max_spheres) or spheres to start from",
                        {"max_spheres", "cover_start"});
  if (r.max_spheres && !r.cover_start.empty())
    throw request_error(ErrorKind::kConflict, "max_spheres", std::to_string(*r.max_spheres),
                        "excludes cover_start: the start's spheres are the budget",
                        {"cover_start"});
  const std::string weights = protrusion_weights_problem(r.cover_weights);
  if (!weights.empty()) throw request_error(ErrorKind::kOutOfRange, "cover_weights", "", weights);
  const std::string problem = r.cover_start.empty() ? "" : cover_start_problem(r.cover_start);
  if (!problem.empty())
    throw request_error(ErrorKind::kOutOfRange, "cover_start",
                        count_text(r.cover_start.size(), "sphere"), problem);
  if (r.target_error)
    throw request_error(ErrorKind::kConflict, "target_error", number_text(*r.target_error),
                        "applies to inner sets, not to a covering set", {"method"});
  if (dilating(r) || r.vertex_tolerance || r.max_protrusion)
    throw request_error(ErrorKind::kConflict, "dilate", "",
                        "a covering set covers by itself: no dilation applies", {"method"});
}

// The certified cover of the request's budget, recorded.
void cover_output(const FitEvaluator& fit, const BakeRequest& r, BakeOutcome& out) {
  CoverOptions options;
  options.threads = r.medial.threads;
  options.weights = r.cover_weights;
  static_cast<CoverSearch&>(options) = r.cover_search;
  out.cover = r.cover_start.empty() ? bake_cover(fit.query(), *r.max_spheres, options)
                                    : tighten_cover(fit.query(), r.cover_start, options);
  out.self_intersecting_pairs = fit.self_intersections().count();
  out.record = cover_bake_record(out.record.source, *out.cover);
  out.record.record_seconds = r.record_seconds;
  out.record.extra_strings["solid"] = to_string(SolidKind::kWinding);
  out.spheres = out.cover->spheres;
  out.spheres.metadata_json = cover_metadata_json(out.record);
}

}  // namespace

void validate(const CoverSearch& search) {
  if (const std::optional<CoverSearchProblem> p = cover_search_problem(search))
    throw request_error(ErrorKind::kOutOfRange, p->field, p->value, p->problem);
}

void validate(const BakeRequest& r) {
  if (std::optional<InputError> problem = bake_options_problem(r.medial)) throw *problem;
  validate(r.robust);
  validate(r.cover_search);
  if (r.max_spheres && *r.max_spheres < 1)
    throw request_error(ErrorKind::kOutOfRange, "max_spheres", std::to_string(*r.max_spheres),
                        "must be >= 1, got " + std::to_string(*r.max_spheres));
  if (r.target_error && !(*r.target_error > 0.0 && *r.target_error < 1.0))
    throw request_error(ErrorKind::kOutOfRange, "target_error", number_text(*r.target_error),
                        "must be in (0, 1), got " + number_text(*r.target_error));
  if (r.method == BakeMethod::kCover) validate_cover(r);
  if (r.method != BakeMethod::kCover && !r.cover_start.empty())
    throw request_error(ErrorKind::kConflict, "cover_start",
                        count_text(r.cover_start.size(), "sphere"),
                        "applies to a covering set only", {"method"});
  if (r.max_spheres && r.target_error)
    throw request_error(ErrorKind::kConflict, "max_spheres", std::to_string(*r.max_spheres),
                        "excludes target_error: a search has one goal", {"target_error"});
  if (!dilating(r)) {
    for (const auto& [length, field] : {std::make_pair(&r.vertex_tolerance, "vertex_tolerance"),
                                        std::make_pair(&r.max_protrusion, "max_protrusion")})
      if (*length)
        throw request_error(ErrorKind::kConflict, field, length_text(**length),
                            "applies only with dilate or cover", {"dilate", "cover"});
  }
  check_length(r.vertex_tolerance, "vertex_tolerance", false);
  check_length(r.max_protrusion, "max_protrusion", true);
  check_length(r.cover, "cover", false);
  check_length(r.robust_thickness, "robust_thickness", true);
}

namespace {

// The bake of the winding-number solid of the mesh \p fit was built from (report: of that
// mesh); \p source is recorded.
BakeOutcome bake_solid(const FitEvaluator& fit, const MeshReport& report,
                       const MeshProvenance& source, const BakeRequest& request,
                       const std::string& name) {
  const double longest = report.largest_side();
  check_medial_tolerance(request, longest, name);
  if (request.target_error && !fit.volume())
    throw InputError::option(ErrorKind::kUnsupported, "target_error",
                             number_text(*request.target_error),
                             "it is not a closed, outward-wound mesh, so its volume and the "
                             "error are not defined",
                             name);
  BakeOutcome out;
  out.record.source = source;
  out.record.record_seconds = request.record_seconds;
  out.record.extra_strings["solid"] = to_string(SolidKind::kWinding);
  if (request.method == BakeMethod::kCover) {
    cover_output(fit, request, out);
    return out;
  }
  out.record.options = request.medial;
  out.medial = bake_medial(fit, request, name, out.record);
  if (out.medial.spheres.empty())
    throw InputError::option(ErrorKind::kUnreachable, "", "",
                             "no medial sphere was found at resolution " +
                                 std::to_string(out.medial.stats.resolution) +
                                 " with object angle " + number_text(request.medial.object_angle) +
                                 "; try a higher resolution or a smaller object_angle",
                             name, {"resolution", "object_angle"});
  out.record.stats = out.medial.stats;
  out.self_intersecting_pairs = fit.self_intersections().count();
  if (dilating(request))
    dilate_output(fit, request, longest, out);
  else
    out.spheres = out.medial.spheres;
  if (request.measure) measure_output(fit, request, out);
  out.spheres.metadata_json = bake_metadata_json(out.record);
  return out;
}

// A cover baked on the robust solid of \p input: the input's own triangles certified too
// (cover_input.h), the record made again from the cover and the check recorded.
void certify_input(const TriangleMesh& input, const FitEvaluator& fit, const BakeRequest& request,
                   BakeOutcome& out) {
  CoverOptions options;
  options.threads = request.medial.threads;
  const InputCoverCheck check = certify_input_cover(input, fit, *out.cover, options);
  const std::map<std::string, std::string> strings = out.record.extra_strings;
  out.record = cover_bake_record(out.record.source, *out.cover);
  out.record.record_seconds = request.record_seconds;
  out.record.extra_strings = strings;
  record_input_cover(check, out.record);
  out.spheres = out.cover->spheres;
  if (!check.certificate.certified)
    out.warnings.push_back("the covering set does not certainly contain " +
                           std::to_string(check.certificate.uncertified_triangles) +
                           " of the input's own triangles (input_certified false)");
}

// What an escalated thickness says: from which to which, and why.
std::string escalation_warning(const RobustSolid& solid, const RobustSolidOptions& options,
                               const MeshProvenance& source) {
  const double longest = source.report.largest_side();
  std::string steps;
  for (double step : kRobustThicknessSteps)
    steps += (steps.empty() ? "" : ", ") + number_text(step);
  return "the robust solid's walls enclosed nothing with robust_thickness " +
         number_text(options.thickness) + ", so they were thickened to " +
         number_text(solid.thickness / longest, 3) + "L = " + number_text(solid.thickness, 4) +
         " (the first of " + steps +
         "L that encloses a volume; recorded as robust_thickness, give one to choose)";
}

// The bake of the robust solid of \p mesh, recorded as such; with a \p fallback reason,
// a warning that says what was done.
BakeOutcome bake_robust(const TriangleMesh& mesh, const MeshProvenance& source,
                        const BakeRequest& request, const std::string& name,
                        const std::string& fallback = "") {
  RobustSolidOptions options = request.robust;
  if (request.robust_thickness) {
    options.thickness = request.robust_thickness->in(source.report.largest_side());
    options.escalate = false;
  }
  const RobustSolid solid = make_robust_solid(mesh, options, name);
  const FitEvaluator fit(solid.mesh, request.medial.threads);
  BakeOutcome out = bake_solid(fit, analyze_mesh(solid.mesh), source, request, name);
  if (out.cover) certify_input(mesh, fit, request, out);
  out.solid = SolidKind::kRobust;
  out.record.extra_strings["solid"] = to_string(SolidKind::kRobust);
  out.record.extra_stats["robust_cell"] = solid.cell;
  out.record.extra_stats["robust_wall_radius"] = solid.wall_radius;
  out.record.extra_stats["robust_resolution"] = solid.resolution;
  out.record.extra_stats["robust_triangles"] = static_cast<double>(solid.mesh.num_triangles());
  out.record.extra_stats["robust_thickness"] = solid.thickness;
  out.robust_thickness = solid.thickness;
  out.robust_thickness_escalated = solid.thickness > options.thickness;
  if (out.robust_thickness_escalated) {
    out.record.extra_stats["robust_thickness_requested"] = options.thickness;
    out.warnings.insert(out.warnings.begin(), escalation_warning(solid, options, source));
  }
  out.spheres.metadata_json =
      out.cover ? cover_metadata_json(out.record) : bake_metadata_json(out.record);
  if (!fallback.empty())
    out.warnings.insert(out.warnings.begin(), "its winding-number solid is not well defined (" +
                                                  fallback + "); baked " + describe(solid) +
                                                  " (solid robust)");
  return out;
}

}  // namespace

BakeOutcome bake_mesh(const TriangleMesh& mesh, const MeshReport& report,
                      const BakeRequest& request, const std::string& name,
                      const std::string& sha256) {
  validate(request);
  if (request.solid == SolidKind::kRobust)
    return bake_robust(mesh, {name, sha256, report}, request, name);
  check_medial_tolerance(request, report.largest_side(), name);
  // Orients a copy (a no-op after the loader), builds the mesh query, computes the volume.
  return bake_mesh(FitEvaluator(mesh, request.medial.threads), report, request, name, sha256);
}

BakeOutcome bake_mesh(const FitEvaluator& fit, const MeshReport& report, const BakeRequest& request,
                      const std::string& name, const std::string& sha256) {
  validate(request);
  const MeshProvenance source{name, sha256, report};
  const TriangleMesh& mesh = fit.query().mesh();
  if (request.solid == SolidKind::kRobust) return bake_robust(mesh, source, request, name);
  if (request.solid == SolidKind::kWinding || report.is_closed_outward())
    return bake_solid(fit, report, source, request, name);
  try {
    return bake_solid(fit, report, source, request, name);
  } catch (const InputError& e) {
    if (e.kind() != ErrorKind::kNoInterior) throw;
    return bake_robust(mesh, source, request, name, e.problem());
  }
}

BakeOutcome bake_file(const std::string& path, const BakeRequest& request,
                      std::vector<std::string>* warnings) {
  validate(request);
  const LoadedMesh loaded = load_mesh(path);
  BakeOutcome out = bake_mesh(loaded.mesh, loaded.report, request, path, file_sha256(path));
  if (warnings) {
    *warnings = loaded.warnings;
    warnings->insert(warnings->end(), out.warnings.begin(), out.warnings.end());
  }
  return out;
}

}  // namespace medspheres
