#pragma once
/// \file
/// What `medspheres eval MESH SPHERES` measures, as one call for every tool: the fit
/// metrics (fit_metrics.h) and the certificate of surface coverage (cover_certificate.h)
/// of a sphere set against a mesh, in the mesh's frame and units.
///
/// Errors: InputError named by the library's fields ("samples", "surface_samples",
/// "threads") for options out of range; a problem of the set names it by the caller's
/// name for it; as FitEvaluator::evaluate and certify_cover otherwise.

#include <cstdint>
#include <string>
#include <vector>

#include "medspheres/bake/fit_metrics.h"
#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// The evaluation options as a user gives them, checked: counts >= 1, threads in [0,
/// kMaxThreads]. \throws InputError (kOutOfRange) naming the field.
FitOptions fit_options(long long samples, long long surface_samples, std::uint64_t seed,
                       int threads);

struct SetEvaluation {
  FitReport fit;
  CoverCertificate certificate;
};

/// Evaluates \p set against \p mesh (as load_mesh gives it) with \p options; the
/// certificate uses options.threads. \p set_name names the set in errors (its file).
SetEvaluation evaluate_sphere_set(const TriangleMesh& mesh, const SphereSet& set,
                                  const FitOptions& options, const std::string& set_name);

/// The evaluation as the JSON object `medspheres eval --json` prints (keys in README,
/// "eval"): \p mesh and \p spheres_file name the inputs, \p longest is L, \p warnings are
/// listed as given. Undefined numbers (NaN) are null. Indented by two spaces.
std::string evaluation_json(const SetEvaluation& evaluation, const std::string& mesh,
                            const std::string& spheres_file, double longest,
                            const std::vector<std::string>& warnings);

}  // namespace medspheres
