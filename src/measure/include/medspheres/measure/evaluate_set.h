#pragma once
/// \file
/// What `medspheres eval MESH SPHERES` measures, as one call for every tool (the CLI, the
/// Python module): the fit metrics (fit_metrics.h) and the certificate of surface coverage
/// (cover_certificate.h) of a sphere set against the solid of a mesh that the caller's solid
/// request chooses (solid_choice.h), in the mesh's frame and units.
///
/// Errors: InputError named by the library's fields ("samples", "surface_samples",
/// "threads", "robust_resolution", "robust_thickness") for options out of range;
/// a problem of the set names it by the caller's name for it; as FitEvaluator::evaluate,
/// certify_cover and make_robust_solid otherwise.

#include <cstdint>
#include <string>
#include <vector>

#include "medspheres/measure/fit_metrics.h"
#include "medspheres/measure/solid_choice.h"
#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// The evaluation options as a user gives them, checked: samples in [1, 10^10] and
/// surface_samples in [1, 10^8] (their points are held in memory), threads in [0,
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

/// `medspheres eval MESH SPHERES`: one evaluation and what is said about it.
struct MeshEvaluation {
  std::string mesh;          ///< the mesh's name (its file)
  std::string spheres_file;  ///< the set's name (its file)
  double longest = 0.0;      ///< L: the largest side of the input mesh's box
  SolidChoice solid;         ///< the solid measured (kWinding or kRobust)
  SetEvaluation evaluation;  ///< against that solid
  /// One sentence each: the loader's (prefixed by the mesh's name), the robust solid's
  /// (when it is measured), the fit's.
  std::vector<std::string> warnings;
};

/// Evaluates \p set (named \p spheres_file) against the solid of \p loaded (named
/// \p mesh_name) that eval_solid(\p solid, L, set.metadata_json) chooses.
/// \throws InputError as check_solid_request, before the mesh is measured.
MeshEvaluation evaluate_mesh_set(const LoadedMesh& loaded, const std::string& mesh_name,
                                 const SphereSet& set, const std::string& spheres_file,
                                 const FitOptions& options, const SolidRequest& solid = {});

/// The evaluation as the JSON object `medspheres eval --json` prints (keys in
/// docs/measuring.md): "solid" names the solid measured ("robust_resolution" and "robust_thickness"
/// too for the robust one). Undefined numbers (NaN) are null. Indented by two spaces.
std::string evaluation_json(const MeshEvaluation& evaluation);

}  // namespace medspheres
